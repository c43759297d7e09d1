// hil/vnano/servo.h - the gripper's servo read back from the pulse the firmware sends: the
// inverse of firmware/src/gripper.h, one home for the harness's virtual Nano (vnano.cpp) and
// the page's (the web engine: servoAngleDeg, servoAperturePercent).
#ifndef ARTICULA_HIL_VNANO_SERVO_H
#define ARTICULA_HIL_VNANO_SERVO_H

#include "../../firmware/src/gripper.h"

namespace vnano {

// The servo angle a pulse width asks for, by the Arduino Servo library's scale (544 us at 0
// degrees, 2400 at 180) that the firmware uses.
inline double servo_angle_deg(double width_us) {
  return (width_us - gripper::kPulseAt0) * 180.0 / double(gripper::kPulseAt180 - gripper::kPulseAt0);
}

// The gripper's aperture, 0 % at the robot file's servo_closed to 100 % at servo_open.
inline double servo_aperture_percent(double angle_deg, double closed_deg, double open_deg) {
  return (angle_deg - closed_deg) * 100.0 / (open_deg - closed_deg);
}

}  // namespace vnano

#endif  // ARTICULA_HIL_VNANO_SERVO_H
