// firmware/src/hal.h - the firmware's only window on the hardware.
//
// Two implementations: hal_avr.cpp (the Nano: direct port writes, Timer1, the USART,
// EEPROM) and sitl/hal_sitl.cpp (the firmware on the PC, on a virtual clock: records every
// coil write and servo pulse with its tick). Nothing else in the firmware includes an AVR header, so all the logic
// runs and is tested on the host (the GRBL layout, without GRBL's <avr/io.h> everywhere).
#ifndef ARTICULA_FIRMWARE_HAL_H
#define ARTICULA_FIRMWARE_HAL_H

#include <stdint.h>

#include <articula/motion.h>
#include <articula/platform.h>

namespace queue {
struct Action;
}

namespace hal {

// Timer ticks per second of the step timer (Timer1 at 16 MHz with prescaler 8): the core's.
static const uint32_t kTickHz = articula::kStepTickHz;

// Ports, timers (the millisecond tick too), EEPROM and the USART, the receiver included:
// bytes that arrive from here on are kept. The realtime bytes among them wait for start().
// Interrupts are enabled on return.
void init();
// After firmware::setup(): the realtime bytes act from now on ('?' and '!' received since
// init() are acted on now, once each), so none is lost at start-up.
void start();

// The four L298N inputs of one motor, written together (one port write on the Nano).
// Bit 0 is IN1 .. bit 3 IN4; 0 switches the coils off.
void write_coils(uint8_t motor, uint8_t pattern);

// The gripper servo's pulse width in microseconds, repeated every 20 ms; 0 stops pulsing.
void set_servo_pulse(uint16_t microseconds);

// True while the endstop switch of `motor` is pressed (always false where none is wired).
bool endstop(uint8_t motor);

// Digital I/O on the header's pins (board.h's kHeaderPin index: D0..D13, A0..A5), for
// protocol.h's O and W; the controller passes only pins its drive leaves free. io_inputs()
// makes the pins `pins` (bit n pin n) inputs with their pull-ups (each reads 1 with nothing on
// it): every pin the configuration keeps not, whenever one is put in use. io_write() makes the
// pin an output at `high` (it stays one until then); io_read() reads a pin (an output reads its
// own level); io_levels() reads every pin at once, bit n pin n.
void io_inputs(uint32_t pins);
void io_write(uint8_t pin, bool high);
bool io_read(uint8_t pin);
uint32_t io_levels();

// The step timer. After start_step_timer(t) the HAL calls firmware::on_step_timer() t ticks
// later, and then again after each interval that call returns, measured from the previous
// deadline (not from when the call finished), so intervals do not accumulate the call's
// own time; a return of 0 stops the timer. Intervals may exceed 16 bits.
void start_step_timer(uint32_t first_ticks);
void stop_step_timer();  // also drops what stage_coils() left
bool step_timer_running();

// A coil pattern for the next step-timer deadline: written first thing at that deadline,
// before on_step_timer() is called, together with every other motor staged for it (on the
// Nano, one port write each, a few cycles apart and a fixed time after the deadline, however
// long the step computation takes). From on_step_timer(), or before start_step_timer().
void stage_coils(uint8_t motor, uint8_t pattern);

// STEP/DIR drivers (a CNC shield's sockets; the build for one, and the SITL). DIR high turns a
// motor towards more steps. stage_pulse() sets the motor's DIR at once (so it holds for the
// whole interval before the deadline, far beyond any driver's setup time) and a STEP pulse
// for the next step-timer deadline, raised with every other motor staged for it (one port
// write), held kStepPulseNs, and lowered. pulse_step() does the same at once (DIR, its setup
// time, the pulse). From the same places as stage_coils() and write_coils().
static const uint16_t kStepPulseNs = 2000;  // >= every chip's step_high_ns (drive.h): DRV8825 1.9 us
static const uint16_t kDirSetupNs = 1000;   // pulse_step(): >= every chip's dir_setup_ns (DRV8825 650 ns)
void stage_pulse(uint8_t motor, bool negative);
void pulse_step(uint8_t motor, bool negative);
// Every driver's ENABLE (the shields' EN, D8, low active): on before a move, off after the
// idle time, as the 4-wire drives' coils are energised and released.
void enable_drivers(bool on);

// Servo arms (the build for them, and the SITL): a motor is a hobby servo on header pin `pin`
// (board.h's kHeaderPin index), given a pulse of `ticks` (Timer1's 0.5 us) every 20 ms from now
// on, one servo after another within the period (the gripper's last). There a step is one tick:
// stage_pulse() makes the motor's pulse one tick longer (or shorter, `negative`) at the next
// step-timer deadline, pulse_step() at once; the width is taken at the start of each pulse, so
// a change never cuts one short. enable_drivers() changes nothing: a servo holds its angle only
// while it gets pulses, so they never stop.
void attach_servo(uint8_t motor, uint8_t pin, uint16_t ticks);

// The step interrupt (or the main loop starting it) took an action of `kind` (queue::Kind)
// off the queue and began it. Nothing on the Nano (no code at all); the SITL machine stamps
// it with its tick, so the host reads when each queued action began from the firmware itself.
#if defined(__AVR__)
inline void action_began(uint8_t) {}
#else
void action_began(uint8_t kind);
#endif

// The main loop put `a` into the motion queue (controller.cpp push_planned, before the
// controller's plan moves on to it), and answered a line with `status` (reply(), after the
// command ran). Nothing on the Nano; the SITL machine records each with the controller's
// plan (firmware::planned()), so the host reads what every line did from the firmware itself.
#if defined(__AVR__)
inline void action_queued(const queue::Action&) {}
inline void replied(uint8_t) {}
#else
void action_queued(const queue::Action& a);
void replied(uint8_t status);
#endif

// Milliseconds since init (wraps after 49 days).
uint32_t millis();

// Serial, 115200 8N1. The receive interrupt acts on the realtime bytes at once and queues
// every other byte for serial_read():
//   '!'  firmware::on_realtime('!');
//   '?'  the status report: the HAL has firmware::status_line() write it into a buffer of
//        its own, from the receive interrupt with interrupts enabled again (the step timer
//        and the servo preempt it; the receive interrupt itself may come again and only
//        queues bytes), and sends it from the next line boundary of the output on (while
//        it is still being written, if need be), ahead of the lines serial_write() has
//        queued and never inside one. A '?' while a report waits or is being built is
//        answered by that report; one while a report is going out gets one more after it.
int16_t serial_read();     // the next received byte, or -1 when none is waiting
void serial_write(char c);  // main loop only (interrupts enabled); blocks while the buffer is full

// EEPROM (1,024 bytes on the ATmega328P).
void eeprom_read(uint16_t address, void* data, uint16_t size);
void eeprom_write(uint16_t address, const void* data, uint16_t size);  // writes only changed bytes

// Constants kept in flash only (the AVR copies ordinary constants into RAM at start-up):
// declared ARTICULA_IN_FLASH (articula/platform.h) and read with flash_read().
void flash_read(void* data, const void* flash, uint16_t size);

// Nothing to do until an interrupt says otherwise: the CPU sleeps (idle mode: the timers, the
// USART and the servo run on) until the next interrupt, the millis tick at the latest (1 ms),
// unless a received byte already waits. Race-free: interrupts off, the check, then SEI right
// before SLEEP (the instruction after SEI runs before any interrupt is served, so one that came
// meanwhile wakes the sleep at once). Called by the main loop after each poll.
void idle();

// Critical sections around data shared with the interrupts.
uint8_t interrupts_off();          // returns the previous state
void interrupts_restore(uint8_t);  // puts it back

}  // namespace hal

#endif  // ARTICULA_FIRMWARE_HAL_H
