// host/lib/predict.cpp - what a prediction's records are described with (predict_detail.h:
// the angles, joints and tool positions of the steps, the tool along a move, the notes on a
// refusal), the settings as text, RoboSim's mappings. predict_program() itself runs the
// firmware: predict_run.cpp.
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

// ---- describing a record (predict_detail.h) ----

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

// ---- RoboSim mappings ----

int32_t robosim_hand_to_aperture(double h) {
  const double thousandths = (100.0 - 200.0 * h) * 1000.0;
  return int32_t(std::clamp(std::llround(thousandths), 0LL, 100000LL));
}

uint32_t robosim_speed_to_rate(double s, uint32_t base) {
  const long long r = std::llround(double(base) * s / kRoboSimFastest);
  return uint32_t(std::clamp(r, 1LL, 4000LL));
}

}  // namespace articula::host
