// firmware/src/coils.h - the four inputs of each motor's driver: which pattern comes next.
//
// A table of the eight half-step states (IN1..IN4) for each 4-wire drive:
//   L298N, a bipolar motor (IN1/IN2 drive coil A's ends, IN3/IN4 coil B's):
//     1000, 1010, 0010, 0110, 0100, 0101, 0001, 1001
//   ULN2003, a unipolar motor (IN1..IN4 sink its four half-coils in turn, a 28BYJ-48's
//   blue, pink, yellow, orange):
//     1000, 1100, 0100, 0110, 0010, 0011, 0001, 1001
// The configuration's drive ($131) picks one. On STEP/DIR drivers (a CNC shield) the same
// calls make a STEP pulse with its DIR (hal::stage_pulse, pulse_step) and switch the drivers'
// ENABLE; the phase stays. On hobby servos (the servo build) they make the motor's pulse one
// tick longer or shorter (hal::attach_servo); the servos hold whatever ENABLE says.
// In every 4-wire table the full-step sequence (two phases on)
// is the odd states, so a motor in full steps moves two places a step and one in half steps one.
// Each motor keeps its own place in the table, apart from its step count: Z and homing
// change the count, never the coils.
#ifndef ARTICULA_FIRMWARE_COILS_H
#define ARTICULA_FIRMWARE_COILS_H

#include <stdint.h>

#include "robot.h"
#include "ram.h"

namespace coils {

// The coils' state (state.h holds it; only coils.cpp touches it): whether they are energised,
// and each motor's place in its 4-wire drive's sequence (a part of its own, which a build for
// pulsed drives only never touches: the Nano's linker then leaves it out).
struct Ram {
  bool on;
};
struct Sequence {
  const uint8_t* table;  // the configuration's drive's (setup())
  uint8_t phase[robot::kJoints];
  uint8_t stride[robot::kJoints];  // 2 in full steps, 1 in half steps
};
ARTICULA_FIRMWARE_RAM(Ram, ram)
ARTICULA_FIRMWARE_RAM(Sequence, sequence)


// The table is the core's articula::kCoilSequence (articula/drive.h): bit 0 is IN1 .. bit 3
// IN4, [0] the L298N's, [1] the ULN2003's.

// Takes the configuration's table, and places every motor on the first full-step state (1010
// or 1100) with its coils off; a servo arm's servos get their step-0 pulses (attach_servos), as
// every motor is at step 0 then.
void setup();

// A servo arm: each servo's pulse from its step-0 pulse and `steps` (null: step 0; power-up and a
// new configuration), or Z's home steps (Z declares the arm at home: a servo goes there at once).
void attach_servos(const int32_t* steps);

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

// The motor's place in kCoilSequence, 0..7 (for tests).
uint8_t phase(uint8_t motor);

}  // namespace coils

#endif  // ARTICULA_FIRMWARE_COILS_H
