// firmware/test/harness.h - the native tests' view of the firmware on its virtual clock
// (firmware/sitl/machine.h): the machine's calls, booted with the test variant's arm, and the
// checks that need GoogleTest.
#ifndef ARTICULA_FIRMWARE_TEST_HARNESS_H
#define ARTICULA_FIRMWARE_TEST_HARNESS_H

#include <articula/motion.h>
#include <articula/protocol.h>

#include <string>
#include <utility>
#include <vector>

#include "hal_sitl.h"
#include "machine.h"
#include "robot.h"

namespace sim {

using sitl::at_rest;
using sitl::command;
using sitl::hal_errors;
using sitl::kByteTicks;
using sitl::kPollTicks;
using sitl::kSecond;
using sitl::motion_settings;
using sitl::on_the_line;
using sitl::reports;
using sitl::run_until;
using sitl::run_until_at_rest;
using sitl::send;
using sitl::send_at;
using sitl::Step;
using sitl::steps_of;
using sitl::take_lines;
using sitl::take_report;
using sitl::tick;

typedef articula::StatusReport<robot::kJoints> Status;

// Power-up (sitl::boot) with this test variant's arm in EEPROM (the halfstep variant's, made
// by `articula configure --header`; the built-in MK2 for the main one).
void boot(bool blank_eeprom = true, const std::string& during_setup = "");

// Sends '?' and runs one pass; the report it answers with, parsed (a test failure if none).
Status status();

// The variant's robot file (the built-in MK2's for the main one): what the tests that need the
// host library load with its loader.
const char* robot_file();

// The same, as a host would work them out: the protocol's 2 MHz tick and the $0 and $1 of
// a `$` listing (sends `$`).
articula::MotionSettings motion_settings_from_listing();
// A `$` listing as numbers: setting -> value in thousandths.
std::vector<std::pair<int, int32_t>> settings_listing();

}  // namespace sim

#endif  // ARTICULA_FIRMWARE_TEST_HARNESS_H
