// firmware/src/stepper.h - runs the motion queue from the step timer's interrupt.
//
// One action at a time: a move (LineStepper spreads the steps of every motor over the
// dominant motor's steps, a StepProfile times those), a gripper pulse and its pause, or
// homing (seek each switch at the homing rate, then a move). When an action ends the
// interrupt starts the next one from the queue at once, so queued moves follow each other
// without a gap: each starts from rest where the last one ended.
//
// A move's coils are staged: each call of the interrupt works out the next step (which
// motors, their patterns: hal::stage_coils) after booking the one the HAL has just written
// at the deadline, so every motor's pins change together at a fixed time after the deadline
// and the step computation never delays them. A homing search writes its step at the
// deadline, right after checking the switch (a staged step would come before the rotor has
// settled on the previous one). Positions count the steps on the coils.
//
// Shared with the main loop and the status report: positions (read with interrupts off),
// the running, stop and fault flags.
// Everything the interrupt needs that takes real arithmetic (the profile constants, the
// homing interval, the switch search range) is computed by update_constants() in the main
// loop while the arm is at rest.
#ifndef ARTICULA_FIRMWARE_STEPPER_H
#define ARTICULA_FIRMWARE_STEPPER_H

#include <articula/motion.h>

#include "robot.h"
#include "ram.h"

namespace stepper {

// The step interrupt's state (state.h holds it; only stepper.cpp touches it).
// (The profile and the line first: avr-gcc reaches a member's bytes through the Z pointer, two
// bytes an access, only within 64 of its object's start; beyond, each takes a 4-byte direct
// store, which a profile's clear in halt() would pay 30 times over.)
struct Ram {
  articula::StepProfile profile;
  articula::LineStepper<robot::kJoints> line;
  volatile uint8_t running;  // set by the main loop (kick), cleared by the interrupt
  volatile uint8_t stop;     // '!' until the main loop has handled it at rest
  volatile uint8_t fault;    // a Fault: homing failed or stopped, or an input's wait ran out
  volatile uint8_t mode;     // stepper.cpp's Mode
  volatile uint8_t homing;
  uint8_t gripper;

  int32_t pos[robot::kJoints];

  // The step staged for the next deadline (hal::stage_coils): the HAL writes its coils first
  // thing at that deadline, on_timer() then books it.
  uint8_t next_mask;      // motors that step
  uint8_t next_negative;  // of those, the ones stepping towards fewer steps

  // From update_constants().
  articula::MotionSettings motion;
  articula::ProfileConstants constants;
  uint32_t homing_ticks;
  uint32_t seek_range[robot::kJoints];  // steps to search for a switch before giving up

  // An input's wait (W): its pin and level, and the milliseconds left.
  uint8_t wait_pin, wait_level;
  uint32_t wait_left;

  // Homing.
  uint8_t seek_mask;  // switch motors not yet found
  uint8_t seek_motor;
  uint32_t seek_left;
  int32_t home_target[robot::kJoints];
};
ARTICULA_FIRMWARE_RAM(Ram, ram)


// Positions 0, nothing running, constants from the settings.
void setup();
// After a settings change (only while nothing runs).
void update_constants();
// The constants a move's StepProfile starts from (the host's prediction uses the same).
const articula::MotionSettings& motion_settings();
// What every move's profile starts from (update_constants()).
const articula::ProfileConstants& constants();

// From the main loop: starts the queue when nothing runs (with interrupts enabled: the
// timer is stopped, so only starting it is a critical section).
void kick();
// An action is under way (the timer runs).
bool busy();
// The planner (main loop, after queue::replan()): the move under way may end at the entry
// planned for the move queued behind it; refused once the move's profile depends on its
// exit (StepProfile::raise_exit), and for homing or a stop.
void raise_exit();
// A Home action (seek or its final move) is under way.
bool homing();

// Motor positions in steps, as stepped.
void read_positions(int32_t* steps);
// Sets them without moving (Z); only while nothing runs.
void set_positions(const int32_t* steps);

// '!': from the receive interrupt. The step interrupt decelerates the move under way
// (StepProfile::stop) and starts nothing more; a homing search or a gripper pause ends at
// once. The main loop empties the queue, and once nothing runs, clear_stop().
void request_stop();
bool stop_requested();
void clear_stop();
// Ends a gripper pause or an input's wait at once (main loop, after a stop request).
void cut_pause();

// Why the interrupt stopped and started nothing more: homing failed (a switch not found within
// twice the motor's range) or was stopped, or an input did not read its level in time (W).
// take_fault() returns it once, then kNoFault.
enum Fault : uint8_t { kNoFault, kHomingFailed, kInputTimedOut };
uint8_t take_fault();

// The gripper aperture of the last gripper action started, whole percent.
uint8_t gripper_percent();

// The step interrupt's work (firmware::on_step_timer).
uint32_t on_timer();

}  // namespace stepper

#endif  // ARTICULA_FIRMWARE_STEPPER_H
