// firmware/src/gripper.cpp - servo pulse widths.
#include "gripper.h"

#include <articula/platform.h>

#include "robot_config.h"

namespace gripper {

uint16_t pulse_us(int32_t aperture) {
  const float closed = ARTICULA_SERVO_CLOSED_DEG, open = ARTICULA_SERVO_OPEN_DEG;
  float deg = closed + (open - closed) * (float(aperture) / 100000.0f);
  deg = articula::clamp(deg, 0.0f, 180.0f);
  return uint16_t(float(kPulseAt0) + deg * (float(kPulseAt180 - kPulseAt0) / 180.0f) + 0.5f);
}

}  // namespace gripper
