// firmware/src/coils.cpp - the coil sequences, or the STEP/DIR drivers' pulses and ENABLE, or the
// servos' pulse widths.
#include "coils.h"

#include <articula/drive.h>

#include "hal.h"
#include "robot.h"

namespace coils {

using articula::kCoilSequence;

namespace {
// The coils' state (coils.h), in the firmware's (state.h).
inline Ram& cs() { return ram(); }
inline Sequence& seq() { return sequence(); }
}  // namespace

void attach_servos(const int32_t* steps) {
  if (!robot::servos()) return;
  for (uint8_t i = 0; i < robot::count() && i < articula::kMaxConfigMotors; ++i)
    hal::attach_servo(i, robot::config().servo_pin[i],
                      uint16_t(robot::config().servo_zero_us[i] * articula::kServoTicksPerUs + (steps ? steps[i] : 0)));
}

void setup() {
  attach_servos(0);
  // (A build for pulsed drives only has no coil patterns: nothing reads the table's state.)
  const uint8_t four_wire = uint8_t((1u << articula::kDriveL298n) | (1u << articula::kDriveUln2003));
  if ((robot::kDrives & four_wire) == 0) {
    release();
    return;
  }
  seq().table = kCoilSequence[robot::config().drive == articula::kDriveUln2003 ? 1 : 0];
  for (uint8_t i = 0; i < robot::kJoints; ++i) {
    seq().phase[i] = 1;
    seq().stride[i] = robot::motor(i).microsteps == 2 ? 1 : 2;
  }
  release();
}

namespace {
// The motor's next place in kCoilSequence, taken.
inline uint8_t advance(uint8_t motor, bool negative) {
  const uint8_t p = uint8_t((seq().phase[motor] + (negative ? 8 - seq().stride[motor] : seq().stride[motor])) & 7);
  seq().phase[motor] = p;
  return p;
}
}  // namespace

// On STEP/DIR drivers a step is a pulse, and energising is the drivers' ENABLE; on servos a step
// is a tick of the pulse (the HAL's stage_pulse and pulse_step), and the servos hold whatever
// ENABLE says.
void step(uint8_t motor, bool negative) {
  if (robot::pulsed())
    hal::pulse_step(motor, negative);
  else
    hal::write_coils(motor, seq().table[advance(motor, negative)]);
}

void stage_step(uint8_t motor, bool negative) {
  if (robot::pulsed())
    hal::stage_pulse(motor, negative);
  else
    hal::stage_coils(motor, seq().table[advance(motor, negative)]);
}

void energise() {
  if (robot::pulsed())
    hal::enable_drivers(true);
  else
    for (uint8_t i = 0; i < robot::kJoints; ++i) hal::write_coils(i, seq().table[seq().phase[i]]);
  cs().on = true;
}

void release() {
  if (robot::pulsed())
    hal::enable_drivers(false);
  else
    for (uint8_t i = 0; i < robot::kJoints; ++i) hal::write_coils(i, 0);
  cs().on = false;
}

bool on() { return cs().on; }

uint8_t phase(uint8_t motor) { return seq().phase[motor]; }

}  // namespace coils
