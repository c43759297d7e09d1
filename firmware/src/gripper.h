// firmware/src/gripper.h - the gripper servo: aperture to pulse width.
#ifndef ARTICULA_FIRMWARE_GRIPPER_H
#define ARTICULA_FIRMWARE_GRIPPER_H

#include <stdint.h>

namespace gripper {

// The pulse width for an aperture in thousandths of a percent (0 to 100000), by the robot's
// servo_closed and servo_open angles: articula/servo.h's servo_pulse_us in float.
uint16_t pulse_us(int32_t aperture);

}  // namespace gripper

#endif  // ARTICULA_FIRMWARE_GRIPPER_H
