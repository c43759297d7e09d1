// firmware/src/ram.h - where a module's state lives: ARTICULA_FIRMWARE_RAM(Type, name), inside the
// module's namespace, declares `name()`, the module's part of the firmware's state (state.h).
//   - On the Nano: one static object at a fixed address (g_<name>, defined in main.cpp), so
//     every access is a direct load or store, as a loose global's was.
//   - On the host (firmware/sitl): the part of the machine the calling thread runs now
//     (sitl::Machine::Use points g_<name> at it), so one program runs several firmwares.
#ifndef ARTICULA_FIRMWARE_RAM_H
#define ARTICULA_FIRMWARE_RAM_H

#if defined(__AVR__)
#define ARTICULA_FIRMWARE_RAM(Type, name) \
  extern Type g_##name;                   \
  inline Type& name() { return g_##name; }
#else
// (__thread, not thread_local: a pointer set by constant initialisation needs no wrapper call at
// each use; initial-exec: one load from the thread's block, in the Python module too.)
#if defined(__EMSCRIPTEN__)
#define ARTICULA_FIRMWARE_THREAD __thread
#else
#define ARTICULA_FIRMWARE_THREAD __thread __attribute__((tls_model("initial-exec")))
#endif
#define ARTICULA_FIRMWARE_RAM(Type, name)         \
  extern ARTICULA_FIRMWARE_THREAD Type* g_##name; \
  inline Type& name() { return *g_##name; }
#endif

#endif  // ARTICULA_FIRMWARE_RAM_H
