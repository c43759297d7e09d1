// Tests firmware/src/stepper.cpp through the serial protocol and the pins: the step times
// of moves are exactly the shared StepProfile/LineStepper sequence (worked out here
// independently, from the settings a `$` listing shows), moves chain without a gap, the
// motors of a coordinated move finish together, '!' decelerates as StepProfile::stop, and
// the coils are released after the idle time and energised again before the next move.
#include <articula/actuation.h>
#include <articula/motion.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"

using namespace articula;

namespace {

const int kJ = robot::kJoints;

// An M line for actuator angles in millidegrees.
std::string m_line(const Millideg* a) {
  std::string s = "M";
  for (int i = 0; i < kJ; ++i) {
    char buf[24];
    std::snprintf(buf, sizeof buf, " %.3f", a[i] / 1000.0);
    s += buf;
  }
  return s;
}

// Angles at a fraction of each motor's range.
std::vector<Millideg> at_fractions(double f0, double f1, double f2) {
  const double f[3] = {f0, f1, f2};
  std::vector<Millideg> a(kJ);
  for (int i = 0; i < kJ; ++i) {
    const MotorSpec& m = robot::motor(uint8_t(i));
    a[i] = Millideg(m.min + (m.max - m.min) * f[i]);
  }
  return a;
}

// Per motor, the ticks of its steps in a move from `from` steps to `to` steps that starts
// at t0, from LineStepper and StepProfile run here; stopped (StepProfile::stop) at the
// first step after stop_at.
std::vector<std::vector<uint64_t>> expected_steps(const int32_t* from, const int32_t* to, uint64_t t0,
                                                  const MotionSettings& s, uint64_t stop_at = UINT64_MAX) {
  std::vector<std::vector<uint64_t>> out(kJ);
  int32_t delta[3] = {0, 0, 0};
  for (int i = 0; i < kJ; ++i) delta[i] = to[i] - from[i];
  LineStepper<3> line;
  line.start(delta, uint8_t(kJ));
  StepProfile p;
  p.start(line.dominant, s);
  if (p.done()) return out;
  uint64_t t = t0 + p.next_interval();
  for (;;) {
    const uint8_t mask = line.next();
    for (int i = 0; i < kJ; ++i)
      if (mask & (1u << i)) out[i].push_back(t);
    if (t > stop_at) p.stop();
    if (p.done()) break;
    t += p.next_interval();
  }
  return out;
}

std::vector<uint64_t> ticks_of(int motor, uint64_t from_tick) {
  std::vector<uint64_t> out;
  for (const sim::Step& s : sim::steps_of(motor, from_tick)) out.push_back(s.tick);
  return out;
}

std::vector<int32_t> positions() {
  const sim::Status st = sim::status();
  return std::vector<int32_t>(st.steps, st.steps + kJ);
}

std::vector<int32_t> quantized(const std::vector<Millideg>& a) {
  std::vector<int32_t> s(kJ);
  for (int i = 0; i < kJ; ++i) s[i] = quantize_within_limits(robot::motor(uint8_t(i)), a[i]);
  return s;
}

}  // namespace

TEST(Stepper, StepTimesAreTheSharedProfileStepForStep) {
  sim::boot();
  const MotionSettings s = sim::motion_settings_from_listing();
  EXPECT_EQ(s.max_rate, 600u);  // the defaults
  EXPECT_EQ(s.accel, 2000u);
  const std::vector<int32_t> from = positions();
  const std::vector<Millideg> target = at_fractions(0.85, 0.2, 0.7);
  const std::vector<int32_t> to = quantized(target);
  const uint64_t t0 = sitl::hw().now;  // the line is run by the next poll, at this time
  ASSERT_EQ(sim::command(m_line(target.data())), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const auto expected = expected_steps(from.data(), to.data(), t0, s);
  size_t total = 0;
  for (int i = 0; i < kJ; ++i) {
    EXPECT_EQ(ticks_of(i, t0), expected[i]) << "motor " << i;
    total += expected[i].size();
  }
  EXPECT_GT(total, 100u);
  EXPECT_EQ(positions(), to);
  EXPECT_EQ(sim::hal_errors(), "");
}

// Other settings, and the firmware's own settings agree with the listing.
TEST(Stepper, SettingsShapeTheProfile) {
  sim::boot();
  ASSERT_EQ(sim::command("$0=250"), "ok");
  ASSERT_EQ(sim::command("$1=700"), "ok");
  const MotionSettings s = sim::motion_settings_from_listing();
  EXPECT_EQ(s.max_rate, 250u);
  EXPECT_EQ(s.accel, 700u);
  EXPECT_EQ(sim::motion_settings().max_rate, 250u);
  EXPECT_EQ(sim::motion_settings().accel, 700u);
  const std::vector<int32_t> from = positions();
  const std::vector<Millideg> target = at_fractions(0.1, 0.9, 0.4);
  const std::vector<int32_t> to = quantized(target);
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(sim::command(m_line(target.data())), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const auto expected = expected_steps(from.data(), to.data(), t0, s);
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(ticks_of(i, t0), expected[i]) << "motor " << i;
  // The move lasted what profile_duration_ticks says (a host's prediction).
  uint32_t n = 0;
  for (int i = 0; i < kJ; ++i) n = std::max(n, uint32_t(std::abs(to[i] - from[i])));
  uint64_t last = 0;
  for (int i = 0; i < kJ; ++i)
    if (!expected[i].empty()) last = std::max(last, expected[i].back());
  EXPECT_EQ(last - t0, profile_duration_ticks(n, s));
}

// Queued moves follow each other without a gap: each starts, from rest, at the tick of the
// last step of the one before.
TEST(Stepper, QueuedMovesChainWithoutAGap) {
  sim::boot();
  const MotionSettings s = sim::motion_settings_from_listing();
  const std::vector<Millideg> a = at_fractions(0.7, 0.3, 0.6), b = at_fractions(0.2, 0.6, 0.3),
                              c = at_fractions(0.6, 0.5, 0.5);
  const std::vector<int32_t> p0 = positions(), pa = quantized(a), pb = quantized(b), pc = quantized(c);
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(sim::command(m_line(a.data())), "ok");
  ASSERT_EQ(sim::command(m_line(b.data())), "ok");
  ASSERT_EQ(sim::command(m_line(c.data())), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  auto last_of = [](const std::vector<std::vector<uint64_t>>& e) {
    uint64_t t = 0;
    for (const auto& v : e)
      if (!v.empty()) t = std::max(t, v.back());
    return t;
  };
  const auto ea = expected_steps(p0.data(), pa.data(), t0, s);
  const auto eb = expected_steps(pa.data(), pb.data(), last_of(ea), s);
  const auto ec = expected_steps(pb.data(), pc.data(), last_of(eb), s);
  for (int i = 0; i < kJ; ++i) {
    std::vector<uint64_t> all = ea[i];
    all.insert(all.end(), eb[i].begin(), eb[i].end());
    all.insert(all.end(), ec[i].begin(), ec[i].end());
    EXPECT_EQ(ticks_of(i, t0), all) << "motor " << i;
  }
  EXPECT_EQ(positions(), pc);
}

// One coordinated move: the dominant motor steps at every profile step; the others' steps
// fall on those same ticks, evenly spread and centred, so every motor is done when the move
// ends: its steps after the last one it makes are under half of its own spacing, the same
// margin it starts with. A motor that makes more than half the dominant's steps (and every
// motor that makes as many) steps in the very last tick. A motor that runs on, or finishes
// early, fails this.
TEST(Stepper, CoordinatedMovesEndTogether) {
  sim::boot();
  const std::vector<Millideg> target = at_fractions(0.95, 0.15, 0.55);
  const std::vector<int32_t> from = positions(), to = quantized(target);
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(sim::command(m_line(target.data())), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  uint32_t n = 0;
  int dominant = 0;
  for (int i = 0; i < kJ; ++i)
    if (uint32_t(std::abs(to[i] - from[i])) > n) {
      n = uint32_t(std::abs(to[i] - from[i]));
      dominant = i;
    }
  const std::vector<uint64_t> ticks = ticks_of(dominant, t0);
  ASSERT_EQ(ticks.size(), n);
  const uint64_t end = ticks.back();
  for (int i = 0; i < kJ; ++i) {
    const std::vector<uint64_t> mine = ticks_of(i, t0);
    const uint32_t d = uint32_t(std::abs(to[i] - from[i]));
    ASSERT_EQ(mine.size(), d) << i;
    if (d == 0) continue;
    // Places of this motor's first and last step among the dominant's steps (1-based).
    const size_t first = size_t(std::find(ticks.begin(), ticks.end(), mine.front()) - ticks.begin()) + 1;
    const size_t last = size_t(std::find(ticks.begin(), ticks.end(), mine.back()) - ticks.begin()) + 1;
    ASSERT_LE(last, n) << i;  // on a dominant tick
    EXPECT_LE(mine.back(), end) << i;
    const double spacing = double(n) / d;
    EXPECT_LT(double(n - last), spacing / 2 + 1e-9) << "motor " << i << " finishes early";
    EXPECT_LE(std::abs(double(first - 1) - double(n - last)), 1.0) << "motor " << i << " not centred";
    if (2 * d > n) {
      EXPECT_EQ(mine.back(), end) << i;
    }
  }
  EXPECT_EQ(positions(), to);
}

TEST(Stepper, CoilsReleasedAfterTheIdleTimeAndEnergisedBeforeTheNextMove) {
  sim::boot();
  EXPECT_EQ(sim::status().coils, false);
  const size_t log0 = sitl::hw().coil_log.size();
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(sim::command("L 0 5"), "ok");
  // Energised (every motor, its current pattern) at the start, before the first step.
  ASSERT_GE(sitl::hw().coil_log.size(), log0 + kJ);
  for (int i = 0; i < kJ; ++i) {
    const sitl::CoilWrite& w = sitl::hw().coil_log[log0 + size_t(i)];
    EXPECT_EQ(w.motor, i);
    EXPECT_EQ(w.tick, t0);
    EXPECT_NE(w.pattern, 0);
    EXPECT_EQ(w.step, 0);
  }
  EXPECT_TRUE(sim::status().coils);
  ASSERT_TRUE(sim::run_until_at_rest());
  const uint64_t end = sim::steps_of(0).back().tick;
  // Still on just before the release time (2000 ms), off just after.
  const uint64_t release = 2000 * (sim::kSecond / 1000);
  ASSERT_TRUE(sim::run_until([&] { return sitl::hw().now + 4 * sim::kPollTicks >= end + release; }, 10 * sim::kSecond));
  EXPECT_TRUE(sim::status().coils);
  for (int i = 0; i < kJ; ++i) EXPECT_NE(sitl::hw().pattern[i], 0);
  ASSERT_TRUE(sim::run_until([&] { return sitl::hw().pattern[0] == 0; }, sim::kSecond));
  const uint64_t released = sitl::hw().now;
  // To the millisecond (millis() counts whole ones) and the main loop's pass.
  EXPECT_GE(released + 2000, end + release);
  EXPECT_LE(released, end + release + 2000 + 2 * sim::kPollTicks);
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(sitl::hw().pattern[i], 0);
  EXPECT_FALSE(sim::status().coils);
  // The next move writes the same patterns back (no step), then steps on from them.
  std::vector<int64_t> before(sitl::hw().position, sitl::hw().position + kJ);
  const size_t log1 = sitl::hw().coil_log.size();
  const uint64_t t1 = sitl::hw().now;
  ASSERT_EQ(sim::command("L 0 -5"), "ok");
  for (int i = 0; i < kJ; ++i) {
    const sitl::CoilWrite& w = sitl::hw().coil_log[log1 + size_t(i)];
    EXPECT_EQ(w.tick, t1);
    EXPECT_NE(w.pattern, 0);
    EXPECT_EQ(w.step, 0);
  }
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sitl::hw().position[0], before[0] - int64_t(sim::steps_of(0, t1).size()));
  EXPECT_EQ(sim::hal_errors(), "");
  // $2=0: never released.
  ASSERT_EQ(sim::command("$2=0"), "ok");
  ASSERT_EQ(sim::command("L 0 5"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  sim::run_until([] { return false; }, 70 * sim::kSecond);
  EXPECT_TRUE(sim::status().coils);
}

// Every step of a move is staged: its coils are written at its deadline before the firmware's
// step computation runs (sitl::step_deadline, as the Nano's HAL does first thing in the
// interrupt), every motor that steps on a deadline at that deadline. The set-up of a move
// from rest (kick) runs with interrupts enabled: the energising writes are not inside a
// critical section.
TEST(Stepper, MoveStepsAreStagedAndSetUpWithInterruptsOn) {
  sim::boot();
  ASSERT_EQ(sim::command("$0=4000"), "ok");
  ASSERT_EQ(sim::command("$1=100000"), "ok");
  const std::vector<Millideg> target = at_fractions(0.9, 0.1, 0.95);
  const size_t log0 = sitl::hw().coil_log.size();
  ASSERT_EQ(sim::command(m_line(target.data())), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  size_t steps = 0, energised = 0;
  for (size_t k = log0; k < sitl::hw().coil_log.size(); ++k) {
    const sitl::CoilWrite& w = sitl::hw().coil_log[k];
    if (w.step != 0) {
      ++steps;
      EXPECT_TRUE(w.staged) << "step " << k << " of motor " << int(w.motor) << " written by the step computation";
    } else if (w.pattern != 0) {
      ++energised;
      EXPECT_FALSE(w.staged);
      EXPECT_FALSE(w.interrupts_off) << "the move was set up with interrupts off";
    }
  }
  EXPECT_GT(steps, 100u);
  EXPECT_EQ(energised, size_t(kJ));
  EXPECT_EQ(positions(), quantized(target));
  EXPECT_EQ(sim::hal_errors(), "");
}

// '!' mid-move: from the next step on, the profile decelerates exactly as StepProfile::stop
// (the shared code, run here), the motors keep to their line, and the position the status
// report gives is where the pins left the motors.
TEST(Stepper, StopDeceleratesAsStepProfileStop) {
  for (double when : {0.08, 0.3, 0.6}) {  // accelerating, cruising, decelerating already
    sim::boot();
    const MotionSettings s = sim::motion_settings_from_listing();
    const std::vector<Millideg> target = at_fractions(0.95, 0.1, 0.8);
    const std::vector<int32_t> from = positions(), to = quantized(target);
    const uint64_t t0 = sitl::hw().now;
    ASSERT_EQ(sim::command(m_line(target.data())), "ok");
    uint32_t n = 0;
    for (int i = 0; i < kJ; ++i) n = std::max(n, uint32_t(std::abs(to[i] - from[i])));
    const uint64_t duration = profile_duration_ticks(n, s);
    ASSERT_TRUE(sim::run_until([&] { return sitl::hw().now >= t0 + uint64_t(when * double(duration)); }, 60 * sim::kSecond));
    const uint64_t t_stop = sitl::hw().now;
    sim::send("!");
    ASSERT_TRUE(sim::run_until_at_rest());
    const auto expected = expected_steps(from.data(), to.data(), t0, s, t_stop);
    for (int i = 0; i < kJ; ++i) EXPECT_EQ(ticks_of(i, t0), expected[i]) << "motor " << i << " stopped at " << when;
    const sim::Status st = sim::status();
    EXPECT_EQ(st.state, kStateIdle);
    for (int i = 0; i < kJ; ++i) {
      EXPECT_EQ(st.steps[i], from[i] + (to[i] > from[i] ? 1 : -1) * int32_t(expected[i].size())) << i;
      EXPECT_EQ(sitl::hw().position[i], st.steps[i]) << i;
    }
    if (when < 0.5) {
      EXPECT_NE(std::vector<int32_t>(st.steps, st.steps + kJ), to);  // it did stop short
    }
  }
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
