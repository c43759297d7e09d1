// firmware/src/gripper.cpp - servo pulse widths (the scale is the core's, articula/servo.h).
#include "gripper.h"

#include <articula/servo.h>

#include "robot.h"

namespace gripper {

uint16_t pulse_us(int32_t aperture) {
  return articula::servo_pulse_us<float>(robot::config().servo_closed_deg, robot::config().servo_open_deg, aperture);
}

}  // namespace gripper
