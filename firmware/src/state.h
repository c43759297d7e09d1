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

// Every part, once: X(type, member of State, the accessor's object or pointer (ram.h)). State,
// the Nano's objects (main.cpp) and the SITL's pointers (sitl/machine.cpp) are all made from it.
#define ARTICULA_FIRMWARE_PARTS(X)                          \
  X(robot::Ram, robot, robot::g_ram)                        \
  X(settings::Ram, settings, settings::g_ram)               \
  X(queue::Ram, queue, queue::g_ram)                        \
  X(coils::Ram, coils, coils::g_ram)                        \
  X(coils::Sequence, coil_sequence, coils::g_sequence)      \
  X(stepper::Ram, stepper, stepper::g_ram)                  \
  X(controller::Ram, controller, controller::g_ram)

namespace firmware {

struct State {
#define ARTICULA_FIRMWARE_MEMBER(type, member, object) type member;
  ARTICULA_FIRMWARE_PARTS(ARTICULA_FIRMWARE_MEMBER)
#undef ARTICULA_FIRMWARE_MEMBER
};

}  // namespace firmware

#endif  // ARTICULA_FIRMWARE_STATE_H
