// firmware/src/coils.cpp - the coil sequences, or the STEP/DIR drivers' pulses and ENABLE, or the
// servos' pulse widths.
#include "coils.h"

#include <articula/drive.h>

#include "hal.h"
#include "robot.h"

namespace coils {

using articula::kCoilSequence;

namespace {
const uint8_t* g_table = kCoilSequence[0];  // the configuration's drive's
uint8_t g_phase[robot::kJoints];
uint8_t g_stride[robot::kJoints];  // 2 in full steps, 1 in half steps
bool g_on;
}  // namespace

void attach_servos(const int32_t* steps) {
  if (!robot::servos()) return;
  for (uint8_t i = 0; i < robot::count() && i < articula::kMaxConfigMotors; ++i)
    hal::attach_servo(i, robot::config.servo_pin[i],
                      uint16_t(robot::config.servo_zero_us[i] * articula::kServoTicksPerUs + (steps ? steps[i] : 0)));
}

void setup() {
  attach_servos(0);
  g_table = kCoilSequence[robot::config.drive == articula::kDriveUln2003 ? 1 : 0];
  for (uint8_t i = 0; i < robot::kJoints; ++i) {
    g_phase[i] = 1;
    g_stride[i] = robot::motor(i).microsteps == 2 ? 1 : 2;
  }
  release();
}

namespace {
// The motor's next place in kCoilSequence, taken.
inline uint8_t advance(uint8_t motor, bool negative) {
  const uint8_t p = uint8_t((g_phase[motor] + (negative ? 8 - g_stride[motor] : g_stride[motor])) & 7);
  g_phase[motor] = p;
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
    hal::write_coils(motor, g_table[advance(motor, negative)]);
}

void stage_step(uint8_t motor, bool negative) {
  if (robot::pulsed())
    hal::stage_pulse(motor, negative);
  else
    hal::stage_coils(motor, g_table[advance(motor, negative)]);
}

void energise() {
  if (robot::pulsed())
    hal::enable_drivers(true);
  else
    for (uint8_t i = 0; i < robot::kJoints; ++i) hal::write_coils(i, g_table[g_phase[i]]);
  g_on = true;
}

void release() {
  if (robot::pulsed())
    hal::enable_drivers(false);
  else
    for (uint8_t i = 0; i < robot::kJoints; ++i) hal::write_coils(i, 0);
  g_on = false;
}

bool on() { return g_on; }

uint8_t phase(uint8_t motor) { return g_phase[motor]; }

}  // namespace coils
