// host/lib/nano_config.cpp - robot file to Nano configuration (nano_config.h).
#include "nano_config.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "program.h"

namespace articula::host {

namespace {
std::string setting_line(uint16_t n, int32_t thousandths) {
  char buf[kSettingLineSize];
  const uint16_t len = format_setting(buf, sizeof buf, n, thousandths);
  return std::string(buf, len > 0 ? len - 1 : 0);  // without its LF
}

// The robot's model and motors in float, as the Nano computes with them.
struct FloatArm {
  Model<float, kMaxJoints, kMaxRows> model;
  Actuation<float, kMaxJoints> actuation{};
};

FloatArm float_arm(const Robot& robot) {
  FloatArm f{cast_model<float>(robot.model), {}};
  const int n = robot.actuation.num_motors;
  f.actuation.num_motors = uint8_t(n);
  for (int i = 0; i < n; ++i) {
    f.actuation.motors[i] = robot.actuation.motors[i];
    for (int j = 0; j < n; ++j) f.actuation.coupling[i][j] = float(robot.actuation.coupling[i][j]);
  }
  return f;
}

// The name as an `N` line carries it: no blanks at its ends (the parser drops them), cut to
// kMaxRobotName, and '-' for what the line cannot carry (a control or non-ASCII byte, the
// banner's '|' and ']', '#' that starts a comment, '?' and '!' that act at once).
std::string line_name(const std::string& name) {
  std::string out;
  size_t b = name.find_first_not_of(" \t");
  for (size_t i = b; b != std::string::npos && i < name.size() && out.size() < kMaxRobotName; ++i) {
    const char c = name[i];
    const bool bad = c < 0x20 || c > 0x7e || c == '|' || c == ']' || c == '#' || c == '?' || c == '!';
    out += bad ? '-' : c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out.empty() ? "-" : out;
}
}  // namespace

bool float_ypp_arm(const Robot& robot, YppArm<float>& arm) {
  const FloatArm f = float_arm(robot);
  return ypp_from_model(arm, f.model) && ypp_limits_from_actuation(arm, f.actuation);
}

NanoConfig nano_config(const Robot& robot) {
  const std::string who = robot.name + " (" + robot.source + "): ";
  const auto fail = [&](const std::string& why) { return NanoConfigError(who + why); };
  if (!robot.has_motors) throw fail("has no motors: the Nano drives steppers, and this robot file names none");
  const int n = robot.actuation.num_motors;
  if (n > kMaxConfigMotors)
    throw fail(std::to_string(n) + " motors: the Nano drives at most " + std::to_string(int(kMaxConfigMotors)));
  NanoConfig out;
  out.image.assign(kConfigImageSize, 0);
  uint8_t* image = out.image.data();
  // Every value through the firmware's own check, so the Nano takes every line.
  const auto put = [&](uint16_t s, int32_t thousandths) {
    if (config_check(s, thousandths) != kOk)
      throw fail("$" + std::to_string(s) + " would be " + number_text(thousandths / 1000.0) +
                 ": beyond what the configuration carries (docs/protocol.md, \"Robot configuration\")");
    config_put(image, s, thousandths);
  };
  put(130, n * 1000);
  // How the motors are driven: the robot file's drivers (an L298N each when it names none).
  const DriveKind drive = arm_drive(robot);
  put(131, int32_t(drive) * 1000);
  // A servo arm: each servo's step-0 pulse and pin, and the rate and acceleration its servos
  // take, in ticks (the slowest servo's: the controller's rate is the dominant motor's).
  if (drive == kDriveServo) {
    double rate = 4000, accel = 100000;
    bool accel_given = false;
    for (int i = 0; i < n; ++i) {
      const MotorDriver& d = robot.drive.motors[size_t(i)];
      const MotorSpec& m = robot.actuation.motors[i];
      const double ticks_per_deg = servo_ticks_per_deg(m);
      put(uint16_t(132 + i), int32_t(d.at[0][0]) * 1000);
      put(uint16_t(135 + i), d.pin * 1000);
      rate = std::min(rate, d.speed_deg_s * ticks_per_deg);
      if (d.accel_deg_s2 > 0) {
        accel = std::min(accel, d.accel_deg_s2 * ticks_per_deg);
        accel_given = true;
      }
    }
    put(138, int32_t(std::max(1.0, std::floor(rate))) * 1000);
    put(139, accel_given ? int32_t(std::max(1.0, std::floor(accel))) * 1000 : 0);
  }
  // The home pose as motor angles, u = C^-1 q, in float with the core's 3 x 3 solve (C padded
  // with the identity), as the firmware's arithmetic would have it.
  const FloatArm f = float_arm(robot);
  float sys[3][4], u[3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) sys[r][c] = r < n && c < n ? f.actuation.coupling[r][c] : float(r == c);
    sys[r][3] = r < n && r < int(robot.home.size()) ? float(robot.home[size_t(r)]) : 0.0f;
  }
  if (!detail::solve3(u, sys))
    for (int i = 0; i < 3; ++i) u[i] = sys[i][3];
  for (int i = 0; i < 3; ++i) {  // unused motors: a valid placeholder
    const bool used = i < n;
    const MotorSpec m = used ? robot.actuation.motors[i] : MotorSpec{200, 1, 1, 1, 1, 0, 0, 0};
    const std::string motor = used ? "the " + robot.motor_names[size_t(i)] + " motor" : "";
    if (m.microsteps > 2 && drive != kDriveStepDir)
      throw fail(motor + " has " + std::to_string(int(m.microsteps)) + " microsteps: the Nano's " +
                 kDriveKindInfo[drive].title + " drivers make full steps (1) or half steps (2)");
    if (validate(m) != kMotorOk) throw fail(motor + ": " + motor_error_text(validate(m)));
    const uint16_t b = uint16_t(100 + 10 * i);
    const int32_t whole[5] = {m.full_steps_per_rev, m.microsteps, m.direction, m.gear_num, m.gear_den};
    for (int k = 0; k < 5; ++k) put(uint16_t(b + k), whole[k] * 1000);
    Millideg home = m.zero;
    if (used) {
      to_millideg(home, rad_to_deg(u[i]));
      home = clamp(home, m.min, m.max);
    }
    const Millideg angles[4] = {m.zero, m.min, m.max, home};
    for (int k = 0; k < 4; ++k) put(uint16_t(b + 5 + k), angles[k]);
    for (int j = 0; j < 3; ++j) {
      const double c = (used && j < n ? robot.actuation.coupling[i][j] : double(i == j)) * 1000.0;
      if (std::fabs(c - std::round(c)) > 1e-6 || std::fabs(c) > 1e9)
        throw fail("coupling entry [" + std::to_string(i) + "][" + std::to_string(j) +
                   "] is not a multiple of 0.001 within 1,000,000: the configuration carries three decimals");
      put(uint16_t(140 + 3 * i + j), int32_t(std::lround(c)));
    }
  }
  // P's closed form, when the model is of its family: the geometry in micrometres.
  YppArm<float> arm;
  int32_t um[6];
  if (n == 3 && ypp_from_model(arm, f.model)) {
    const float g[6] = {arm.base_height, arm.shoulder_offset, arm.upper, arm.fore, arm.tool_forward, arm.tool_up};
    bool fits = true;
    for (int k = 0; k < 6; ++k) fits = fits && to_millideg(um[k], g[k]);  // mm to micrometres: the same rounding
    if (fits) {
      put(150, 1000);
      for (int k = 0; k < 6; ++k) put(uint16_t(151 + k), um[k]);
    }
  }
  const bool grip = robot.gripper.present;
  const float servo[2] = {grip ? float(robot.gripper.servo_open_deg) : 90.0f,
                          grip ? float(robot.gripper.servo_closed_deg) : 90.0f};
  for (int k = 0; k < 2; ++k) {
    int32_t v = 0;
    if (!to_millideg(v, servo[k])) v = -1;  // (refused by put's check)
    put(uint16_t(160 + k), v);
  }
  const std::string name = line_name(robot.name);
  config_name_bytes(image + kConfigNameOffset, name.data(), uint8_t(name.size()));

  if (config_read(out.arm, image) != kConfigOk) throw fail("the configuration does not read back (a bug)");
  out.checksum = config_checksum(image);
  for (uint16_t s = 100; s <= 161; ++s) {
    ConfigField field;
    if (!config_field(s, field)) continue;
    const int32_t v = config_get(image, s);
    out.lines.push_back(setting_line(s, field.whole ? v * 1000 : v));
  }
  out.lines.push_back(std::string("N ") + out.arm.name);
  out.lines.push_back(setting_line(kCommitSetting, int32_t(out.checksum) * 1000));
  return out;
}

ConfiguredArm<kFirmwareMotors> firmware_arm(const Robot& robot) {
  ConfiguredArm<kFirmwareMotors> out{};
  const int n = robot.actuation.num_motors;
  try {
    const NanoConfig c = nano_config(robot);
    if (config_read(out, c.image.data()) != kConfigOk) throw NanoConfigError("the configuration does not read back (a bug)");
    return out;
  } catch (const NanoConfigError&) {
    if (!robot.has_motors) throw;
  }
  if (n > kFirmwareMotors)
    throw NanoConfigError(robot.name + " (" + robot.source + "): " + std::to_string(n) +
                          " motors: the firmware drives at most " + std::to_string(kFirmwareMotors));
  const FloatArm f = float_arm(robot);
  out.actuation.num_motors = uint8_t(n);
  double u[kMaxJoints];
  HostActuation a = robot.actuation;
  if (!invert_coupling(a))
    for (int i = 0; i < n; ++i) a.coupling_inv[i][i] = 1;
  actuators_from_joints(u, a, robot.home.data());
  for (int i = 0; i < n; ++i) {
    const MotorSpec& m = robot.actuation.motors[i];
    out.actuation.motors[i] = m;
    for (int j = 0; j < n; ++j) out.actuation.coupling[i][j] = f.actuation.coupling[i][j];
    Millideg h = m.zero;
    to_millideg(h, rad_to_deg(u[i]));
    out.home[i] = clamp(h, m.min, m.max);
  }
  for (int i = n; i < kFirmwareMotors; ++i) out.actuation.motors[i] = MotorSpec{200, 1, 1, 1, 1, 0, 0, 0};
  // (Not a configuration the Nano takes: its steps drive no servo build, so its servos are
  // taken as steppers.)
  const DriveKind kind = arm_drive(robot);
  out.drive = uint8_t(kind == kDriveServo ? kDriveL298n : kind);
  out.has_point = float_ypp_arm(robot, out.arm);
  out.servo_open_deg = out.servo_closed_deg = 90.0f;
  if (robot.gripper.present) {
    out.servo_open_deg = float(robot.gripper.servo_open_deg);
    out.servo_closed_deg = float(robot.gripper.servo_closed_deg);
  }
  const std::string name = line_name(robot.name);
  std::memcpy(out.name, name.data(), name.size());
  return out;
}

}  // namespace articula::host
