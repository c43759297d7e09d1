// firmware/src/firmware.h - the firmware's entry points, called by the HAL's main loop
// and interrupts (hal_avr.cpp / main.cpp on the Nano, firmware/sitl/ on the PC).
#ifndef ARTICULA_FIRMWARE_FIRMWARE_H
#define ARTICULA_FIRMWARE_FIRMWARE_H

#include <stdint.h>

#include "robot.h"

namespace firmware {

// Once, after hal::init() and before hal::start(): loads the settings from EEPROM, sets up
// the arm's state.
void setup();

// After a robot configuration is put in use (robot::use; `$199=` commits one): the coils,
// the step constants and the arm's position as at power-up.
void configured();

// One pass of the main loop: reads serial bytes, runs and answers commands, feeds the
// motion queue, sends requested status reports, releases idle coils. Never blocks for
// longer than a command's own computation.
void poll();

// From the step timer interrupt: puts out the step that is due and returns the ticks to the
// next one (0: nothing more; the timer stops until the firmware starts it again).
uint32_t on_step_timer();

// From the serial receive interrupt, for the realtime byte '!' (stop). ('?' is the HAL's:
// it calls status_line().)
void on_realtime(char c);

// The status report line for '?', LF included, into buf (cap bytes, at least
// articula::status_report_size(joints)); returns its length. Called by the HAL in interrupt
// context with interrupts enabled: the state is read in one short critical section.
uint8_t status_line(char* buf, uint8_t cap);

// The controller's plan, as the SITL machine reads it with each reply and queued action
// (hal::replied, hal::action_queued): the commanded angles and steps once the queue has run,
// and whether moves are allowed. (Only the SITL calls them: on the Nano the linker drops them.)
const robot::State& planned();
bool homed();

}  // namespace firmware

#endif  // ARTICULA_FIRMWARE_FIRMWARE_H
