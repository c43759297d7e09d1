// Tests homing with endstops (firmware/src/stepper.cpp, seek and set): with switches fitted
// ($3) the arm powers up in Alarm and refuses moves; H seeks each switch towards its
// motor's minimum angle at the homing rate, takes the switch as that minimum, sends the
// motors without a switch to the home pose; a switch that is never found, or a '!' during
// the search, leaves the arm in Alarm with the queue emptied.
#include <articula/actuation.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "queue.h"
#include "robot.h"

using namespace articula;

namespace {

const int kJ = robot::kJoints;

// Motor m's switch: pressed `at` steps (of the pins) towards its minimum angle.
void fit_switch(int m, int64_t at) {
  const bool towards_fewer = robot::motor(uint8_t(m)).direction > 0;
  sitl::hw().endstop_fitted[m] = true;
  sitl::hw().endstop_at[m] = towards_fewer ? -at : at;
  sitl::hw().endstop_below[m] = towards_fewer;
}

void boot_with_switches(int mask) {
  sim::boot();
  ASSERT_EQ(sim::command("$3=" + std::to_string(mask)), "ok");
  sim::boot(false);
}

// The step a switch stands for: the motor's minimum angle.
int32_t min_angle_step(int m) {
  const MotorSpec& s = robot::motor(uint8_t(m));
  return quantize_within_limits(s, s.min);
}

}  // namespace

TEST(Homing, SeeksTheSwitchAndSetsThePosition) {
  boot_with_switches(1);
  EXPECT_EQ(sim::status().state, kStateAlarm);
  EXPECT_EQ(sim::command("L 0 1"), "error:12");
  fit_switch(0, 40);
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(sim::command("H"), "ok");
  ASSERT_EQ(sim::command("L 0 10"), "ok");  // accepted behind H
  sim::tick();
  EXPECT_EQ(sim::status().state, kStateHome);
  ASSERT_TRUE(sim::run_until_at_rest(120 * sim::kSecond));
  // 40 seek steps (the 40th presses the switch) at the homing rate's interval.
  const std::vector<sim::Step> seek = sim::steps_of(0, t0);
  ASSERT_GE(seek.size(), 40u);
  const uint64_t interval = 2000000 / 200;  // default $4 = 200 steps/s
  for (size_t k = 0; k < 40; ++k) {
    EXPECT_EQ(seek[k].tick, t0 + (k + 1) * interval) << k;
    EXPECT_EQ(seek[k].dir, robot::motor(0).direction > 0 ? -1 : 1);
  }
  // Then the move of L 0 10 from the minimum angle, commanded min + 10 degrees.
  const sim::Status st = sim::status();
  EXPECT_EQ(st.state, kStateIdle);
  const MotorSpec& base = robot::motor(0);
  EXPECT_EQ(st.steps[0], quantize_within_limits(base, base.min + 10000));
  // The pins moved exactly that far from the switch.
  const int64_t at_switch = sitl::hw().endstop_at[0];
  EXPECT_EQ(sitl::hw().position[0] - at_switch, int64_t(st.steps[0]) - min_angle_step(0));
  // Motors without a switch went to the home pose.
  for (int i = 1; i < kJ; ++i) EXPECT_EQ(st.steps[i], robot::home_steps()[i]) << i;
  for (int i = 1; i < kJ; ++i) EXPECT_EQ(sitl::hw().position[i], robot::home_steps()[i]) << i;
  EXPECT_EQ(sim::hal_errors(), "");
}

// Every motor with a switch: sought one after the other, in motor order, each in its own
// direction towards its minimum.
TEST(Homing, EveryMotorInTurn) {
  const int all = (1 << kJ) - 1;
  boot_with_switches(all);
  ASSERT_EQ(sim::command("$4=1000"), "ok");
  for (int m = 0; m < kJ; ++m) fit_switch(m, 10 + 7 * m);
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(sim::command("H"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest(120 * sim::kSecond));
  const sim::Status st = sim::status();
  EXPECT_EQ(st.state, kStateIdle);
  uint64_t prev_end = t0;
  for (int m = 0; m < kJ; ++m) {
    EXPECT_EQ(st.steps[m], min_angle_step(m)) << m;  // a switch motor stays on its switch
    const std::vector<sim::Step> s = sim::steps_of(m, t0);
    ASSERT_EQ(s.size(), size_t(10 + 7 * m)) << m;
    EXPECT_GT(s.front().tick, prev_end) << m;  // after the motor before it
    prev_end = s.back().tick;
    EXPECT_EQ(sitl::hw().position[m], sitl::hw().endstop_at[m]);
  }
}

TEST(Homing, SwitchNeverFoundLeavesAlarm) {
  boot_with_switches(1);
  ASSERT_EQ(sim::command("$4=4000"), "ok");
  // No switch fitted in the SITL HAL: the search gives up after twice the motor's range.
  ASSERT_EQ(sim::command("H"), "ok");
  ASSERT_EQ(sim::command("L 0 10"), "ok");
  ASSERT_EQ(sim::command("G 50"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest(120 * sim::kSecond));
  const sim::Status st = sim::status();
  EXPECT_EQ(st.state, kStateAlarm);
  EXPECT_EQ(st.free_slots, queue::kSize);
  EXPECT_EQ(st.gripper, 0);  // the queued G was discarded
  const MotorSpec& base = robot::motor(0);
  const size_t range = size_t(2 * (max_steps(base) - min_steps(base)) + 16);
  EXPECT_EQ(sim::steps_of(0).size(), range);
  EXPECT_EQ(sim::command("L 0 1"), "error:12");
  // Z ends the alarm.
  EXPECT_EQ(sim::command("Z"), "ok");
  EXPECT_EQ(sim::status().state, kStateIdle);
}

TEST(Homing, StopDuringTheSearchLeavesAlarm) {
  boot_with_switches(1);
  fit_switch(0, 100);
  ASSERT_EQ(sim::command("H"), "ok");
  sim::run_until([] { return sim::steps_of(0).size() >= 10; }, 10 * sim::kSecond);
  sim::send("!");
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_LT(sim::steps_of(0).size(), 15u);
  EXPECT_EQ(sim::status().state, kStateAlarm);
  EXPECT_EQ(sim::command("M 0 90 0"), kJ == 3 ? "error:12" : "error:5");
  // H again finds it.
  ASSERT_EQ(sim::command("H"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest(60 * sim::kSecond));
  EXPECT_EQ(sim::status().state, kStateIdle);
  EXPECT_EQ(sim::status().steps[0], min_angle_step(0));
}

// Switches fitted, but $3 says none: no alarm at power-up, H goes to the home pose.
TEST(Homing, NoSwitchesNoAlarm) {
  sim::boot();
  EXPECT_EQ(sim::status().state, kStateIdle);
  fit_switch(0, 5);
  ASSERT_EQ(sim::command("H"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(sim::status().steps[i], robot::home_steps()[i]);
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
