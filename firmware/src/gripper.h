// firmware/src/gripper.h - the gripper servo: aperture to pulse width.
#ifndef ARTICULA_FIRMWARE_GRIPPER_H
#define ARTICULA_FIRMWARE_GRIPPER_H

#include <stdint.h>

namespace gripper {

// The Arduino Servo library's convention: 544 us at 0 degrees, 2400 us at 180.
static const uint16_t kPulseAt0 = 544;
static const uint16_t kPulseAt180 = 2400;

// The servo angle is linear in the aperture, from the robot file's servo_closed (0 %) to
// servo_open (100 %), limited to 0..180 degrees; the pulse width is that angle's, rounded
// to the nearest microsecond. aperture in thousandths of a percent, 0 to 100000.
uint16_t pulse_us(int32_t aperture);

}  // namespace gripper

#endif  // ARTICULA_FIRMWARE_GRIPPER_H
