// firmware/src/main.cpp - the Nano's entry point (AVR only; the native tests have their own).
//
// Our own main() rather than Arduino's setup()/loop(): nothing of an Arduino core is used (the
// CMake build links none; PlatformIO's framework builds one, and since nothing refers to it,
// none of it is linked: its main(), init(), millis() and HardwareSerial stay out of the ELF,
// and hal_avr.cpp's interrupt handlers are the only ones). The
// interrupt handlers that call the firmware (the step timer, the serial receive) live in
// hal_avr.cpp, next to the timer and USART state they use.
#if defined(__AVR__)

#include "firmware.h"
#include "hal.h"
#include "state.h"

// The firmware's state, each module's part at a fixed address (state.h). (= {}: constant
// initialisation, all zero in .bss; without it avr-gcc runs the members' constructors at start-up.)
#define ARTICULA_FIRMWARE_OBJECT(type, member, object) type object = {};
ARTICULA_FIRMWARE_PARTS(ARTICULA_FIRMWARE_OBJECT)
#undef ARTICULA_FIRMWARE_OBJECT

int main() {
  hal::init();        // interrupts on, the receiver too: no byte is lost from here
  firmware::setup();  // the arm's state, before any realtime byte acts on it
  hal::start();       // '?' and '!' act from here, those received meanwhile too
  for (;;) {
    firmware::poll();
    hal::idle();  // sleeps until an interrupt brings work (a byte, a step, the millis tick)
  }
}

#endif  // __AVR__
