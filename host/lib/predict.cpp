// host/lib/predict.cpp - the controller model (predict.h: what the physics' live commands
// still use; predict_program() runs the firmware itself, predict_run.cpp). Each rule below
// names the firmware code it follows. Also what both share to describe a record
// (predict_detail.h).
#include "predict.h"

#include <articula/line.h>
#include <articula/motion.h>
#include <articula/protocol.h>
#include <articula/servo.h>

#include "blocks.h"
#include "nano_config.h"
#include "predict_detail.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace articula::host {

namespace {
void add_note(PredictRecord& r, const std::string& note) { append_note(r.note, note); }
}  // namespace

// ---- what the model and the firmware's run share: describing a state (predict_detail.h) ----

// error:9's note: which motor the move would take beyond its range, and the range, in degrees.
std::string limit_note(const Robot& robot, const int32_t* target_millideg) {
  std::string out;
  for (int i = 0; i < robot.actuation.num_motors; ++i) {
    const MotorSpec& m = robot.actuation.motors[i];
    if (target_millideg[i] >= m.min && target_millideg[i] <= m.max) continue;
    append_note(out, "the " + robot.motor_names[size_t(i)] + " motor to " + number_text(target_millideg[i] / 1000.0) +
                         " deg is beyond its range, " + number_text(m.min / 1000.0) + " to " +
                         number_text(m.max / 1000.0) + " deg");
  }
  return out;
}

// The tool (mm) after every dominant step of `moves`, from `steps` (counted) + `offset`
// (Z's shift: the physical steps), each move's steps spread as LineStepper spreads them on
// the arm. Empty for a robot of more than 8 motors (LineStepper's byte of bits).
std::vector<Vec3<double>> tool_path(const Robot& robot, const int32_t* steps, const int32_t* offset,
                                    const std::vector<const std::vector<int32_t>*>& moves) {
  std::vector<Vec3<double>> out;
  const int n = robot.actuation.num_motors;
  if (n > 8) return out;
  int32_t pos[kMaxJoints];
  for (int i = 0; i < n; ++i) pos[i] = steps[i] + offset[i];
  for (const std::vector<int32_t>* delta : moves) {
    LineStepper<8> ls;
    ls.start(delta->data(), uint8_t(n));
    while (!ls.done()) {
      const uint8_t mask = ls.next();
      for (int i = 0; i < n; ++i)
        if (mask & (1u << i)) pos[i] += (ls.negative & (1u << i)) ? -1 : 1;
      double q[kMaxJoints];
      joints_from_steps(q, robot.actuation, pos);
      out.push_back(tool_position(robot.model, q));
    }
  }
  return out;
}

// The worst distance (mm) of the points from the segment a-b.
double distance_from_segment(const std::vector<Vec3<double>>& points, const Vec3<double>& a, const Vec3<double>& b) {
  const Vec3<double> ab = b - a;
  const double len2 = dot(ab, ab);
  double worst = 0;
  for (const Vec3<double>& p : points) {
    const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    worst = std::max(worst, norm(p - (a + t * ab)));
  }
  return worst;
}

void describe_state(const Robot& robot, PredictRecord& r, const int32_t* steps, const Millideg* commanded,
                    const int32_t* offset) {
  const auto& a = robot.actuation;
  const int n = a.num_motors, nj = robot.model.num_joints;
  int32_t physical[kMaxJoints];
  double u_ideal[kMaxJoints], q_ideal[kMaxJoints], q_real[kMaxJoints];
  r.steps.assign(steps, steps + n);
  r.commanded.assign(commanded, commanded + n);
  r.actuator_deg.clear();
  for (int i = 0; i < n; ++i) {
    physical[i] = steps[i] + offset[i];
    r.actuator_deg.push_back(steps_to_degrees<double>(a.motors[i], physical[i]));
    // The commanded angle where the arm really is: shifted by what Z declared.
    u_ideal[i] =
        deg_to_rad(commanded[i] / 1000.0 + a.motors[i].direction * offset[i] * degrees_per_step<double>(a.motors[i]));
  }
  joints_from_actuators(q_ideal, a, u_ideal);
  joints_from_steps(q_real, a, physical);
  r.joints.clear();
  r.joints_ideal.clear();
  for (int j = 0; j < nj; ++j) {
    r.joints.push_back(joint_from_model(robot, j, q_real[j]));
    r.joints_ideal.push_back(joint_from_model(robot, j, q_ideal[j]));
  }
  r.tool_ideal = tool_position(robot.model, q_ideal);
  r.tool_quantized = tool_position(robot.model, q_real);
  r.error_mm = norm(r.tool_quantized - r.tool_ideal);
  if (r.has_target) r.target_error_mm = norm(r.tool_quantized - r.target);
}

// Z and $n=v are answered only once the queue is empty and the arm at rest: the arm then
// idles until the host's next line arrives, a gap the prediction cannot know (serial round
// trip and host), so times after such a line are lower bounds by that gap.
const char* const kWaitsForRest =
    "the reply waits for the arm to be at rest: the actions after it start when the host sends them (times "
    "below assume at once)";

// ---- settings (firmware/src/settings.cpp) ----

std::array<uint32_t, 2> setting_range(int num_motors, int n) {
  if (n < 0 || n >= ControllerSettings::kCount) return {0, 0};
  const SettingRange r = articula::setting_range(uint8_t(n), uint8_t(std::min(num_motors, 31)));
  return {r.min, r.max};
}

Status check_setting(int num_motors, int32_t n, int32_t thousandths) {
  return articula::check_setting(n, thousandths, uint8_t(std::min(num_motors, 31)));
}

void apply_settings_text(ControllerSettings& s, const std::string& text, int num_motors) {
  std::stringstream ss(text);
  std::string item;
  bool any = false;
  while (std::getline(ss, item, ',')) {
    item = trim_blanks(item);
    if (item.empty()) throw std::invalid_argument("an empty entry (expected n=value, e.g. 0=800)");
    const std::string line = item[0] == '$' ? item : "$" + item;
    Command cmd;
    Status st = line.size() > kMaxLineLength ? kLineTooLong
                                             : parse_line(cmd, line.data(), uint8_t(line.size()), uint8_t(num_motors));
    if (st == kOk && cmd.type != kCmdSetSetting) st = kMissingArgument;
    if (st == kOk) st = check_setting(num_motors, cmd.arg[0], cmd.arg[1]);
    if (st == kSettingUnknown)
      throw std::invalid_argument("'" + item + "': no such setting (the settings are 0 to " +
                                  std::to_string(ControllerSettings::kCount - 1) + ")");
    if (st == kValueOutOfRange) {
      const auto range = setting_range(num_motors, cmd.arg[0]);
      throw std::invalid_argument("'" + item + "': $" + std::to_string(cmd.arg[0]) + " takes a whole number from " +
                                  std::to_string(range[0]) + " to " + std::to_string(range[1]));
    }
    if (st != kOk)
      throw std::invalid_argument("'" + item + "': expected n=value, e.g. 0=800 (" + status_text(st) + ")");
    s.value[size_t(cmd.arg[0])] = uint32_t(cmd.arg[1] / 1000);
    any = true;
  }
  if (!any) throw std::invalid_argument("no settings given (expected n=value,..., e.g. 0=800,1=3000)");
}

// ---- the model's planner (what the physics' live commands time their moves with) ----

namespace {

// The move a queued action makes: the record's, or one of its segments.
struct MoveOf {
  const std::vector<int32_t>& delta;
  uint32_t steps;
  uint16_t cruise4;
};

// controller.cpp push_planned(): a move's block, with its junction level to the move queued
// before it (`before`: none when the arm is at rest with nothing queued, or after another
// action) kept below the cruise caps of both; `cap` is set to this move's cap.
PlanBlock plan_block(const MoveOf& m, const MoveOf* before, uint16_t before_cap, const MotionSettings& motion,
                     uint32_t junction, uint16_t& cap) {
  PlanBlock b{uint16_t(std::min(m.steps, uint32_t(0xFFFF))), 0, 0, m.cruise4};
  ProfileConstants k;
  profile_constants(k, motion);
  cap = cruise_level_cap(motion, k.cruise, block_cruise(b, k.cruise));
  if (before)
    b.max_entry = std::min({cap, before_cap,
                            junction_level<kMaxJoints>(before->delta.data(), before->steps, m.delta.data(), m.steps,
                                                       uint8_t(m.delta.size()), junction)});
  return b;
}

}  // namespace

std::vector<PlanBlock> plan_segments(const std::vector<PredictRecord::Segment>& segments, const MotionSettings& motion,
                                     uint32_t junction) {
  std::vector<PlanBlock> plan;
  uint16_t last_cap = 0xFFFF;
  for (size_t i = 0; i < segments.size(); ++i) {
    const PredictRecord::Segment& s = segments[i];
    const MoveOf m{s.delta_steps, s.dominant_steps, s.cruise4};
    std::optional<MoveOf> before;
    if (i > 0) before.emplace(MoveOf{segments[i - 1].delta_steps, segments[i - 1].dominant_steps, 0});
    uint16_t cap = 0;
    plan.push_back(plan_block(m, before ? &*before : nullptr, last_cap, motion, junction, cap));
    last_cap = cap;
  }
  plan_entries([&](size_t k) -> const PlanBlock& { return plan[k]; }, [&](size_t k, uint16_t e) { plan[k].entry = e; },
               plan.size());
  return plan;
}

uint64_t segments_ticks(const std::vector<PredictRecord::Segment>& segments, const std::vector<PlanBlock>& plan,
                        const MotionSettings& motion, std::vector<uint64_t>* ends) {
  if (ends) ends->clear();
  ProfileConstants k;
  profile_constants(k, motion);
  StepProfile p;
  uint64_t t = 0;
  for (size_t i = 0; i < segments.size(); ++i) {
    const uint32_t exit = i + 1 < plan.size() ? plan[i + 1].entry : 0;
    const uint32_t cruise = block_cruise(plan[i], k.cruise);
    if (p.level() > 0)
      p.follow(segments[i].dominant_steps, exit, cruise);
    else
      p.start(segments[i].dominant_steps, k, exit, cruise);
    while (!p.done()) t += p.next_interval();
    if (ends) ends->push_back(t);
  }
  return t;
}


// ---- RoboSim mappings ----

int32_t robosim_hand_to_aperture(double h) {
  const double thousandths = (100.0 - 200.0 * h) * 1000.0;
  return int32_t(std::clamp(std::llround(thousandths), 0LL, 100000LL));
}

uint32_t robosim_speed_to_rate(double s, uint32_t base) {
  const long long r = std::llround(double(base) * s / kRoboSimFastest);
  return uint32_t(std::clamp(r, 1LL, 4000LL));
}

// ---- the controller ----

ControllerModel::ControllerModel(const Robot& robot, const ControllerSettings& settings)
    : robot_(robot), settings_(settings) {
  if (!robot.has_motors)
    throw PredictError(robot.name + " has no motors (" + robot.source +
                       "): a prediction needs motor steps; only the kinematic model can run its programs");
  n_ = robot.actuation.num_motors;
  reset(planned_, robot_.actuation);
  // firmware::setup(): no endstops means the arm is taken to be at step 0, Idle; with
  // endstops it is in Alarm until H or Z.
  homed_ = settings_.value[ControllerSettings::kEndstops] == 0;
  base_rate_ = settings_.value[ControllerSettings::kMaxRate];

  // robot::setup() (firmware/src/robot.cpp): the arm as the Nano configured for this robot
  // holds it (nano_config.h: P's arm, the home pose, the servo), read by the core's
  // config_read as the firmware reads it.
  ConfiguredArm<kFirmwareMotors> c;
  try {
    c = firmware_arm(robot_);
  } catch (const NanoConfigError& e) {
    throw PredictError(e.what());
  }
  has_ik_ = c.has_point;
  arm_ = c.arm;
  home_.assign(c.home, c.home + n_);
  home_steps_.assign(size_t(n_), 0);
  servo_open_ = c.servo_open_deg;
  servo_closed_ = c.servo_closed_deg;
  for (int i = 0; i < n_; ++i)
    home_steps_[size_t(i)] = quantize_within_limits(robot_.actuation.motors[i], home_[size_t(i)]);
}

PredictRecord ControllerModel::begin(int line, const std::string& text) const {
  PredictRecord r;
  r.line = line;
  r.text = text;
  r.start_tick = r.end_tick = clock_;
  return r;
}

// The state after the statement: steps, the angles and joint values they give, the ideal
// and the quantized tool position.
void ControllerModel::finish(PredictRecord& r) {
  describe(r, planned_);
  r.gripper_percent = gripper_percent_;
  if (!r.queued) r.start_tick = r.end_tick = clock_;
}

void ControllerModel::describe(PredictRecord& r, const MotorState<kMaxJoints>& state) const {
  describe_state(robot_, r, state.steps, state.commanded, offset_);
}

// queue_command()'s tail: an action that moves goes into the queue and runs after the ones
// before it; a move within the same steps only changes the commanded angles.
Status ControllerModel::queue_move(PredictRecord& r, const MotorState<kMaxJoints>& next, bool home,
                                   uint64_t extra_ticks) {
  uint32_t dominant = 0;
  bool moves = home;
  const MotorState<kMaxJoints> before = planned_;
  for (int i = 0; i < n_; ++i) {
    const int64_t d = int64_t(next.steps[i]) - planned_.steps[i];
    dominant = std::max(dominant, uint32_t(d < 0 ? -d : d));
    moves = moves || d != 0;
  }
  planned_ = next;
  if (!moves) {
    add_note(r, "within the same steps: only the commanded angles change, nothing is queued");
    return kOk;
  }
  r.queued = true;
  r.action = home ? PredictRecord::Action::kHome : PredictRecord::Action::kMove;
  r.delta_steps.clear();
  for (int i = 0; i < n_; ++i) r.delta_steps.push_back(next.steps[i] - before.steps[i]);
  r.seek_ticks = extra_ticks;
  r.motion = settings_.motion();
  r.junction = settings_.value[ControllerSettings::kJunction];
  r.dominant_steps = dominant;
  r.ticks = extra_ticks + profile_duration_ticks(dominant, settings_.motion());
  r.start_tick = clock_;
  clock_ += r.ticks;
  r.end_tick = clock_;
  return kOk;
}

// G and S (queue_command): a servo pulse, then the settle pause; always queued.
// A pause in the queue (stepper.cpp: the gripper's settle time, or D).
void ControllerModel::queue_pause(PredictRecord& r, uint64_t ms) {
  r.queued = true;
  r.action = PredictRecord::Action::kPause;
  r.ticks = ms * (kControllerTickHz / 1000);
  r.start_tick = clock_;
  clock_ += r.ticks;
  r.end_tick = clock_;
}

void ControllerModel::queue_gripper(PredictRecord& r, int32_t aperture) {
  queue_pause(r, settings_.value[ControllerSettings::kSettleMs]);
  gripper_percent_ = (aperture + 500) / 1000;
  add_note(r, "servo pulse " + std::to_string(articula::servo_pulse_us<float>(servo_closed_, servo_open_, aperture)) + " us");
}

// P (controller.cpp, solve_point): the closed form in float, the in-limits solution nearest
// the planned pose, each angle rounded to a millidegree and clamped into its limits
// (articula/line.h, ypp_point_angles, the firmware's own), then moved to as M would.
Status ControllerModel::solve_point(MotorState<kMaxJoints>& next, const int32_t* um) const {
  if (!has_ik_ || n_ != 3) return kNoClosedForm;
  Millideg best[kMaxJoints] = {};
  const Status s = ypp_point_angles(best, arm_, robot_.actuation.motors,
                                    make_vec3(float(um[0]) * 0.001f, float(um[1]) * 0.001f, float(um[2]) * 0.001f),
                                    planned_.commanded);
  return s != kOk ? s : move_absolute(next, robot_.actuation, best);
}

// T (controller.cpp, line_command): the line cut by the firmware's rule in float
// (articula/line.h), checked whole before anything is queued, then each segment a move.
Status ControllerModel::line(PredictRecord& r, const int32_t* arg) {
  if (!has_ik_ || n_ != 3) return kNoClosedForm;
  const YppLineSolver solver = {&arm_, robot_.actuation.motors};
  float from[3], to[4];
  for (int k = 0; k < 4; ++k) to[k] = float(arg[k]) * 0.001f;
  solver.tool(from, planned_.commanded);
  const float tol = float(int32_t(settings_.value[ControllerSettings::kChord])) * 0.001f;
  LineCutter<float, kMaxJoints> cut;
  Millideg end[kMaxJoints] = {};
  cut.start(from, to, planned_.commanded, 3, tol);
  while (!cut.done()) {
    const Status s = cut.next(solver, end);
    if (s == kOk) continue;
    const float f = cut.refused_fraction();
    add_note(r, std::string(s == kLineNotFollowed ? "the pose would jump" : "cannot be reached") + " at " +
                    number_text(std::round(double(f) * cut.length() * 10) / 10) + " mm along the line of " +
                    number_text(std::round(double(cut.length()) * 10) / 10) + " mm, at (" +
                    number_text(std::round((from[0] + f * (to[0] - from[0])) * 10) / 10) + ", " +
                    number_text(std::round((from[1] + f * (to[1] - from[1])) * 10) / 10) + ", " +
                    number_text(std::round((from[2] + f * (to[2] - from[2])) * 10) / 10) + ") mm; nothing moves");
    return s;
  }
  cut.start(from, to, planned_.commanded, 3, tol);
  const MotorState<kMaxJoints> before = planned_;
  r.segments.clear();
  while (!cut.done()) {
    cut.next(solver, end);
    MotorState<kMaxJoints> next = planned_;
    move_absolute(next, robot_.actuation, end);
    PredictRecord::Segment seg;
    for (int i = 0; i < n_; ++i) {
      const int32_t d = next.steps[i] - planned_.steps[i];
      seg.delta_steps.push_back(d);
      seg.dominant_steps = std::max(seg.dominant_steps, uint32_t(d < 0 ? -d : d));
    }
    planned_ = next;
    if (seg.dominant_steps == 0) continue;  // within the same steps: nothing queued
    seg.cruise4 = segment_cruise4(seg.dominant_steps,
                                  segment_ticks4(cut.segment_length(), to[3], kControllerTickHz));
    r.segments.push_back(seg);
  }
  // From rest to rest, all its segments planned at once.
  const uint64_t ticks = segments_ticks(
      r.segments, plan_segments(r.segments, settings_.motion(), settings_.value[ControllerSettings::kJunction]),
      settings_.motion());
  // The tool at every step the motors make, against the line.
  std::vector<const std::vector<int32_t>*> moves;
  for (const auto& sg : r.segments) moves.push_back(&sg.delta_steps);
  const std::vector<Vec3<double>> path = tool_path(robot_, before.steps, offset_, moves);
  const Vec3<double> a = make_vec3(double(from[0]), double(from[1]), double(from[2]));
  const Vec3<double> b = make_vec3(double(to[0]), double(to[1]), double(to[2]));
  r.line_error_mm = distance_from_segment(path, a, b);
  add_note(r, std::to_string(r.segments.size()) + " segments; the tool at every step stays within " +
                  number_text(std::round(r.line_error_mm * 1000) / 1000) + " mm of the line");
  r.delta_steps.clear();
  r.dominant_steps = 0;
  for (int i = 0; i < n_; ++i) {
    const int32_t d = planned_.steps[i] - before.steps[i];
    r.delta_steps.push_back(d);
  }
  if (r.segments.empty()) {
    add_note(r, "within the same steps: only the commanded angles change, nothing is queued");
    return kOk;
  }
  r.queued = true;
  r.action = PredictRecord::Action::kMove;
  r.motion = settings_.motion();
  r.junction = settings_.value[ControllerSettings::kJunction];
  for (const auto& sg : r.segments) r.dominant_steps += sg.dominant_steps;
  r.ticks = ticks;
  r.start_tick = clock_;
  clock_ += ticks;
  r.end_tick = clock_;
  return kOk;
}

// H (queue_command and stepper.cpp): switch motors seek their switch one after the other at
// the homing rate, then every motor moves to its home step in one move.
Status ControllerModel::home(PredictRecord& r) {
  const uint32_t mask = settings_.value[ControllerSettings::kEndstops];
  MotorState<kMaxJoints> next = planned_;
  const uint32_t rate = settings_.value[ControllerSettings::kHomingRate];
  const uint64_t homing_ticks = (kControllerTickHz + rate / 2) / rate;
  uint64_t seek = 0;
  const bool was_homed = homed_;
  for (int i = 0; i < n_; ++i) {
    const MotorSpec& m = robot_.actuation.motors[i];
    next.commanded[i] = (mask & (1u << i)) ? m.min : home_[size_t(i)];
    next.steps[i] = quantize_within_limits(m, next.commanded[i]);
  }
  MotorState<kMaxJoints> after_seek = planned_;
  for (int i = 0; i < n_; ++i) {
    if (!(mask & (1u << i))) continue;
    // One homing interval per step to the switch, and one more to see it pressed.
    const int64_t d = int64_t(planned_.steps[i]) + offset_[i] - next.steps[i];
    seek += uint64_t((d < 0 ? -d : d) + 1) * homing_ticks;
    after_seek.steps[i] = next.steps[i];
    offset_[i] = 0;  // the switch tells the controller where the motor really is
  }
  if (mask != 0)
    add_note(r, std::string("seek time assumes each switch trips at its motor's minimum angle") +
                    (was_homed ? "" : " and the arm starts at the steps the controller counts (0 at power-up)"));
  homed_ = true;  // until the search fails: the firmware's rule, a search cannot fail here
  planned_ = after_seek;
  queue_move(r, next, true, seek);
  return kOk;
}

Status ControllerModel::run_command(PredictRecord& r, const std::string& text) {
  Command cmd;
  const Status parsed = parse_protocol_line(cmd, text, n_);
  if (parsed != kOk) return parsed;
  r.command = cmd.type;
  if (text.find('!') != std::string::npos)
    add_note(r, "the line holds '!': sent to the arm it stops the arm and empties the queue (not simulated)");
  if (text.find('?') != std::string::npos) add_note(r, "the line holds '?': the arm answers it with a status report");
  switch (cmd.type) {
    case kCmdNone:
      return kOk;
    case kCmdInfo:
      add_note(r, "answered with an info line; nothing moves");
      return kOk;
    case kCmdListSettings:
      add_note(r, "answered with the settings; nothing moves");
      return kOk;
    case kCmdName: {
      const Status s = config_check_name(text.data() + cmd.arg[0], uint8_t(cmd.arg[1]));
      if (s == kOk) add_note(r, "stages the robot's name in the configuration (robot configuration: not simulated)");
      return s;
    }
    case kCmdSetSetting: {
      if (cmd.arg[0] >= 100) {  // the robot configuration (articula/config.h)
        if (cmd.arg[0] == kCommitSetting) {
          add_note(r, "commits the staged robot configuration when its checksum is this one (not simulated: the "
                      "prediction keeps this robot file's arm)");
          add_note(r, kWaitsForRest);
          r.waits_for_rest = true;
          return kOk;
        }
        const Status s = config_check(uint16_t(cmd.arg[0]), cmd.arg[1]);
        if (s == kOk) add_note(r, "stages a value of the robot configuration (not simulated)");
        return s;
      }
      const Status s = check_setting(n_, cmd.arg[0], cmd.arg[1]);
      if (s != kOk) return s;
      settings_.value[size_t(cmd.arg[0])] = uint32_t(cmd.arg[1] / 1000);
      add_note(r, cmd.arg[0] == ControllerSettings::kEndstops
                      ? "saved; decides Alarm at the next power-up, H uses it from now"
                      : "takes effect for the actions after it");
      add_note(r, kWaitsForRest);
      r.waits_for_rest = true;
      return kOk;
    }
    case kCmdSetZero: {
      bool shifted = false;
      for (int i = 0; i < n_; ++i) {
        const int32_t physical = planned_.steps[i] + offset_[i];
        planned_.commanded[i] = home_[size_t(i)];
        planned_.steps[i] = home_steps_[size_t(i)];
        offset_[i] = physical - planned_.steps[i];
        shifted = shifted || offset_[i] != 0;
      }
      homed_ = true;
      add_note(r, shifted ? "nothing moves: the controller now counts the arm's pose as home, so its steps "
                            "and limits are off the arm's (joint values and tools below are where the arm really is)"
                          : "nothing moves");
      add_note(r, kWaitsForRest);
      r.waits_for_rest = true;
      return kOk;
    }
    case kCmdRotate:
    case kCmdMoveAbsolute:
    case kCmdMoveTool: {
      if (!homed_) return kNotHomed;
      MotorState<kMaxJoints> next = planned_;
      Status s;
      if (cmd.type == kCmdRotate) {
        s = move_relative(next, robot_.actuation, uint8_t(cmd.arg[0]), cmd.arg[1]);
        if (s == kJointLimit) {
          int32_t target[kMaxJoints];
          for (int i = 0; i < n_; ++i) target[i] = planned_.commanded[i] + (i == cmd.arg[0] ? cmd.arg[1] : 0);
          add_note(r, limit_note(robot_, target));
        }
      } else if (cmd.type == kCmdMoveAbsolute) {
        s = move_absolute(next, robot_.actuation, cmd.arg);
        if (s == kJointLimit) add_note(r, limit_note(robot_, cmd.arg));
      } else {
        r.has_target = true;
        r.target = make_vec3(cmd.arg[0] / 1000.0, cmd.arg[1] / 1000.0, cmd.arg[2] / 1000.0);
        s = solve_point(next, cmd.arg);
        if (s == kNoClosedForm)
          add_note(r,
                   "the firmware solves P only for a yaw-pitch-pitch arm with 3 motors (identity or "
                   "parallelogram coupling)");
      }
      if (s != kOk) return s;
      return queue_move(r, next, false);
    }
    case kCmdLine: {
      if (!homed_) return kNotHomed;
      r.has_target = true;
      r.target = make_vec3(cmd.arg[0] / 1000.0, cmd.arg[1] / 1000.0, cmd.arg[2] / 1000.0);
      const Status s = line(r, cmd.arg);
      if (s == kNoClosedForm)
        add_note(r, "the firmware runs T only for a yaw-pitch-pitch arm with 3 motors (identity or parallelogram "
                    "coupling); articula run follows the line on any robot");
      return s;
    }
    case kCmdGripper:
    case kCmdAperture: {
      const int32_t aperture = cmd.type == kCmdAperture ? cmd.arg[0] : (cmd.arg[0] ? 0 : 100000);
      queue_gripper(r, aperture);
      return kOk;
    }
    case kCmdHome:
      return home(r);
    case kCmdDwell:  // (the parser checked its range)
      queue_pause(r, uint64_t(cmd.arg[0]));
      add_note(r, "waits; nothing moves");
      return kOk;
  }
  return kUnknownCommand;
}

PredictRecord ControllerModel::execute_line(const std::string& line, int line_number) {
  PredictRecord r = begin(line_number, line);
  if (is_stop_line(line)) {  // the realtime stop
    r.stop = true;
    add_note(r, "stops the arm: it decelerates along its path to rest and empties its queue; the lines after it "
                "wait for rest and start from the steps reached (never answered)");
    finish(r);
    return r;
  }
  // A rejected line changes nothing: what a command can change is put back (no command changes
  // anything before it fails; this makes sure). Not the whole model: its robot is large.
  const MotorState<kMaxJoints> planned = planned_;
  int32_t offset[kMaxJoints];
  std::copy(offset_, offset_ + kMaxJoints, offset);
  const bool homed = homed_;
  const ControllerSettings settings = settings_;
  const int gripper = gripper_percent_;
  const uint64_t clock = clock_;
  r.reply = run_command(r, line);
  if (r.reply != kOk) {
    planned_ = planned;
    std::copy(offset, offset + kMaxJoints, offset_);
    homed_ = homed;
    settings_ = settings;
    gripper_percent_ = gripper;
    clock_ = clock;
    r.queued = false;
    r.action = PredictRecord::Action::kNone;
    r.waits_for_rest = false;
    r.ticks = r.dominant_steps = 0;
  }
  finish(r);
  return r;
}

void ControllerModel::ensure_ik() {
  if (!ik_) ik_.emplace(robot_);
}

// RoboSim statements, as the protocol commands a harness sends for them.
void ControllerModel::robosim(PredictRecord& r, const Statement& st) {
  const int nj = robot_.model.num_joints;
  switch (st.kind) {
    case Statement::Kind::kJoints:
    case Statement::Kind::kTarget: {
      if (!homed_) {
        r.reply = kNotHomed;
        return;
      }
      double q[kMaxJoints];
      if (st.kind == Statement::Kind::kJoints) {
        for (int j = 0; j < nj; ++j)
          q[j] = joint_to_model(robot_, j, st.values[size_t(j)]);
      } else {
        r.has_target = true;
        r.target = make_vec3(st.values[0], st.values[1], st.values[2]);
        ensure_ik();
        std::vector<double> start(static_cast<size_t>(nj));
        double u[kMaxJoints];
        for (int i = 0; i < n_; ++i) u[i] = deg_to_rad(planned_.commanded[i] / 1000.0);
        joints_from_actuators(start.data(), robot_.actuation, u);
        IkOptions opt;
        opt.weights = weights_;
        IkResult res;
        try {
          res = ik_->solve(IkTarget::at(r.target), start, opt);
        } catch (const std::invalid_argument& e) {
          r.reply = kUnreachable;
          add_note(r, e.what());
          return;
        }
        r.ik_status = ik_status_name(res.status);
        if (!res.reached()) {
          r.reply = kUnreachable;
          add_note(r, std::string("ik: ") + ik_status_name(res.status) + ", the best pose is " +
                          number_text(std::round(res.position_error_mm * 1000) / 1000) +
                          " mm from the target (P would be refused likewise)");
          return;
        }
        for (int j = 0; j < nj; ++j) q[j] = res.q[size_t(j)];
      }
      // u = C^-1 q, to exact millidegrees: what M sends.
      double u[kMaxJoints];
      actuators_from_joints(u, robot_.actuation, q);
      Millideg target[kMaxJoints];
      std::vector<double> sent;  // M's values, degrees: exact thousandths
      for (int i = 0; i < n_; ++i) {
        if (!to_millideg(target[i], rad_to_deg(u[i]))) {
          r.reply = kValueOutOfRange;
          return;
        }
        // The IK keeps the motors' limits up to rounding; m's values are sent as they are.
        if (st.kind == Statement::Kind::kTarget)
          target[i] = clamp(target[i], robot_.actuation.motors[i].min, robot_.actuation.motors[i].max);
        sent.push_back(target[i] / 1000.0);
      }
      r.protocol = protocol_line(robot_, 'M', sent, true);
      r.command = kCmdMoveAbsolute;
      MotorState<kMaxJoints> next = planned_;
      r.reply = move_absolute(next, robot_.actuation, target);
      if (r.reply == kOk) queue_move(r, next, false);
      return;
    }
    case Statement::Kind::kLinkLengths: {
      set_link_lengths(robot_, st.values);
      ik_.reset();
      add_note(
          r,
          "host model only: the real arm's links cannot change length (tool positions from here use the new lengths)");
      return;
    }
    case Statement::Kind::kWeights:
      weights_ = st.values;
      ensure_ik();
      if (ik_->has_closed_form() && std::find(weights_.begin(), weights_.end(), 0.0) == weights_.end())
        add_note(r, "IK weights for a; the closed form this arm uses ignores them unless one is 0 (frozen)");
      else
        add_note(r, "IK weights for a");
      return;
    case Statement::Kind::kSpeed: {
      const uint32_t rate = robosim_speed_to_rate(st.values[0], base_rate_);
      settings_.value[ControllerSettings::kMaxRate] = rate;
      r.protocol = protocol_line(robot_, '$', {double(kSetMaxRate), double(rate)});
      r.command = kCmdSetSetting;
      add_note(r, "top step rate " + std::to_string(rate) + " steps/s (" + number_text(st.values[0]) + "/" + number_text(kRoboSimFastest) + " of " +
                      std::to_string(base_rate_) + ")");
      add_note(r, kWaitsForRest);
      r.waits_for_rest = true;
      return;
    }
    case Statement::Kind::kHand: {
      const int32_t aperture = robosim_hand_to_aperture(st.values[0]);
      r.protocol = protocol_line(robot_, 'G', {aperture / 1000.0}, true);
      r.command = kCmdAperture;
      queue_gripper(r, aperture);
      return;
    }
    case Statement::Kind::kZoom:
      add_note(r, "zoom is for a viewer: no effect on the arm");
      return;
    case Statement::Kind::kProtocol:
      break;
  }
}

PredictRecord ControllerModel::execute(const Statement& st) {
  if (st.kind == Statement::Kind::kProtocol) return execute_line(st.text, st.line);
  std::string text(1, robosim_letter(st.kind));
  for (double v : st.values) text += " " + number_text(v);
  PredictRecord r = begin(st.line, text);
  ControllerModel saved = *this;
  robosim(r, st);
  if (r.reply != kOk) {  // nothing changes, but keep what the attempt found out
    *this = saved;
    r.queued = false;
    r.action = PredictRecord::Action::kNone;
    r.waits_for_rest = false;
    r.ticks = r.dominant_steps = 0;
    r.protocol.clear();
  }
  finish(r);
  return r;
}

}  // namespace articula::host
