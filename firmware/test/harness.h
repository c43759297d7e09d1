// firmware/test/harness.h - runs the firmware on the fake HAL like the Nano would.
//
// The main loop is poll(), called once every kPollTicks of simulated time; between two
// polls the step timer's interrupt fires at each of its deadlines and the clock jumps to it:
// the staged coils are written, then firmware::on_step_timer() runs. Received bytes go to
// the fake HAL's receive interrupt (fake::receive): '?' is answered by a status report at
// once (at the next line boundary of the output), '!' goes to firmware::on_realtime, every
// other byte to serial_read().
#ifndef ARTICULA_FIRMWARE_TEST_HARNESS_H
#define ARTICULA_FIRMWARE_TEST_HARNESS_H

#include <articula/motion.h>
#include <articula/protocol.h>

#include <functional>
#include <string>
#include <vector>

#include "fake_hal.h"
#include "robot.h"

namespace sim {

static const uint64_t kPollTicks = 1000;  // a main-loop pass every 0.5 ms
static const uint64_t kSecond = 2000000;  // ticks

typedef articula::StatusReport<robot::kJoints> Status;

// Power-up: the fake hardware reset (the EEPROM blank, or kept as it is), then as main.cpp:
// hal::init(), firmware::setup(), hal::start(). `during_setup`: bytes that arrive after the
// receiver is on and before the firmware is set up.
void boot(bool blank_eeprom = true, const std::string& during_setup = "");

// Bytes from the host, at the current time.
void send(const std::string& bytes);

// One main-loop pass: poll(), then the clock advances kPollTicks, firing every step-timer
// deadline on the way.
void tick();
// Ticks until done() (checked after each pass) or max_ticks have passed; false on timeout.
bool run_until(const std::function<bool()>& done, uint64_t max_ticks);

// Complete lines the firmware has written since the last call (without their LF).
std::vector<std::string> take_lines();

// Sends `line` and an LF, runs until a reply (ok / error:N) comes; returns it ("" on
// timeout). Report lines before it go to reports().
std::string command(const std::string& line, uint64_t max_ticks = 120 * kSecond);
const std::vector<std::string>& reports();

// Sends '?' and runs one pass; the report it answers with, parsed (a test failure if none).
Status status();

// Nothing moving, nothing queued, no stop under way.
bool at_rest();
bool run_until_at_rest(uint64_t max_ticks = 600 * kSecond);

// The motion settings the firmware's StepProfile uses now.
articula::MotionSettings motion_settings();
// The same, as a host would work them out: the protocol's 2 MHz tick and the $0 and $1 of
// a `$` listing (sends `$`).
articula::MotionSettings motion_settings_from_listing();
// A `$` listing as numbers: setting -> value in thousandths.
std::vector<std::pair<int, int32_t>> settings_listing();

// Step events of one motor from the coil log (decoded by the fake HAL): times and signs.
struct Step {
  uint64_t tick;
  int8_t dir;
};
std::vector<Step> steps_of(int motor, uint64_t from_tick = 0);

// Every error the fake HAL saw (illegal coil patterns, jumps, unbalanced interrupts).
std::string hal_errors();

}  // namespace sim

#endif  // ARTICULA_FIRMWARE_TEST_HARNESS_H
