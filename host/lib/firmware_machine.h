// host/lib/firmware_machine.h - the one firmware of the host library (firmware/src, its
// eight-motor build on the virtual clock: firmware/sitl) and who holds it. Its state is
// global, as on the Nano: one machine per process. A prediction (predict_run.cpp) and a live
// session (firmware_session.cpp) take it under its lock; a session that finds it held by
// another since its last turn powers it up again and replays its own lines.
// (Inside the host library only: its headers are the firmware's.)
#ifndef ARTICULA_HOST_FIRMWARE_MACHINE_H
#define ARTICULA_HOST_FIRMWARE_MACHINE_H

#include <mutex>

#include "nano_config.h"
#include "predict.h"

namespace articula::host {

// Held while the machine runs.
std::mutex& firmware_lock();
// The session whose run the machine holds: null after a prediction (or before any run).
const void*& firmware_owner();

// The arm the firmware is put in use with (firmware_arm); PredictError for a robot without
// motors or one it cannot drive.
ConfiguredArm<kFirmwareMotors> machine_arm(const Robot& robot);

// Power-up with the robot's arm and the settings: the settings written as `$n=v` lines, then
// a power cycle (as a Nano set up so and switched on). A switch on every motor, pressed from
// its minimum angle on (H seeks the switches $3 names). Under the lock.
void power_up(const Robot& robot, const ConfiguredArm<kFirmwareMotors>& arm, const ControllerSettings& settings);

}  // namespace articula::host

#endif  // ARTICULA_HOST_FIRMWARE_MACHINE_H
