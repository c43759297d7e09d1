// Tests the STEP/DIR side of firmware/src/coils.cpp and the HAL (a CNC shield's sockets):
// the drivers' pins as the SITL HAL decodes them, independently of the firmware: a STEP pulse
// a step, towards more steps while DIR is high, ignored while the drivers are off; ENABLE
// following the coils' idle rule. Built for the arms on STEP/DIR drivers (firmware/native.cmake);
// on another arm each test says it does not apply.
#include <gtest/gtest.h>

#include <string>

#include "coils.h"
#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"

TEST(StepDir, DisabledAtStartEnabledForAMoveAndOffAgain) {
  sim::boot();
  if (!robot::step_dir()) GTEST_SKIP() << "this arm's motors are on coils: Coils.* tests them";
  EXPECT_FALSE(coils::on());
  EXPECT_FALSE(sitl::hw().drivers_enabled);
  coils::energise();
  EXPECT_TRUE(sitl::hw().drivers_enabled);
  for (int m = 0; m < robot::kJoints; ++m) EXPECT_NE(sitl::hw().pattern[m] & sitl::kEnabled, 0) << m;
  coils::release();
  EXPECT_FALSE(sitl::hw().drivers_enabled);
  for (int m = 0; m < robot::kJoints; ++m) EXPECT_EQ(sitl::hw().pattern[m], 0) << m;
  // A pulse with the drivers off moves nothing, and the decoder says so.
  coils::step(0, false);
  EXPECT_EQ(sitl::hw().position[0], 0);
  EXPECT_NE(sim::hal_errors().find("while the drivers are disabled"), std::string::npos);
}

TEST(StepDir, APulseAStepTheWayDirSays) {
  sim::boot();  // (the variant's arm, to know its drive)
  if (!robot::step_dir()) GTEST_SKIP() << "this arm's motors are on coils: Coils.* tests them";
  for (int m = 0; m < robot::kJoints; ++m) {
    sim::boot();
    coils::energise();
    const size_t from = sitl::hw().coil_log.size();
    for (int k = 0; k < 7; ++k) coils::step(uint8_t(m), false);
    for (int k = 0; k < 10; ++k) coils::step(uint8_t(m), true);
    EXPECT_EQ(sitl::hw().position[m], -3) << m;
    int up = 0, down = 0;
    for (size_t i = from; i < sitl::hw().coil_log.size(); ++i) {
      const sitl::CoilWrite& w = sitl::hw().coil_log[i];
      EXPECT_EQ(int(w.motor), m);  // no other motor pulsed
      ASSERT_NE(w.pattern & sitl::kStepPulse, 0);
      (w.pattern & sitl::kDirHigh ? up : down) += 1;
    }
    EXPECT_EQ(up, 7);
    EXPECT_EQ(down, 10);
    EXPECT_EQ(sim::hal_errors(), "");
  }
}

// The firmware's moves through the pins: one pulse per step, each at a deadline (staged), the
// decoded position the firmware's step count.
TEST(StepDir, MovesPulseTheDrivers) {
  sim::boot();
  if (!robot::step_dir()) GTEST_SKIP() << "this arm's motors are on coils: Coils.* tests them";
  for (const char* line : {"L 0 20", "L 1 -20", "L 2 10", "L 0 -30", "L 2 -15", "L 1 25"}) {
    ASSERT_EQ(sim::command(line), "ok") << line;
    ASSERT_TRUE(sim::run_until_at_rest());
  }
  EXPECT_EQ(sim::hal_errors(), "");
  const sim::Status st = sim::status();
  for (int m = 0; m < robot::kJoints; ++m) {
    EXPECT_EQ(sitl::hw().position[m], st.steps[m]) << m;
    EXPECT_NE(st.steps[m], 0) << m;
    int pulses = 0;
    for (const sitl::CoilWrite& w : sitl::hw().coil_log)
      if (w.motor == m && (w.pattern & sitl::kStepPulse)) {
        ++pulses;
        EXPECT_TRUE(w.staged);
      }
    EXPECT_GT(pulses, 100) << m;  // 1/4 and 1/8 steps: many
  }
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
