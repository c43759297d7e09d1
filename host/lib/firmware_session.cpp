// host/lib/firmware_session.cpp - a program's statements as lines, and the firmware as a live
// session (firmware_session.h).
#include "firmware_session.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "blocks.h"
#include "firmware_machine.h"
#include "ik.h"
#include "records_json.h"

// The firmware (firmware/src, built for the host's eight motors: firmware/sitl/sitl.cmake).
#include "firmware.h"
#include "hal_sitl.h"
#include "machine.h"
#include "queue.h"

namespace articula::host {

namespace {
void say(PredictRecord& r, const std::string& note) { append_note(r.note, note); }
}  // namespace


// The statements as the host sends them: RoboSim's as protocol lines (a: the IK from the
// pose the firmware plans when the line goes), the host-only ones (l, w, z; a line the
// protocol cannot parse; an a without a solution) kept as records and never sent.
StatementLines::StatementLines(Robot& robot, uint32_t base_rate, std::function<std::vector<Millideg>()> commanded)
    : robot_(robot), base_rate_(base_rate), commanded_(std::move(commanded)) {}
StatementLines::~StatementLines() = default;

bool StatementLines::begin(const Statement& st, PredictRecord& r, std::string& line) {
    r.line = st.line;
    if (st.kind == Statement::Kind::kProtocol) {
      r.text = st.text;
      if (is_stop_line(st.text)) {
        r.stop = true;
        say(r, "stops the arm: it decelerates along its path to rest and empties its queue; the lines after "
                    "it wait for rest and start from the steps reached (never answered)");
        line = "!";
        return true;
      }
      Command cmd;
      r.reply = parse_protocol_line(cmd, st.text, robot_.actuation.num_motors);
      if (r.reply != kOk || cmd.type == kCmdNone) return false;
      r.command = cmd.type;
      line = st.text;
      // (The realtime bytes inside a line: not sent with it.)
      if (line.find('!') != std::string::npos)
        say(r, "the line holds '!': sent to the arm it stops the arm and empties the queue (not simulated)");
      if (line.find('?') != std::string::npos)
        say(r, "the line holds '?': the arm answers it with a status report");
      line.erase(std::remove_if(line.begin(), line.end(), [](char c) { return c == '!' || c == '?'; }), line.end());
      return true;
    }
    r.text = std::string(1, robosim_letter(st.kind));
    for (double v : st.values) r.text += " " + number_text(v);
    robosim(st, r);
    if (r.reply != kOk || r.protocol.empty()) return false;
    line = r.protocol;
    return true;
}

void StatementLines::robosim(const Statement& st, PredictRecord& r) {
    const int nj = robot_.model.num_joints, n = robot_.actuation.num_motors;
    switch (st.kind) {
      case Statement::Kind::kJoints:
      case Statement::Kind::kTarget: {
        double q[kMaxJoints];
        if (st.kind == Statement::Kind::kJoints) {
          for (int j = 0; j < nj; ++j) q[j] = joint_to_model(robot_, j, st.values[size_t(j)]);
        } else {
          r.has_target = true;
          r.target = make_vec3(st.values[0], st.values[1], st.values[2]);
          if (!ik_) ik_ = std::make_unique<InverseKinematics>(robot_);
          std::vector<double> start(static_cast<size_t>(nj));
          double u[kMaxJoints];
          const std::vector<Millideg> plan = commanded_();
          for (int i = 0; i < n; ++i) u[i] = deg_to_rad(plan[size_t(i)] / 1000.0);
          joints_from_actuators(start.data(), robot_.actuation, u);
          IkOptions opt;
          opt.weights = weights_;
          IkResult res;
          try {
            res = ik_->solve(IkTarget::at(r.target), start, opt);
          } catch (const std::invalid_argument& e) {
            r.reply = kUnreachable;
            say(r, e.what());
            return;
          }
          r.ik_status = ik_status_name(res.status);
          if (!res.reached()) {
            r.reply = kUnreachable;
            say(r, std::string("ik: ") + ik_status_name(res.status) + ", the best pose is " +
                            number_text(std::round(res.position_error_mm * 1000) / 1000) +
                            " mm from the target (P would be refused likewise)");
            return;
          }
          for (int j = 0; j < nj; ++j) q[j] = res.q[size_t(j)];
        }
        // u = C^-1 q, to exact millidegrees: what M sends.
        double u[kMaxJoints];
        actuators_from_joints(u, robot_.actuation, q);
        std::vector<double> sent;  // M's values, degrees: exact thousandths
        for (int i = 0; i < n; ++i) {
          Millideg t;
          if (!to_millideg(t, rad_to_deg(u[i]))) {
            r.reply = kValueOutOfRange;
            return;
          }
          // The IK keeps the motors' limits up to rounding; m's values are sent as they are.
          if (st.kind == Statement::Kind::kTarget)
            t = clamp(t, robot_.actuation.motors[i].min, robot_.actuation.motors[i].max);
          sent.push_back(t / 1000.0);
        }
        r.protocol = protocol_line(robot_, 'M', sent, true);
        r.command = kCmdMoveAbsolute;
        return;
      }
      case Statement::Kind::kLinkLengths:
        set_link_lengths(robot_, st.values);
        ik_.reset();
        say(r, "host model only: the real arm's links cannot change length (tool positions from here use the "
                    "new lengths)");
        return;
      case Statement::Kind::kWeights:
        weights_ = st.values;
        if (!ik_) ik_ = std::make_unique<InverseKinematics>(robot_);
        if (ik_->has_closed_form() && std::find(weights_.begin(), weights_.end(), 0.0) == weights_.end())
          say(r, "IK weights for a; the closed form this arm uses ignores them unless one is 0 (frozen)");
        else
          say(r, "IK weights for a");
        return;
      case Statement::Kind::kSpeed: {
        const uint32_t rate = robosim_speed_to_rate(st.values[0], base_rate_);
        r.protocol = protocol_line(robot_, '$', {double(kSetMaxRate), double(rate)});
        r.command = kCmdSetSetting;
        say(r, "top step rate " + std::to_string(rate) + " steps/s (" + number_text(st.values[0]) + "/" +
                        number_text(kRoboSimFastest) + " of " + std::to_string(base_rate_) + ")");
        return;
      }
      case Statement::Kind::kHand:
        r.protocol = protocol_line(robot_, 'G', {robosim_hand_to_aperture(st.values[0]) / 1000.0}, true);
        r.command = kCmdAperture;
        return;
      case Statement::Kind::kZoom:
        say(r, "zoom is for a viewer: no effect on the arm");
        return;
      case Statement::Kind::kProtocol:
        break;
    }
}

// ---- a live session (firmware_session.h) ----

namespace {

// One event of the machine's: the clock to the next thing that happens.
void machine_step() { sitl::run_to(sitl::next_event()); }

// How long the firmware may take to answer a line (one waiting for the arm to be at rest).
const uint64_t kReplyWithin = 3600 * sitl::kSecond;
}  // namespace

FirmwareSession::FirmwareSession(const Robot& robot, const ControllerSettings& settings)
    : robot_(robot), settings_(settings), nano_(std::make_unique<sitl::Machine>()) {
  const ConfiguredArm<kFirmwareMotors> arm = machine_arm(robot_);
  const sitl::Machine::Use use(*nano_);
  power_up(robot_, arm, settings_);
  const sitl::Hardware& hw = sitl::hw();
  t0_ = hw.now;
  coils_ = hw.coil_log.size();
  actions_ = hw.actions.size();
  replies_ = hw.replies.size();
  queued_ = hw.queued.size();
}

FirmwareSession::~FirmwareSession() = default;

Status FirmwareSession::send(const std::string& text, int line, uint64_t tick, Sender sender) {
  const sitl::Machine::Use use(*nano_);
  const sitl::Hardware& hw = sitl::hw();
  uint64_t at = std::max(tick, now_);
  if (sender == kStreamed) at = std::max(at, wire_);
  sitl::run_to(t0_ + at);
  if (sender == kAtRest) {
    const uint64_t give_up = hw.now + kReplyWithin;
    while (!sitl::at_rest() && hw.now < give_up) machine_step();
    at = hw.now - t0_;
  }
  const bool bang = is_stop_line(text);
  // (As run_lines sends: the first line, and each at rest, all in at once; streamed, byte
  // after byte on the wire.)
  const Sent x{text, line, at, sender == kAtRest || !sent_any_};
  sent_any_ = true;
  put(x);
  if (bang) {
    sitl::run_to(sitl::hw().now);
    now_ = hw.now - t0_;
    harvest();
    return kOk;
  }
  unanswered_.push_back(x);
  const size_t want = hw.replies.size() + unanswered_.size();
  const uint64_t give_up = hw.now + kReplyWithin;
  while (hw.replies.size() < want && hw.now < give_up) machine_step();
  now_ = hw.now - t0_;
  if (hw.replies.size() < want) {
    harvest();
    throw std::runtime_error("line " + std::to_string(line) + " (" + text + "): the firmware did not answer within " +
                             std::to_string(kReplyWithin / sitl::kSecond) + " s");
  }
  const Status status = Status(hw.replies.back().status);
  wire_ = now_ + (reply_text(status).size() + 1) * sitl::kByteTicks;
  harvest();
  return status;
}

void FirmwareSession::put(const Sent& x) {
  const std::string bytes = is_stop_line(x.text) ? "!" : x.text + "\n";
  if (x.at_once)
    sitl::send(bytes);
  else
    sitl::send_at(t0_ + x.at, bytes);
}

void FirmwareSession::run_to(uint64_t tick) {
  const sitl::Machine::Use use(*nano_);
  if (feed_) {
    run_feeding(t0_ + tick);
    now_ = std::max(now_, sitl::hw().now - t0_);
    harvest();
    return;
  }
  if (tick <= now_) return;
  sitl::run_to(t0_ + tick);
  now_ = tick;
  harvest();
}

// Event by event, so that a line goes at the very tick the arm comes to rest after the reply
// before (as send() with kAtRest sends it).
void FirmwareSession::run_feeding(uint64_t until) {
  const sitl::Hardware& hw = sitl::hw();
  for (;;) {
    // The firmware reads what came and answers it at this very tick (as run_lines' sender
    // sees it), before the next line goes or the clock moves on.
    for (sitl::run_to(hw.now); feed_ && hw.replies.size() >= feed_answers_ && sitl::at_rest(); sitl::run_to(hw.now))
      if (!feed_next()) break;
    if (hw.now >= until) return;
    sitl::run_to(std::min(sitl::next_event(), until));
  }
}

bool FirmwareSession::feed_next() {
  const sitl::Hardware& hw = sitl::hw();
  harvest();  // (the replies so far taken off unanswered_)
  const uint64_t at = hw.now - t0_;
  std::string text;
  int line = 0;
  if (!feed_(at, text, line)) {
    feed_ = nullptr;
    feed_ended_ = at;
    return false;
  }
  const Sent x{text, line, at, true};  // (at rest: all of it in at once)
  sent_any_ = true;
  put(x);
  if (!is_stop_line(text)) {
    unanswered_.push_back(x);
    feed_answers_ = hw.replies.size() + unanswered_.size();
  }
  return true;
}

void FirmwareSession::feed(Feed next) {
  const sitl::Machine::Use use(*nano_);
  feed_ = std::move(next);
  feed_ended_ = 0;
  feed_answers_ = sitl::hw().replies.size() + unanswered_.size();
  run_feeding(sitl::hw().now);  // (the first line now, if the arm is at rest)
  harvest();
}

void FirmwareSession::drive_inputs(uint32_t driven, std::function<uint32_t(uint64_t tick)> levels) {
  const sitl::Machine::Use use(*nano_);
  sitl::Hardware& hw = sitl::hw();
  hw.io_driven = driven;
  levels_ = std::move(levels);
  hw.io_sync = [this] {
    sitl::Hardware& h = sitl::hw();
    h.io_external = levels_(h.now - t0_);
  };
}

bool FirmwareSession::input_level(int pin, uint64_t tick) {
  const uint32_t bit = uint32_t(1) << pin;
  bool output = false, driven = false;
  {
    const sitl::Machine::Use use(*nano_);
    output = (sitl::hw().io_output & bit) != 0;
    driven = (sitl::hw().io_driven & bit) && levels_;
  }
  if (output) return output_level(pin, tick);
  return driven ? (levels_(tick) & bit) != 0 : true;  // (levels_ may run other machines: not inside Use)
}

bool FirmwareSession::output_level(int pin, uint64_t tick) {
  const sitl::Machine::Use use(*nano_);
  const auto& log = sitl::hw().io_log;
  for (size_t k = log.size(); k-- > 0;)
    if (log[k].pin == pin && log[k].tick <= t0_ + tick) return log[k].high;
  return true;  // (every free pin powers up an input with its pull-up)
}

uint64_t FirmwareSession::clock() {
  const sitl::Machine::Use use(*nano_);
  return sitl::hw().now - t0_;
}

std::optional<FirmwareSession::InputWait> FirmwareSession::waiting() {
  const sitl::Machine::Use use(*nano_);
  const sitl::Hardware& hw = sitl::hw();
  if (hw.actions.empty() || hw.actions.back().kind != queue::kWaitIn) return std::nullopt;
  const size_t began = hw.actions.size() - 1;
  for (size_t q = hw.queued.size(); q-- > 0;)
    if (hw.queued[q].began == began) {
      const sitl::QueuedAction& a = hw.queued[q];
      return InputWait{a.pin, a.percent};
    }
  return std::nullopt;
}

uint64_t FirmwareSession::run_to_rest() {
  const sitl::Machine::Use use(*nano_);
  const uint64_t give_up = sitl::hw().now + kReplyWithin;
  while (!sitl::at_rest() && sitl::hw().now < give_up) machine_step();
  now_ = sitl::hw().now - t0_;
  harvest();
  return now_;
}

bool FirmwareSession::at_rest() {
  const sitl::Machine::Use use(*nano_);
  return sitl::at_rest();
}

std::vector<Millideg> FirmwareSession::commanded() {
  const sitl::Machine::Use use(*nano_);
  const robot::State& plan = firmware::planned();
  return std::vector<Millideg>(plan.commanded, plan.commanded + robot_.actuation.num_motors);
}

std::vector<FirmwareSession::Event> FirmwareSession::take(uint64_t tick) {
  std::vector<Event> out;
  while (!events_.empty() && events_.front().tick <= tick) {
    out.push_back(std::move(events_.front()));
    events_.pop_front();
  }
  return out;
}

void FirmwareSession::harvest() {
  const sitl::Hardware& hw = sitl::hw();
  const int n = robot_.actuation.num_motors;
  // (Its rank at a tie: a step, then the timer's stops and the begins in the order the firmware
  // logged them (a wait met at once begins and stops at one tick), then a reply.)
  std::vector<std::pair<int, Event>> got;
  // Replies, in the order of the lines; the actions queued before each, its line's.
  for (; replies_ < hw.replies.size(); ++replies_) {
    const sitl::Reply& r = hw.replies[replies_];
    if (unanswered_.empty()) throw std::logic_error("the firmware answered a line it was never sent");
    const Sent x = std::move(unanswered_.front());
    unanswered_.pop_front();
    line_of_.resize(std::max(line_of_.size(), r.queued), x.line);
    for (; queued_ < r.queued; ++queued_) line_of_[queued_] = x.line;
    Event e;
    e.kind = Event::kReply;
    e.tick = r.tick - t0_;
    e.line = x.line;
    e.status = Status(r.status);
    e.text = x.text;
    Command cmd;
    if (e.status == kOk && parse_protocol_line(cmd, x.text, n) == kOk && cmd.type == kCmdSetZero)
      e.counted.assign(r.planned.steps, r.planned.steps + n);
    got.push_back({3, e});
  }
  // The actions queued for a line not answered yet: its.
  for (; queued_ < hw.queued.size(); ++queued_) {
    line_of_.resize(queued_ + 1, 0);
    line_of_[queued_] = unanswered_.empty() ? 0 : unanswered_.front().line;
  }
  for (; actions_ < hw.actions.size(); ++actions_) {
    const sitl::ActionEvent& a = hw.actions[actions_];
    Event e;
    e.tick = a.tick - t0_;
    e.counted.assign(a.counted, a.counted + n);
    if (a.kind == sitl::kTimerStopped) {
      e.kind = Event::kIdle;
      got.push_back({1, e});
      continue;
    }
    size_t q = next_begin_;
    while (q < hw.queued.size() && hw.queued[q].began != actions_) ++q;  // (those a '!' emptied, skipped)
    if (q == hw.queued.size()) throw std::logic_error("the firmware began an action it never queued");
    next_begin_ = q + 1;
    const sitl::QueuedAction& qa = hw.queued[q];
    e.kind = Event::kBegin;
    e.line = q < line_of_.size() ? line_of_[q] : 0;
    e.action = Event::Action(qa.kind);
    if (qa.kind == queue::kMove || qa.kind == queue::kHome) e.delta.assign(qa.delta, qa.delta + n);
    e.motion = MotionSettings{kStepTickHz, qa.max_rate, qa.accel};
    if (qa.kind == queue::kGripper) e.percent = qa.percent;
    if (qa.kind == queue::kOutput || qa.kind == queue::kWaitIn) {
      e.pin = qa.pin;
      e.level = qa.percent;
    }
    e.settle_ticks = qa.settle_ticks;
    got.push_back({1, e});
  }
  for (; coils_ < hw.coil_log.size(); ++coils_) {
    const sitl::CoilWrite& w = hw.coil_log[coils_];
    if (w.step == 0 || w.motor >= n) continue;
    const uint64_t t = w.tick - t0_;
    if (got.empty() || got.back().first != 0 || got.back().second.tick != t) {
      Event e;
      e.kind = Event::kStep;
      e.tick = t;
      got.push_back({0, e});
    }
    Event& e = got.back().second;
    e.mask = uint8_t(e.mask | (1u << w.motor));
    if (w.step < 0) e.negative = uint8_t(e.negative | (1u << w.motor));
  }
  std::stable_sort(got.begin(), got.end(), [](const auto& a, const auto& b) {
    return a.second.tick != b.second.tick ? a.second.tick < b.second.tick : a.first < b.first;
  });
  for (auto& g : got) events_.push_back(std::move(g.second));
}


}  // namespace articula::host
