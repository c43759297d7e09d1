// firmware/src/gripper.cpp - servo pulse widths (the scale is the core's, articula/servo.h).
#include "gripper.h"

#include <articula/servo.h>

#include "robot_config.h"

namespace gripper {

uint16_t pulse_us(int32_t aperture) {
  return articula::servo_pulse_us<float>(ARTICULA_SERVO_CLOSED_DEG, ARTICULA_SERVO_OPEN_DEG, aperture);
}

}  // namespace gripper
