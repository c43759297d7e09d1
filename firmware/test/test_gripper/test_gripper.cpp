// Tests firmware/src/gripper.cpp and the gripper actions: the servo pulse widths of S and
// G (the angle linear between the robot file's closed and open angles, the Arduino Servo
// convention 544 us at 0 degrees and 2400 us at 180), the settle pause before the next
// action, and the aperture in status reports.
#include <articula/servo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "hal_sitl.h"
#include "gripper.h"
#include "harness.h"
#include "robot.h"

namespace {

// Worked out here in double: aperture in percent, between the configuration's angles (the
// robot file's, test_robot checks).
uint16_t expected_us(double percent) {
  const double closed = robot::config().servo_closed_deg, open = robot::config().servo_open_deg;
  double deg = closed + (open - closed) * percent / 100.0;
  deg = std::min(180.0, std::max(0.0, deg));
  return uint16_t(std::lround(544.0 + deg * (2400.0 - 544.0) / 180.0));
}

}  // namespace

TEST(Gripper, PulseWidths) {
  sim::boot();
  EXPECT_EQ(gripper::pulse_us(0), expected_us(0));
  EXPECT_EQ(gripper::pulse_us(100000), expected_us(100));
  for (int32_t a = 0; a <= 100000; a += 137) EXPECT_NEAR(gripper::pulse_us(a), expected_us(a / 1000.0), 1) << a;
  // The convention's end points.
  EXPECT_EQ(articula::kServoPulseAt0Us, 544);
  EXPECT_EQ(articula::kServoPulseAt180Us, 2400);
}

TEST(Gripper, SAndGSetThePulse) {
  sim::boot();
  EXPECT_TRUE(sitl::hw().servo_log.empty());  // no pulses before the first S or G
  const struct {
    const char* line;
    double percent;
  } cases[] = {{"S 1", 0}, {"S 0", 100}, {"G 50", 50}, {"G 0", 0}, {"G 100", 100}, {"g 33.3", 33.3}, {"G 99.5", 99.5}};
  for (const auto& c : cases) {
    const size_t before = sitl::hw().servo_log.size();
    const uint64_t t = sitl::hw().now;
    ASSERT_EQ(sim::command(c.line), "ok") << c.line;
    ASSERT_EQ(sitl::hw().servo_log.size(), before + 1) << c.line;
    EXPECT_EQ(sitl::hw().servo_log.back().tick, t) << c.line;
    EXPECT_EQ(sitl::hw().servo_log.back().us, expected_us(c.percent)) << c.line;
    ASSERT_TRUE(sim::run_until_at_rest());
    EXPECT_EQ(sim::status().gripper, int(std::floor(c.percent + 0.5))) << c.line;
  }
  // S 1 is G 0, S 0 is G 100.
  EXPECT_EQ(expected_us(0), gripper::pulse_us(0));
  EXPECT_NE(expected_us(0), expected_us(100));
}

// The settle time: the move after a gripper action starts that long after the pulse.
TEST(Gripper, SettlePauseBeforeTheNextAction) {
  for (int settle_ms : {300, 0, 1234}) {
    sim::boot();
    ASSERT_EQ(sim::command("$5=" + std::to_string(settle_ms)), "ok");
    const uint64_t t0 = sitl::hw().now;
    ASSERT_EQ(sim::command("S 1"), "ok");
    const uint64_t t1 = sitl::hw().now;  // the move is queued at this pass
    ASSERT_EQ(sim::command("L 0 5"), "ok");
    ASSERT_TRUE(sim::run_until_at_rest());
    const articula::MotionSettings s = sim::motion_settings_from_listing();
    articula::StepProfile p;
    p.start(100, s);
    const uint64_t first = p.next_interval();
    ASSERT_FALSE(sim::steps_of(0).empty());
    EXPECT_EQ(sitl::hw().servo_log.back().tick, t0);
    // Starts when the pause ends (at once when the move is queued later than that).
    EXPECT_EQ(sim::steps_of(0).front().tick, std::max(t1, t0 + uint64_t(settle_ms) * 2000) + first) << settle_ms;
  }
  // A stop during the pause ends it at once.
  sim::boot();
  ASSERT_EQ(sim::command("$5=5000"), "ok");
  ASSERT_EQ(sim::command("S 0"), "ok");
  ASSERT_EQ(sim::command("L 0 5"), "ok");
  sim::run_until([] { return false; }, 100 * sim::kPollTicks);
  EXPECT_EQ(sim::status().state, articula::kStateRun);
  sim::send("!");
  sim::tick();
  sim::tick();
  EXPECT_EQ(sim::status().state, articula::kStateIdle);
  EXPECT_TRUE(sim::steps_of(0).empty());
  EXPECT_EQ(sim::status().gripper, 100);
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
