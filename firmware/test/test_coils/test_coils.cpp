// Tests firmware/src/coils.cpp: the L298N's (or the ULN2003's) input patterns of full and half steps, forwards,
// backwards and across the wrap of the table, as the motors see them (decoded by the SITL
// HAL from the pin writes, independently of the firmware's table), and through whole moves.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "coils.h"
#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"

namespace {

// The sequences as the specification writes them, IN1..IN4 left to right: [0] an L298N's
// bipolar motor, [1] a ULN2003's unipolar one (a 28BYJ-48).
const char* const kFullSteps[2][4] = {{"1010", "0110", "0101", "1001"}, {"1100", "0110", "0011", "1001"}};
const char* const kHalfSteps[2][8] = {{"1000", "1010", "0010", "0110", "0100", "0101", "0001", "1001"},
                                      {"1000", "1100", "0100", "0110", "0010", "0011", "0001", "1001"}};
// The variant's: its configuration's drive.
int drive_table() { return robot::config().drive == articula::kDriveUln2003 ? 1 : 0; }

std::string pins(uint8_t pattern) {
  std::string s;
  for (int bit = 0; bit < 4; ++bit) s += (pattern >> bit) & 1 ? '1' : '0';
  return s;
}

// The patterns written to one motor since `from` (an index into the coil log).
std::vector<std::string> written(int motor, size_t from) {
  std::vector<std::string> out;
  for (size_t i = from; i < sitl::hw().coil_log.size(); ++i)
    if (sitl::hw().coil_log[i].motor == motor) out.push_back(pins(sitl::hw().coil_log[i].pattern));
  return out;
}

bool half_steps(int motor) { return robot::motor(uint8_t(motor)).microsteps == 2; }

}  // namespace

TEST(Coils, TableIsTheSpecifiedHalfStepSequence) {
  for (int t = 0; t < 2; ++t) {
    for (int i = 0; i < 8; ++i) EXPECT_EQ(pins(articula::kCoilSequence[t][i]), kHalfSteps[t][i]) << t << " " << i;
    // The full-step states (two phases on) are the odd places.
    for (int i = 0; i < 4; ++i) EXPECT_EQ(pins(articula::kCoilSequence[t][2 * i + 1]), kFullSteps[t][i]) << t << " " << i;
  }
}

TEST(Coils, StartReleasedThenEnergiseOnTheFirstFullStepState) {
  sim::boot();
  if (robot::step_dir()) GTEST_SKIP() << "STEP/DIR drivers have no coils: StepDir.* tests their pulses";
  EXPECT_FALSE(coils::on());
  for (int m = 0; m < robot::kJoints; ++m) {
    EXPECT_EQ(written(m, 0), std::vector<std::string>{"0000"}) << m;
    EXPECT_EQ(coils::phase(uint8_t(m)), 1);
  }
  const size_t from = sitl::hw().coil_log.size();
  coils::energise();
  EXPECT_TRUE(coils::on());
  for (int m = 0; m < robot::kJoints; ++m) EXPECT_EQ(written(m, from), std::vector<std::string>{kFullSteps[drive_table()][0]}) << m;
  coils::release();
  EXPECT_FALSE(coils::on());
  for (int m = 0; m < robot::kJoints; ++m) EXPECT_EQ(written(m, from).back(), "0000") << m;
}

// Each motor in its robot-file mode: forwards through two whole cycles (across the table's
// wrap), then backwards through them, one write per step, every pattern as specified.
TEST(Coils, SequencesForwardBackwardAndWrap) {
  sim::boot();  // (the variant's arm, to know its drive)
  if (robot::step_dir()) GTEST_SKIP() << "STEP/DIR drivers have no coils: StepDir.* tests their pulses";
  for (int m = 0; m < robot::kJoints; ++m) {
    sim::boot();
    coils::energise();
    const bool half = half_steps(m);
    const int period = half ? 8 : 4;
    const char* const* seq = half ? kHalfSteps[drive_table()] : kFullSteps[drive_table()];
    const int start = half ? 1 : 0;  // both start on the first full step (1010, or 1100)
    size_t from = sitl::hw().coil_log.size();
    for (int k = 0; k < 2 * period + 3; ++k) coils::step(uint8_t(m), false);
    std::vector<std::string> w = written(m, from);
    ASSERT_EQ(w.size(), size_t(2 * period + 3));
    for (size_t k = 0; k < w.size(); ++k) EXPECT_EQ(w[k], seq[(start + 1 + int(k)) % period]) << "motor " << m << " forward " << k;
    from = sitl::hw().coil_log.size();
    for (int k = 0; k < 3 * period; ++k) coils::step(uint8_t(m), true);
    w = written(m, from);
    ASSERT_EQ(w.size(), size_t(3 * period));
    // Back from place start + 2 period + 3, one place a step, past the wrap twice.
    for (size_t k = 0; k < w.size(); ++k)
      EXPECT_EQ(w[k], seq[((start + 2 * period + 3 - 1 - int(k)) % period + period) % period]) << "motor " << m << " back " << k;
    // The other motors were not touched.
    for (int o = 0; o < robot::kJoints; ++o) {
      if (o != m) {
        EXPECT_TRUE(written(o, from).empty());
      }
    }
    EXPECT_EQ(sitl::hw().position[m], 2 * period + 3 - 3 * period);
    EXPECT_EQ(sim::hal_errors(), "");
  }
}

// The firmware's moves, seen through the pins: one write of all four inputs per motor step,
// the decoded position equals the firmware's step count, in both directions; the coils are
// energised before the first step.
TEST(Coils, MovesDriveTheSequences) {
  sim::boot();
  if (robot::step_dir()) GTEST_SKIP() << "STEP/DIR drivers have no coils: StepDir.* tests their pulses";
  for (const char* line : {"L 0 20", "L 1 -20", "L 2 10", "L 0 -30", "L 2 -15", "L 1 25"}) {
    ASSERT_EQ(sim::command(line), "ok") << line;
    ASSERT_TRUE(sim::run_until_at_rest());
  }
  EXPECT_EQ(sim::hal_errors(), "");
  const sim::Status st = sim::status();
  for (int m = 0; m < robot::kJoints; ++m) {
    EXPECT_EQ(sitl::hw().position[m], st.steps[m]) << m;
    EXPECT_NE(st.steps[m], 0) << m;
    // Every write of this motor after the first energising is a step of exactly one place.
    int energised = 0, steps = 0;
    for (const sitl::CoilWrite& w : sitl::hw().coil_log) {
      if (w.motor != m) continue;
      if (w.step != 0) {
        ++steps;
      } else if (w.pattern != 0) {
        ++energised;
      }
    }
    EXPECT_EQ(energised, 1) << m;  // the release time (2 s) never passed between moves
    EXPECT_GT(steps, 0);
  }
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
