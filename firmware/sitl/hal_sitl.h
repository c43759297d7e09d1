// firmware/sitl/hal_sitl.h - hal.h on the host, on a virtual clock: the hardware the firmware
// runs on in software in the loop (machine.h runs its main loop and interrupts; the native
// tests run the firmware's own controller on it).
//
// A virtual clock in step-timer ticks (2 MHz), advanced by the machine; every coil write
// and servo pulse change recorded with its time; serial in and out buffers; a 1 KB EEPROM
// image; endstops that press at a given step. The coil patterns are decoded back into step
// counts here, independently of the firmware, so tests see what the motors would do.
//
// The serial line works as the Nano's HAL does (hal_avr.cpp), with a transmitter that takes
// no time: receive() is the receive interrupt ('?' builds the status report at once with
// firmware::status_line(), '!' goes to firmware::on_realtime(), both only after
// hal::start()); the report goes out at the next line boundary of what serial_write() sent,
// never inside a line. Interrupts can come in the middle of the firmware's work: every HAL
// call made with interrupts enabled, outside the step timer's call and the report's build,
// first calls `interrupt_point` (a test sets it to deliver bytes mid-command).
//
// The firmware's .cpp files compile unchanged against it (hal.h is their only window).
#ifndef ARTICULA_FIRMWARE_SITL_HAL_SITL_H
#define ARTICULA_FIRMWARE_SITL_HAL_SITL_H

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include <articula/settings.h>

#include "coil_decoder.h"  // (virtual-nano/: the SITL reads the coils as the virtual Nanos do)
#include "report.h"
#include "../src/robot.h"  // (by its path: the host library has a robot.h of its own)
#include "../src/ram.h"

namespace sitl {

static const int kMotors = robot::kJoints;  // the most this build of the firmware drives

// A STEP/DIR driver's inputs in the coil log, as a motor's "pattern": kEnabled while ENABLE is
// active (0 when the drivers are off, as released coils), kDirHigh while DIR is high, and
// kStepPulse on a STEP pulse (the entry with the decoded step).
static const uint8_t kStepPulse = 0x10, kDirHigh = 0x20, kEnabled = 0x40;

struct CoilWrite {
  uint64_t tick;
  uint8_t motor;
  uint8_t pattern;  // bit 0 IN1 .. bit 3 IN4; or a STEP/DIR driver's (kEnabled, kDirHigh, kStepPulse)
  int8_t step;      // decoded: +1, -1, or 0 (energised, released, or the same pattern)
  bool staged;      // written at a deadline from stage_coils(), before on_step_timer()
  bool interrupts_off;  // the firmware had interrupts off around the write (write_coils)
};

struct ServoChange {
  uint64_t tick;
  uint16_t us;
};

// The queue's actions as the firmware ran them: each one it took off its queue and began
// (hal::action_began), and each time the step timer stopped. An action ends at the next entry.
static const uint8_t kTimerStopped = 0xFF;
struct ActionEvent {
  uint64_t tick;
  uint8_t kind;  // queue::Kind, or kTimerStopped
  int32_t counted[kMotors];  // the firmware's step counts then (stepper::read_positions)
};

// What the controller did with each line, as it did it (hal::action_queued, hal::replied):
// every action it queued, with the action log's entry where it began (kNever: a '!' emptied
// it from the queue first), and every reply with the plan it left.
static const size_t kNever = ~size_t(0);
struct QueuedAction {
  uint64_t tick;
  uint8_t kind;             // queue::Kind
  int32_t delta[kMotors];   // kMove, kHome: its steps, from the plan before it
  uint8_t percent;          // kGripper: the aperture, whole percent, and its servo pulse;
  uint16_t pulse_us;        //   kOutput, kWaitIn: the level (0 or 1)
  uint8_t pin;              // kOutput, kWaitIn: the header pin
  uint16_t steps, cruise4;  // kMove: its plan block (articula/planner.h)
  uint32_t settle_ticks;    // kGripper, kDwell: its pause; kWaitIn: its limit, ms (0: one look)
  uint32_t max_rate, accel;  // $0 and $1 when it was queued (they change only at rest)
  size_t began;             // its entry in Hardware::actions, or kNever
};
struct Reply {
  uint64_t tick;
  uint8_t status;
  size_t queued;          // Hardware::queued's size then: the actions its line queued are before it
  robot::State planned;   // the plan then (firmware::planned())
  bool homed;
  uint32_t settings[articula::kSettingCount];
};

struct Hardware {
  Hardware() {
    for (int m = 0; m < kMotors; ++m) {
      microsteps[m] = 1;
      endstop_below[m] = true;
    }
  }
  uint64_t now = 0;  // ticks
  bool timer_running = false;
  uint64_t deadline = 0;

  std::vector<CoilWrite> coil_log;
  std::vector<ServoChange> servo_log;
  std::vector<ActionEvent> actions;  // actions begun and timer stops (its call returned 0, or stop_step_timer())
  std::vector<QueuedAction> queued;
  std::deque<size_t> in_queue;  // those of `queued` the firmware's queue may still hold, oldest first
  std::vector<Reply> replies;
  uint16_t servo_us = 0;

  std::deque<char> rx;  // received, not yet read by serial_read()
  std::string tx;       // everything the firmware sent, in the order it went out
  uint64_t serial_writes = 0;  // serial_write() calls
  int last_read = -1;          // the last byte serial_read() returned
  bool tx_line_start = true;   // the last byte serial_write() sent was an LF (or none was)

  // The status report, scheduled by the Nano's own rules (report.h; with an instant
  // transmitter a report is never going out when another '?' comes).
  bool started = false;     // hal::start() has run
  bool stop_early = false;  // '!' before it
  report::Schedule report_schedule;
  std::string report;       // built, waiting for a line boundary
  uint64_t reports_built = 0;
  std::function<void()> interrupt_point;

  // Coils staged for the next deadline (stage_coils), bit i for motor i.
  uint8_t staged_mask = 0;
  uint8_t staged[kMotors] = {};
  bool in_step_timer = false;  // inside firmware::on_step_timer()

  uint8_t eeprom[1024];
  uint32_t eeprom_bytes_written = 0;

  // The coil decoder: positions from the patterns, 2 for half steps, any other count full
  // steps (stride 2 in the half-step table), per motor (set at boot from the robot).
  uint8_t microsteps[kMotors];  // 1 each at first
  bool unipolar = false;        // the motors are on ULN2003s: the unipolar half-step table

  // STEP/DIR drivers: each STEP pulse moves its motor one step, towards more steps while its
  // DIR pin is high, when the drivers are enabled (a disabled driver ignores STEP: an error).
  bool dir[kMotors] = {};
  bool drivers_enabled = false;
  uint8_t staged_pulses = 0;  // bit i: a pulse of motor i at the next deadline
  int64_t position[kMotors] = {};
  vnano::CoilDecoder coils[kMotors];  // the virtual Nanos' decoder (virtual-nano/coil_decoder.h)
  uint8_t pattern[kMotors] = {};
  std::vector<std::string> errors;  // decoding errors: an illegal pattern or jump

  // The header pins (hal::io_*), bit n for header pin n: the firmware's outputs and the levels
  // it set (an output's, or an input's pull-up), and the inputs something outside drives (a
  // wire from another machine's output: a cell), with their levels. An input nothing drives
  // reads its pull-up. Every output change is logged with its tick.
  uint32_t io_output = 0;
  uint32_t io_high = 0;
  uint32_t io_driven = 0;
  uint32_t io_external = 0;
  struct IoChange {
    uint64_t tick;
    uint8_t pin;
    bool high;
  };
  std::vector<IoChange> io_log;
  // Called before the firmware reads its pins while something outside drives one (io_driven):
  // the host brings io_external up to the current tick (a cell's wires from other machines).
  std::function<void()> io_sync;

  // Endstops: pressed while position <= at (below) or >= at (!below).
  bool endstop_fitted[kMotors] = {};
  int64_t endstop_at[kMotors] = {};
  bool endstop_below[kMotors];  // true each at first

  int interrupts_off_depth = 0;
};

// The hardware of the machine this thread runs now (machine.h: Machine::Use): what every hal::
// call here reads and writes.
extern ARTICULA_FIRMWARE_THREAD Hardware* g_hw;  // (firmware/src/ram.h)
inline Hardware& hw() { return *g_hw; }

// An entry of the action log at the current tick, with the firmware's step counts.
void log_action(uint8_t kind);

// A fresh machine: everything reset; the EEPROM kept unless blank_eeprom (then all 0xFF).
void reset(bool blank_eeprom);

// A byte arrives at the receiver (the receive interrupt).
void receive(char c);

// The step timer's deadline: the staged coils written, then firmware::on_step_timer();
// returns what it returned.
uint32_t step_deadline();

}  // namespace sitl

#endif  // ARTICULA_FIRMWARE_SITL_HAL_SITL_H
