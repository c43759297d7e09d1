// host/lib/firmware_machine.cpp - the firmware of the host library, powered up (firmware_machine.h).
#include "firmware_machine.h"

#include <string>

#include "blocks.h"

// The firmware (firmware/src, built for the host's eight motors: firmware/sitl/sitl.cmake).
#include "hal_sitl.h"
#include "machine.h"

namespace articula::host {

static_assert(kFirmwareMotors == robot::kJoints, "the host's build of the firmware (host/CMakeLists.txt)");

ConfiguredArm<kFirmwareMotors> machine_arm(const Robot& robot) {
  if (!robot.has_motors)
    throw PredictError(robot.name + " has no motors (" + robot.source +
                       "): a prediction needs motor steps; only the kinematic model can run its programs");
  try {
    return firmware_arm(robot);
  } catch (const NanoConfigError& e) {
    throw PredictError(e.what());
  }
}

void power_up(const Robot& robot, const ConfiguredArm<kFirmwareMotors>& arm, const ControllerSettings& settings) {
  sitl::boot(true, "", nullptr, &arm);
  const ControllerSettings defaults;
  bool changed = false;
  for (int n = 0; n < ControllerSettings::kCount; ++n) {
    if (settings.value[size_t(n)] == defaults.value[size_t(n)]) continue;
    const std::string reply = sitl::command(protocol_line(robot, '$', {double(n), double(settings.value[size_t(n)])}));
    if (reply != "ok") throw PredictError("the firmware refused setting $" + std::to_string(n) + " = " +
                                          std::to_string(settings.value[size_t(n)]) + ": " + reply);
    changed = true;
  }
  if (changed) sitl::boot(false, "", nullptr, &arm);
  sitl::take_lines();
  for (int i = 0; i < robot.actuation.num_motors; ++i) {
    const MotorSpec& m = robot.actuation.motors[i];
    const int32_t at = quantize_within_limits(m, m.min);
    sitl::hw().endstop_fitted[i] = true;
    sitl::hw().endstop_at[i] = at;
    sitl::hw().endstop_below[i] = at <= quantize_within_limits(m, m.max);
  }
}

}  // namespace articula::host
