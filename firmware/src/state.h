// firmware/src/state.h - the firmware's state: every module's RAM (GRBL's habit, its `sys` and
// `st`), gathered so that one program can hold several firmwares.
//
// Each module keeps its part in a struct of its own (stepper::Ram, queue::Ram, controller::Ram
// in controller.h, ...: declared in its header, touched only by its .cpp) and reaches it through
// the accessor ram.h declares (stepper::ram()):
//   - on the Nano, each part is a static object at a fixed address (main.cpp defines them): every
//     access is a direct load or store, as the loose globals were, and all of it is zero in .bss
//     with no constructor run at start-up. (One object for every part cost 420-530 B more flash:
//     avr-gcc reaches a member through the Z pointer only within 64 bytes of its object's start,
//     beyond that each byte of a copy or a clear takes a 4-byte direct store. So the parts stay
//     apart, and their large members come first.)
//   - on the host (firmware/sitl), a State is one machine's (sitl::Machine), and its Use points
//     every part's accessor of the calling thread at it.
#ifndef ARTICULA_FIRMWARE_STATE_H
#define ARTICULA_FIRMWARE_STATE_H

#include "controller.h"
#include "coils.h"
#include "queue.h"
#include "robot.h"
#include "settings.h"
#include "stepper.h"

namespace firmware {

struct State {
  robot::Ram robot;
  settings::Ram settings;
  queue::Ram queue;
  coils::Ram coils;
  coils::Sequence coil_sequence;
  stepper::Ram stepper;
  controller::Ram controller;
};

}  // namespace firmware

#endif  // ARTICULA_FIRMWARE_STATE_H
