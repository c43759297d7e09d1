// firmware/src/state.h - the firmware's state: every module's RAM in one object (GRBL's habit,
// its `sys` and `st`), so that one program can hold several firmwares.
//
// Each module keeps its part in a struct of its own (stepper::Ram, queue::Ram, ...: declared in
// its header, used only by its .cpp), and firmware::State gathers them. state() is the one the
// code runs on:
//   - on the Nano, one static object at a fixed address (g_state): every access is a direct load
//     or store, as the loose globals were, and nothing is initialised but by setup() (all of it
//     in .bss: no flash for a copy of it);
//   - on the host (firmware/sitl), each sitl::Machine has its own, and state() is the one the
//     calling thread runs now (sitl::Machine::Use sets it): several machines, in one thread by
//     turns or each in a thread of its own.
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

#if !defined(__AVR__)
// (__thread, not thread_local: a pointer set only by constant initialisation needs no wrapper
// call at each use. initial-exec: one load from the thread's block, in the Python module too.)
#if defined(__EMSCRIPTEN__)
extern __thread State* g_state;
#else
extern __thread State* g_state __attribute__((tls_model("initial-exec")));
#endif
#endif

// Each module's part: on the host the one in the machine's State; on the Nano an object of its
// own at a fixed address (main.cpp), which avr-gcc addresses as tightly as the loose globals
// were (a member of one large object costs it 420-530 B more flash: a struct's copy or clear
// at an offset goes byte by byte through 4-byte direct stores, where at an object's start it
// goes through the Z pointer in 2-byte ones).
#if defined(__AVR__)
#define ARTICULA_FIRMWARE_PART(type, name, accessor) \
  extern type g_##name;                              \
  inline type& accessor() { return g_##name; }
#else
#define ARTICULA_FIRMWARE_PART(type, name, accessor) \
  inline type& accessor() { return g_state->name; }
#endif
ARTICULA_FIRMWARE_PART(robot::Ram, robot, robot_ram)
ARTICULA_FIRMWARE_PART(settings::Ram, settings, settings_ram)
ARTICULA_FIRMWARE_PART(queue::Ram, queue, queue_ram)
ARTICULA_FIRMWARE_PART(coils::Ram, coils, coils_ram)
ARTICULA_FIRMWARE_PART(coils::Sequence, coil_sequence, coil_sequence)
ARTICULA_FIRMWARE_PART(stepper::Ram, stepper, stepper_ram)
ARTICULA_FIRMWARE_PART(controller::Ram, controller, controller_ram)
#undef ARTICULA_FIRMWARE_PART

}  // namespace firmware

// The accessors the modules' headers declare, for the state above.
namespace robot {
inline articula::ConfiguredArm<kJoints>& config() { return firmware::robot_ram().config; }
inline uint16_t checksum() { return firmware::robot_ram().checksum; }
inline const int32_t* home_steps() { return firmware::robot_ram().home_steps; }
}  // namespace robot

namespace settings {
inline uint32_t* value() { return firmware::settings_ram().value; }
}  // namespace settings

#endif  // ARTICULA_FIRMWARE_STATE_H
