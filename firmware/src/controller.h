// firmware/src/controller.h - the controller's state (controller.cpp: the firmware's entry
// points, firmware.h): the line being read and the one waiting, the plan, the planner's memory
// of the last move, a T's cut. Only controller.cpp touches it; state.h holds it.
#ifndef ARTICULA_FIRMWARE_CONTROLLER_H
#define ARTICULA_FIRMWARE_CONTROLLER_H

#include <articula/line.h>
#include <articula/protocol.h>

#include "robot.h"
#include "ram.h"

namespace controller {

// T's four numbers, P's three; M's one per motor (three on the Nano; eight in the host's build).
typedef articula::BasicCommand<(robot::kJoints > 4 ? robot::kJoints : 4)> Command;

struct Ram {
  // (The cut first: avr-gcc reaches a member through the Z pointer only within 64 bytes of its
  // object's start, stepper.h says.)
  articula::LineCutter<float, robot::kJoints> cut;  // T (articula/line.h): the segments of the line being queued
  bool cutting;                        // the pending T passed its check; `cut` holds what is left of it
  float cut_speed;                     //   its tool speed, mm/s
  bool has_pending;
  articula::LineEvent held;  // a complete line behind the pending one, still in `line`
  volatile bool homed;       // position known: moves allowed (read by status_line)
  bool stop_flushed;         // the queue and waiting lines of the current stop are dealt with
  bool was_busy;             // busy at the last pass
  uint32_t idle_since;       // millis() at the first pass at rest
  uint32_t last_steps;                 // the last move queued, for the planner's junction with the
  uint16_t last_cap;                   //   next: its dominant steps (0 after any other action), the
  int32_t last_delta[robot::kJoints];  //   highest level its cruise may be entered at, its steps
  robot::State planned;      // commanded angles and steps once the queue has run
  Command pending;
  articula::LineAssembler line;
};
ARTICULA_FIRMWARE_RAM(Ram, ram)


}  // namespace controller

#endif  // ARTICULA_FIRMWARE_CONTROLLER_H
