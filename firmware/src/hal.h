// firmware/src/hal.h - the firmware's only window on the hardware.
//
// Two implementations: hal_avr.cpp (the Nano: direct port writes, Timer1, the USART,
// EEPROM) and test/fake_hal.cpp (native tests: records every coil write and servo pulse
// with its time). Nothing else in the firmware includes an AVR header, so all the logic
// runs and is tested on the host (the GRBL layout, without GRBL's <avr/io.h> everywhere).
#ifndef ARTICULA_FIRMWARE_HAL_H
#define ARTICULA_FIRMWARE_HAL_H

#include <stdint.h>

namespace hal {

// Timer ticks per second of the step timer (Timer1 at 16 MHz with prescaler 8).
static const uint32_t kTickHz = 2000000UL;

void init();

// The four L298N inputs of one motor, written together (one port write on the Nano).
// Bit 0 is IN1 .. bit 3 IN4; 0 switches the coils off.
void write_coils(uint8_t motor, uint8_t pattern);

// The gripper servo's pulse width in microseconds, repeated every 20 ms; 0 stops pulsing.
void set_servo_pulse(uint16_t microseconds);

// True while the endstop switch of `motor` is pressed (always false where none is wired).
bool endstop(uint8_t motor);

// The step timer. After start_step_timer(t) the HAL calls firmware::on_step_timer() t ticks
// later, and then again after each interval that call returns, measured from the previous
// deadline (not from when the call finished), so intervals do not accumulate the call's
// own time; a return of 0 stops the timer. Intervals may exceed 16 bits.
void start_step_timer(uint32_t first_ticks);
void stop_step_timer();
bool step_timer_running();

// Milliseconds since init (wraps after 49 days).
uint32_t millis();

// Serial, 115200 8N1. The receive interrupt hands the realtime bytes ('?', '!') to
// firmware::on_realtime() at once and queues every other byte for serial_read().
int16_t serial_read();     // the next received byte, or -1 when none is waiting
void serial_write(char c);  // blocks while the transmit buffer is full

// EEPROM (1,024 bytes on the ATmega328P).
void eeprom_read(uint16_t address, void* data, uint16_t size);
void eeprom_write(uint16_t address, const void* data, uint16_t size);  // writes only changed bytes

// Critical sections around data shared with the interrupts.
uint8_t interrupts_off();          // returns the previous state
void interrupts_restore(uint8_t);  // puts it back

}  // namespace hal

#endif  // ARTICULA_FIRMWARE_HAL_H
