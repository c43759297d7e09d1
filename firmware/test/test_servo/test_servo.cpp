// Tests a servo arm's side of the firmware (the servo build's steps are ticks of each servo's
// pulse, firmware/src/coils.cpp): the moves never ask a servo for more than its rate and
// acceleration ($138, $139, the robot file's speed and accel), whatever $0 and $1 say; its
// pulses never stop (a servo holds only while it gets them); Z sends it home; and a
// configuration whose servos share a pin, or lack a step-0 pulse, is refused. Built for the
// servo arms (firmware/native.cmake); on another arm each test says it does not apply.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "coils.h"
#include "hal.h"
#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"

namespace {
const char* kNotServos = "this arm's motors are steppers: Coils.* and StepDir.* test them";

// The commit of the image staged in the SITL EEPROM (its CRC, as the host would send it).
std::string commit_staged() {
  const uint8_t* e = sitl::hw().eeprom + robot::kEepromAddress + 1;
  return "$199=" + std::to_string(articula::config_checksum(e));
}

// The shortest interval between two steps of `motor` since `from`, in ticks.
uint64_t shortest_interval(int motor, uint64_t from) {
  const std::vector<sim::Step> s = sim::steps_of(motor, from);
  uint64_t best = ~uint64_t(0);
  for (size_t i = 1; i < s.size(); ++i) best = std::min(best, s[i].tick - s[i - 1].tick);
  return best;
}
}  // namespace

TEST(Servo, TheServosCapTheRateWhateverTheSettingsSay) {
  sim::boot();
  if (!robot::servos()) GTEST_SKIP() << kNotServos;
  const uint16_t cap = robot::config().rate_cap;
  ASSERT_GT(cap, 0u);
  ASSERT_LT(cap, 4000u);
  ASSERT_EQ(sim::command("$0=4000"), "ok");  // the most the settings take
  ASSERT_EQ(sim::command("$1=100000"), "ok");
  const uint64_t from = sitl::hw().now;
  ASSERT_EQ(sim::command("L 0 40"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  ASSERT_GT(sim::steps_of(0, from).size(), 100u);
  // The fastest step is at the servos' rate, never the settings' 4000 steps/s.
  const double fastest = double(hal::kTickHz) / double(shortest_interval(0, from));
  EXPECT_LE(fastest, cap * 1.01) << "steps/s";
  EXPECT_GE(fastest, cap * 0.9) << "steps/s";
  EXPECT_EQ(sim::hal_errors(), "");
}

TEST(Servo, ItsPulsesGoOnAtRestAndAtHome) {
  sim::boot();
  if (!robot::servos()) GTEST_SKIP() << kNotServos;
  ASSERT_EQ(sim::command("L 0 10"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const int64_t moved = sitl::hw().position[0];
  EXPECT_NE(moved, 0);
  // The idle time passes: a servo arm's "release" changes nothing a servo sees.
  const uint64_t later = sitl::hw().now + 3 * sim::kSecond;
  sim::run_until([&] { return sitl::hw().now >= later; }, 4 * sim::kSecond);
  EXPECT_EQ(sitl::hw().position[0], moved);
  ASSERT_EQ(sim::command("L 0 -5"), "ok");  // moves again from where it was
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::status().steps[0], int32_t(sitl::hw().position[0]));
  // Z: the home pose's steps, and each servo is given the pulse for them at once.
  ASSERT_EQ(sim::command("Z"), "ok");
  for (int i = 0; i < robot::count(); ++i) EXPECT_EQ(sim::status().steps[i], robot::home_steps()[i]) << i;
  EXPECT_EQ(sim::hal_errors(), "");
}

TEST(Servo, TwoServosOnOnePinOrNoStepZeroPulseAreRefused) {
  sim::boot();
  if (!robot::servos()) GTEST_SKIP() << kNotServos;
  const uint16_t before = robot::checksum();
  // The shoulder's servo on the base's pin.
  ASSERT_EQ(sim::command("$136=" + std::to_string(robot::config().servo_pin[0])), "ok");
  EXPECT_EQ(sim::command(commit_staged()), "error:18");
  EXPECT_EQ(robot::checksum(), before);
  ASSERT_EQ(sim::command("$136=" + std::to_string(robot::config().servo_pin[1])), "ok");
  // No pulse at step 0 (a stepper arm's zero).
  ASSERT_EQ(sim::command("$132=0"), "ok");
  EXPECT_EQ(sim::command(commit_staged()), "error:18");
  EXPECT_EQ(robot::checksum(), before);
}
