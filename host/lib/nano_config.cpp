// host/lib/nano_config.cpp - robot file to Nano configuration (nano_config.h).
#include "nano_config.h"

#include <cmath>

namespace articula::host {

namespace {
std::string setting_line(uint16_t n, int32_t thousandths) {
  char buf[kSettingLineSize];
  const uint16_t len = format_setting(buf, sizeof buf, n, thousandths);
  return std::string(buf, len > 0 ? len - 1 : 0);  // without its LF
}
}  // namespace

NanoConfig nano_config(const Robot& robot) {
  const std::string who = robot.name + " (" + robot.source + "): ";
  const auto fail = [&](const std::string& why) { return NanoConfigError(who + why); };
  if (!robot.has_motors) throw fail("has no motors: the Nano drives steppers, and this robot file names none");
  const int n = robot.actuation.num_motors;
  if (n > kMaxConfigMotors)
    throw fail(std::to_string(n) + " motors: the Nano drives at most " + std::to_string(int(kMaxConfigMotors)));
  for (int i = 0; i < n; ++i) {
    const MotorSpec& m = robot.actuation.motors[i];
    if (m.microsteps > 2)
      throw fail("the " + robot.motor_names[size_t(i)] + " motor has " + std::to_string(int(m.microsteps)) +
           " microsteps: the Nano's L298N drivers make full steps (1) or half steps (2)");
    for (int j = 0; j < n; ++j) {
      const double c = robot.actuation.coupling[i][j] * 1000.0;
      if (std::fabs(c - std::round(c)) > 1e-6 || std::fabs(c) > 1e9)
        throw fail("coupling entry [" + std::to_string(i) + "][" + std::to_string(j) +
             "] is not a multiple of 0.001 within 1,000,000: the configuration carries three decimals");
    }
  }
  // The firmware's own path for its built-in arm (robot.cpp): the model and motors in float.
  const Model<float, kMaxJoints, kMaxRows> fm = cast_model<float>(robot.model);
  Actuation<float, kMaxJoints> fa{};
  fa.num_motors = uint8_t(n);
  for (int i = 0; i < n; ++i) {
    fa.motors[i] = robot.actuation.motors[i];
    for (int j = 0; j < n; ++j) fa.coupling[i][j] = float(robot.actuation.coupling[i][j]);
  }
  float home[kMaxJoints] = {};
  for (int i = 0; i < n && i < int(robot.home.size()); ++i) home[i] = float(robot.home[size_t(i)]);
  const bool grip = robot.gripper.present;
  NanoConfig out;
  out.image.assign(kConfigImageSize, 0);
  const ConfigFit fit = config_make(out.image.data(), fm, fa, home, grip ? float(robot.gripper.servo_open_deg) : 90.0f,
                                    grip ? float(robot.gripper.servo_closed_deg) : 90.0f, robot.name.c_str());
  switch (fit) {
    case kFitOk:
      break;
    case kFitOutOfRange:
      throw fail("a number beyond what the configuration carries (more than 10,000 steps per turn, a gear beyond "
           "1,000,000, or a servo angle outside 0 to 180 deg)");
    case kFitBadHome:
      throw fail("the home pose puts a motor outside its limits");
    default:
      throw fail("a motor the firmware cannot drive (steps, gear or limits)");
  }
  ConfiguredArm<kMaxConfigMotors> arm;
  if (config_read(arm, out.image.data()) != kConfigOk) throw fail("the configuration does not read back (a bug)");
  out.checksum = config_checksum(out.image.data());
  out.has_point = arm.has_point;
  out.name = arm.name;
  for (uint16_t s = 100; s <= 161; ++s) {
    ConfigField f;
    if (!config_field(s, f)) continue;
    const int32_t v = config_get(out.image.data(), s);
    out.lines.push_back(setting_line(s, f.whole ? v * 1000 : v));
  }
  out.lines.push_back("N " + out.name);
  out.lines.push_back(setting_line(kCommitSetting, int32_t(out.checksum) * 1000));
  return out;
}

ConfiguredArm<kMaxConfigMotors> configured_arm(const NanoConfig& config) {
  ConfiguredArm<kMaxConfigMotors> arm;
  config_read(arm, config.image.data());
  return arm;
}

}  // namespace articula::host
