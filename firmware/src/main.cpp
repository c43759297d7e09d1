// firmware/src/main.cpp - the Nano's entry point (AVR only; the native tests have their own).
//
// Our own main() rather than Arduino's setup()/loop(): the Arduino core's main.cpp is then
// never taken from the core's archive (main is already defined), nor is the serialEventRun()
// check it makes after every loop(), and nothing refers to HardwareSerial, so its USART
// interrupt handlers stay out of the ELF and hal_avr.cpp's own are the only ones. The
// interrupt handlers that call the firmware (the step timer, the serial receive) live in
// hal_avr.cpp, next to the timer and USART state they use.
#if defined(__AVR__)

#include "firmware.h"
#include "hal.h"

// From the Arduino core (wiring.c): starts Timer0 for millis(), sets up the ADC, enables
// interrupts.
extern "C" void init(void);

int main() {
  init();
  hal::init();        // the receiver is on from here: no byte is lost
  firmware::setup();  // the arm's state, before any realtime byte acts on it
  hal::start();       // '?' and '!' act from here, those received meanwhile too
  for (;;) {
    firmware::poll();
    hal::idle();  // sleeps until an interrupt brings work (a byte, a step, the millis tick)
  }
}

#endif  // __AVR__
