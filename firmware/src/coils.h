// firmware/src/coils.h - the four L298N inputs of each motor: which pattern comes next.
//
// One table of the eight half-step states (IN1..IN4): 1000, 1010, 0010, 0110, 0100, 0101,
// 0001, 1001. The full-step sequence (two phases on: 1010, 0110, 0101, 1001) is its odd
// states, so a motor in full steps moves two places a step and one in half steps one.
// Each motor keeps its own place in the table, apart from its step count: Z and homing
// change the count, never the coils.
#ifndef ARTICULA_FIRMWARE_COILS_H
#define ARTICULA_FIRMWARE_COILS_H

#include <stdint.h>

namespace coils {

// Bit 0 is IN1 .. bit 3 IN4.
extern const uint8_t kSequence[8];

// Places every motor on the first full-step state (1010) with its coils off.
void setup();

// One step of `motor` towards more (negative false) or fewer steps: the next pattern,
// written at once. From the step interrupt.
void step(uint8_t motor, bool negative);
// The same step, staged for the next step-timer deadline (hal::stage_coils). The motor's
// place in the sequence moves on now.
void stage_step(uint8_t motor, bool negative);

// Writes every motor's current pattern (before a move), or 0 to every motor (at rest).
void energise();
void release();
bool on();

// The motor's place in kSequence, 0..7 (for tests).
uint8_t phase(uint8_t motor);

}  // namespace coils

#endif  // ARTICULA_FIRMWARE_COILS_H
