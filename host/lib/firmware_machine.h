// host/lib/firmware_machine.h - the firmware of the host library (firmware/src, its eight-motor
// build on the virtual clock: firmware/sitl), powered up for a robot. Each prediction
// (predict_run.cpp) and each live session (firmware_session.cpp) has a machine of its own
// (sitl::Machine), made the thread's while it runs: any number side by side, in any threads.
// (Inside the host library only: its headers are the firmware's.)
#ifndef ARTICULA_HOST_FIRMWARE_MACHINE_H
#define ARTICULA_HOST_FIRMWARE_MACHINE_H

#include "nano_config.h"
#include "predict.h"

namespace articula::host {

// The arm the firmware is put in use with (firmware_arm); PredictError for a robot without
// motors or one it cannot drive.
ConfiguredArm<kFirmwareMotors> machine_arm(const Robot& robot);

// Power-up with the robot's arm and the settings: the settings written as `$n=v` lines, then
// a power cycle (as a Nano set up so and switched on). A switch on every motor, pressed from
// its minimum angle on (H seeks the switches $3 names). The thread's machine (sitl::Machine::Use).
void power_up(const Robot& robot, const ConfiguredArm<kFirmwareMotors>& arm, const ControllerSettings& settings);

}  // namespace articula::host

#endif  // ARTICULA_HOST_FIRMWARE_MACHINE_H
