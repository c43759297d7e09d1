// Tests shared/articula/motion.h: settings validation, the trapezoid/triangle step-interval
// profile (shape, exact symmetry, physics against the analytic trapezoid, a double reference
// of the same recurrence, determinism, stop()), the overflow limits, and the Bresenham
// line stepper (exact counts, even and centred spreading, directions).
#include <articula/motion.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace articula;

namespace articula {
void PrintTo(MotionError e, std::ostream* os) { *os << int(e) << " (" << motion_error_text(e) << ")"; }
}  // namespace articula

namespace {

// The MK2 arm's base motor as the firmware will drive it: Timer1 at 16 MHz / 8.
const MotionSettings kMk2Base = {2000000, 1000, 4000};
// A spread of other valid settings: 16x microstepping, the 20-tick floor, a slow ramp,
// a 16 MHz timer, and a ramp shorter than two steps.
const MotionSettings kMicrostep = {2000000, 8000, 64000};
const MotionSettings kFloor = {2000000, 100000, 1000000};
const MotionSettings kSlow = {2000000, 500, 100};
const MotionSettings kFast16 = {16000000, 3000, 5000};
const MotionSettings kJerky = {2000000, 300, 40000};
const MotionSettings kAll[] = {kMk2Base, kMicrostep, kFloor, kSlow, kFast16, kJerky};

std::string name(const MotionSettings& s) {
  return "f=" + std::to_string(s.tick_hz) + " v=" + std::to_string(s.max_rate) + " a=" + std::to_string(s.accel);
}

std::vector<uint32_t> intervals(uint32_t n, const MotionSettings& s) {
  StepProfile p;
  p.start(n, s);
  std::vector<uint32_t> v;
  while (!p.done() && v.size() <= n) v.push_back(p.next_interval());
  return v;
}

uint64_t sum(const std::vector<uint32_t>& v) {
  uint64_t t = 0;
  for (uint32_t x : v) t += x;
  return t;
}

// Independent of motion.h: the figures of the ideal motion, in double.
double cruise_ticks(const MotionSettings& s) { return std::round(double(s.tick_hz) / s.max_rate); }
double ideal_c0(const MotionSettings& s) { return s.tick_hz * std::sqrt(2.0 / s.accel); }
double ramp_steps(const MotionSettings& s) { return double(s.max_rate) * s.max_rate / (2.0 * s.accel); }
// Rest to rest over n steps at accel a, top speed v: trapezoid n/v + v/a, or triangle 2 sqrt(n/a).
double analytic_seconds(uint32_t n, const MotionSettings& s) {
  const double v = s.max_rate, a = s.accel;
  return n >= v * v / a ? n / v + v / a : 2.0 * std::sqrt(n / a);
}

// The same recurrence in double, without fixed point or remainders: c0' = 0.675978 c0,
// c_n = c_{n-1} (4n - 1) / (4n + 1), the first interval c0, cruise once c_n < cruise, the
// middle step, the mirror. Each interval rounded to whole ticks.
std::vector<uint32_t> reference(uint32_t n, const MotionSettings& s) {
  const double cruise = cruise_ticks(s);
  const double first = std::max(std::round(ideal_c0(s)), cruise);
  std::vector<double> ramp = {ideal_c0(s) * std::tgamma(0.75) / (2.0 * std::tgamma(1.25))};
  std::vector<uint32_t> out(n);
  uint32_t lo = 0, hi = n;  // fill from both ends
  size_t level = 0;         // ramp[level] is the next climbing value
  while (lo < hi) {
    const double c = level == 0 ? first : ramp[level];
    const bool cruising = level > 0 && c < cruise;
    if (cruising) {
      out[lo++] = uint32_t(cruise);
      continue;
    }
    if (hi - lo == 1) {  // the middle step
      out[lo++] = uint32_t(level == 0 ? c : std::round(c));
      break;
    }
    out[lo++] = out[--hi] = uint32_t(level == 0 ? c : std::round(c));
    ++level;
    ramp.push_back(ramp.back() * (4.0 * level - 1) / (4.0 * level + 1));
  }
  return out;
}

// ---------------------------------------------------------------------------------------
TEST(MotionValidate, AcceptsTheFirmwareSettingsAndRejectsEachProblem) {
  for (const MotionSettings& s : kAll) EXPECT_EQ(validate(s), kMotionOk) << name(s);
  EXPECT_EQ(validate(MotionSettings{0, 1000, 4000}), kMotionZero);
  EXPECT_EQ(validate(MotionSettings{2000000, 0, 4000}), kMotionZero);
  EXPECT_EQ(validate(MotionSettings{2000000, 1000, 0}), kMotionZero);
  // The timer runs at most at the Nano's 16 MHz clock.
  EXPECT_EQ(validate(MotionSettings{16000000, 1000, 4000}), kMotionOk);
  EXPECT_EQ(validate(MotionSettings{16000001, 1000, 4000}), kMotionTickTooFast);
  // The 20-tick floor on round(f / v): 2e6 / 102564 = 19.50004 rounds to 20, 2e6 / 102565
  // = 19.4998 to 19.
  EXPECT_EQ(validate(MotionSettings{2000000, 102564, 4000000}), kMotionOk);
  EXPECT_EQ(validate(MotionSettings{2000000, 102565, 4000000}), kMotionTooFast);
  // Longest cruise interval 2^22 ticks: 2^23 / 2 is, 8388611 / 2 = 4194305.5 is not.
  EXPECT_EQ(validate(MotionSettings{8388608, 2, 1000}), kMotionOk);
  EXPECT_EQ(validate(MotionSettings{8388611, 2, 1000}), kMotionTooSlow);
  // Longest first interval: f^2 / a below 2^43 (c0 below 2^22 ticks).
  EXPECT_EQ(validate(MotionSettings{2000000, 1000, 1}), kMotionOk);
  EXPECT_EQ(validate(MotionSettings{4000000, 1000, 1}), kMotionTooSlow);
  EXPECT_EQ(validate(MotionSettings{4000000, 1000, 2}), kMotionOk);
  // Longest ramp: c0 below 2^13 cruise intervals (a ramp below 2^24 steps). At 2 MHz and
  // a = 1, 256 c0 = 724077343 and 724077343 >> 21 = 345: a cruise of 346 ticks (v = 5788)
  // is fine, 345 (v = 5789) is not.
  EXPECT_EQ(validate(MotionSettings{2000000, 5788, 1}), kMotionOk);
  EXPECT_EQ(validate(MotionSettings{2000000, 5789, 1}), kMotionRampTooLong);
  EXPECT_GT(ramp_steps(MotionSettings{2000000, 5789, 1}), 16.7e6);
  // Every error has its own text.
  std::set<std::string> texts;
  for (int e = kMotionOk; e <= kMotionRampTooLong; ++e) {
    const std::string t = motion_error_text(MotionError(e));
    EXPECT_FALSE(t.empty());
    EXPECT_NE(t, "?");
    texts.insert(t);
  }
  EXPECT_EQ(texts.size(), size_t(kMotionRampTooLong) + 1);
  EXPECT_EQ(std::string(motion_error_text(MotionError(99))), "?");
}

TEST(StepProfile, InvalidSettingsGiveAnEmptyMove) {
  StepProfile p;
  p.start(1000, MotionSettings{2000000, 0, 4000});
  EXPECT_TRUE(p.done());
  EXPECT_EQ(p.next_interval(), 0u);
  EXPECT_EQ(p.steps_left(), 0u);
}

TEST(StepProfile, ZeroOneTwoThreeSteps) {
  const uint32_t c0 = uint32_t(std::lround(ideal_c0(kMk2Base)));  // 44721: 2e6 sqrt(2 / 4000)
  EXPECT_EQ(c0, 44721u);
  StepProfile p;
  p.start(0, kMk2Base);
  EXPECT_TRUE(p.done());
  EXPECT_EQ(p.next_interval(), 0u);
  EXPECT_EQ(intervals(1, kMk2Base), std::vector<uint32_t>({c0}));
  // Two steps: accelerate to the first, decelerate to rest at the second: c0 both times.
  EXPECT_EQ(intervals(2, kMk2Base), std::vector<uint32_t>({c0, c0}));
  const std::vector<uint32_t> three = intervals(3, kMk2Base);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_EQ(three[0], c0);
  EXPECT_EQ(three[2], c0);
  EXPECT_LT(three[1], c0);
  // Done stays done.
  p.start(2, kMk2Base);
  p.next_interval();
  p.next_interval();
  EXPECT_TRUE(p.done());
  EXPECT_EQ(p.next_interval(), 0u);
  EXPECT_EQ(p.steps_left(), 0u);
}

// Pins the firmware's numbers: the host's predictions and a flashed Nano must agree, so a
// change of formula has to be deliberate. 44721 = round(2e6 sqrt(2/4000)); 18138 =
// 0.6 * 0.675978 * 44721.36; 14108 = 18138.2 * 7/9 (rounded); cruise 2000 = 2e6 / 1000.
TEST(StepProfile, Mk2BaseFirstIntervalsArePinned) {
  const std::vector<uint32_t> v = intervals(1000, kMk2Base);
  const std::vector<uint32_t> head(v.begin(), v.begin() + 6);
  EXPECT_EQ(head, std::vector<uint32_t>({44721, 18138, 14108, 11937, 10533, 9530}));
  EXPECT_EQ(v[500], 2000u);
  EXPECT_EQ(sum(v), 2498762u);
}

TEST(StepProfile, ShapeForEveryLengthUpTo600) {
  for (const MotionSettings& s : kAll) {
    const uint32_t cruise = uint32_t(cruise_ticks(s));
    for (uint32_t n = 0; n <= 600; ++n) {
      const std::vector<uint32_t> v = intervals(n, s);
      ASSERT_EQ(v.size(), n) << name(s);
      for (uint32_t i = 0; i < n; ++i) {
        ASSERT_GE(v[i], cruise) << name(s) << " n=" << n << " i=" << i;
        // Exactly symmetric: the deceleration replays the acceleration.
        ASSERT_EQ(v[i], v[n - 1 - i]) << name(s) << " n=" << n << " i=" << i;
        // Non-increasing up to the middle, so (by symmetry) non-decreasing after it.
        if (i + 1 <= (n - 1) / 2) {
          ASSERT_GE(v[i], v[i + 1]) << name(s) << " n=" << n << " i=" << i;
        }
      }
    }
  }
}

TEST(StepProfile, LongMovesCruiseShortMovesAreTriangles) {
  for (const MotionSettings& s : kAll) {
    const double ramp = ramp_steps(s);
    const uint32_t cruise = uint32_t(cruise_ticks(s));
    // Long: ten ramps' worth. The middle runs at the cruise interval, and the ramp level
    // there (what a stop would take) is v^2 / (2a).
    const uint32_t n = uint32_t(std::max(1000.0, 20 * ramp));
    StepProfile p;
    p.start(n, s);
    std::vector<uint32_t> v;
    uint32_t level_mid = 0;
    while (!p.done()) {
      if (v.size() == n / 2) level_mid = p.stop_steps();
      v.push_back(p.next_interval());
    }
    EXPECT_EQ(v[n / 2], cruise) << name(s);
    EXPECT_NEAR(level_mid, ramp, 0.02 * ramp + 1.5) << name(s);
    const size_t at_cruise = size_t(std::count(v.begin(), v.end(), cruise));
    EXPECT_GE(at_cruise, n - 2 * (1.03 * ramp + 2)) << name(s);
    // Short: half a ramp each way never reaches the top speed; the peak is sqrt(a n).
    if (ramp < 40) continue;
    const uint32_t m = uint32_t(ramp);
    const std::vector<uint32_t> t = intervals(m, s);
    const uint32_t peak = *std::min_element(t.begin(), t.end());
    EXPECT_GT(peak, cruise) << name(s);
    EXPECT_NEAR(double(s.tick_hz) / peak, std::sqrt(double(s.accel) * m), 0.02 * std::sqrt(double(s.accel) * m))
        << name(s);
  }
}

TEST(StepProfile, DurationMatchesTheAnalyticTrapezoid) {
  for (const MotionSettings& s : kAll) {
    const double ramp = ramp_steps(s);
    for (double k : {2.5, 5.0, 20.0}) {  // moves of 2.5, 5 and 20 ramps' worth of steps
      const uint32_t n = uint32_t(std::max(200.0, k * 2 * ramp));
      const double t = double(profile_duration_ticks(n, s)) / s.tick_hz;
      EXPECT_NEAR(t, analytic_seconds(n, s), 0.01 * analytic_seconds(n, s)) << name(s) << " n=" << n;
    }
    // Triangles from 20 steps on, within 2 %.
    for (uint32_t n : {20u, 50u, 100u}) {
      if (n >= 2 * ramp) continue;
      const double t = double(profile_duration_ticks(n, s)) / s.tick_hz;
      EXPECT_NEAR(t, analytic_seconds(n, s), 0.02 * analytic_seconds(n, s)) << name(s) << " n=" << n;
    }
  }
}

TEST(StepProfile, StepTimesFollowTheIdealRamp) {
  // Every step of the climb comes within 0.015 c0 (plus the half-tick rounding of each
  // interval) of t_k = c0 sqrt(k), the time of constant acceleration from rest.
  for (const MotionSettings& s : {kMk2Base, kMicrostep, kSlow, kFast16}) {
    const double c0 = ideal_c0(s);
    const uint32_t n = uint32_t(4 * ramp_steps(s));
    StepProfile p;
    p.start(n, s);
    double t = 0;
    for (uint32_t k = 1; k < ramp_steps(s); ++k) {
      t += p.next_interval();
      ASSERT_NEAR(t, c0 * std::sqrt(double(k)), 0.015 * c0 + 0.5 * k) << name(s) << " k=" << k;
    }
  }
}

TEST(StepProfile, ImpliedAccelerationMatchesAccel) {
  // The acceleration between the mean speeds of two neighbouring windows of w steps, from
  // the step times: exact for constant acceleration. Windows of 1/16 of the ramp: single
  // intervals near the top speed change by under a tick, so whole-tick rounding would
  // swamp a step-by-step estimate. Not at the 20-tick floor (kFloor): there the timer
  // itself only has speeds f/20, f/21, ... 5 % apart, and the ramp holds each for hundreds
  // of steps (between 20.5 and 21.5 ticks: 430 steps), so no window sees a smooth ramp.
  for (const MotionSettings& s : kAll) {
    const double ramp = ramp_steps(s);
    if (ramp < 64 || cruise_ticks(s) < 100) continue;
    const uint32_t w = uint32_t(ramp / 16);
    std::vector<double> t = {0};
    StepProfile p;
    p.start(uint32_t(4 * ramp), s);
    while (!p.done()) t.push_back(t.back() + double(p.next_interval()) / s.tick_hz);
    double worst = 0;
    for (uint32_t k = w + 2; k + w <= uint32_t(ramp * 0.98); ++k) {
      const double v1 = w / (t[k] - t[k - w]), v2 = w / (t[k + w] - t[k]);
      const double a = (v2 - v1) / ((t[k + w] - t[k - w]) / 2);
      worst = std::max(worst, std::fabs(a / s.accel - 1));
    }
    EXPECT_LT(worst, 0.05) << name(s);
    std::cout << "[ figures  ] " << name(s) << ": implied acceleration within " << 100 * worst
              << " % over the ramp (windows of " << w << " steps)\n";
  }
}

TEST(StepProfile, MatchesADoubleReferenceOfTheSameRecurrence) {
  for (const MotionSettings& s : {kMk2Base, kMicrostep, kSlow, kFast16, kJerky}) {
    for (uint32_t n : {1u, 2u, 3u, 7u, 50u, 251u, 1000u, 5001u}) {
      const std::vector<uint32_t> v = intervals(n, s), r = reference(n, s);
      ASSERT_EQ(v.size(), r.size());
      for (uint32_t i = 0; i < n; ++i)
        ASSERT_NEAR(double(v[i]), double(r[i]), 1.0) << name(s) << " n=" << n << " i=" << i;
    }
  }
}

TEST(StepProfile, DeterministicAndTheHelpersAgree) {
  for (const MotionSettings& s : kAll) {
    for (uint32_t n : {0u, 1u, 5u, 99u, 1234u}) {
      const std::vector<uint32_t> a = intervals(n, s), b = intervals(n, s);
      EXPECT_EQ(a, b);
      // A reused profile restarts cleanly.
      StepProfile p;
      p.start(77, s);
      for (int i = 0; i < 30; ++i) p.next_interval();
      p.start(n, s);
      std::vector<uint32_t> c;
      while (!p.done()) c.push_back(p.next_interval());
      EXPECT_EQ(a, c);
      EXPECT_EQ(profile_duration_ticks(n, s), sum(a));
      std::vector<uint64_t> times(n + 3, 0);
      ASSERT_EQ(profile_step_times(times.data(), n + 3, n, s), n);
      uint64_t t = 0;
      for (uint32_t i = 0; i < n; ++i) EXPECT_EQ(times[i], t += a[i]);
      if (n > 2) {
        std::vector<uint64_t> few(2, 0);
        EXPECT_EQ(profile_step_times(few.data(), 2, n, s), 2u);
        EXPECT_EQ(few[1], uint64_t(a[0]) + a[1]);
      }
    }
  }
}

// The firmware starts moves in its step interrupt from constants it computed beforehand:
// the same intervals as starting from the settings, for every length, after a stop too.
TEST(StepProfile, StartFromPrecomputedConstantsIsTheSame) {
  for (const MotionSettings& s : kAll) {
    ProfileConstants k;
    ASSERT_EQ(profile_constants(k, s), kMotionOk) << name(s);
    EXPECT_EQ(k.cruise, uint32_t(cruise_ticks(s))) << name(s);
    EXPECT_NEAR(double(k.first), std::max(ideal_c0(s), cruise_ticks(s)), 0.5) << name(s);
    EXPECT_NEAR(k.c0r / 256.0, 0.675978 * ideal_c0(s), 0.01 * ideal_c0(s) / 256 + 1) << name(s);
    for (uint32_t n : {0u, 1u, 2u, 3u, 7u, 100u, 2345u}) {
      for (uint32_t stop_at : {0u, 1u, 2u, 50u, 100000u}) {
        StepProfile a, b;
        a.start(n, s);
        b.start(77, s);  // reused: the start must reset everything
        b.next_interval();
        b.start(n, k);
        for (uint32_t i = 0; !a.done() || !b.done(); ++i) {
          if (i == stop_at) {
            a.stop();
            b.stop();
          }
          ASSERT_EQ(a.done(), b.done());
          ASSERT_EQ(a.next_interval(), b.next_interval()) << name(s) << " n=" << n << " step " << i;
        }
      }
    }
  }
  // Invalid settings: all zero, and an empty move.
  ProfileConstants k;
  EXPECT_EQ(profile_constants(k, MotionSettings{2000000, 0, 4000}), kMotionZero);
  EXPECT_EQ(k.cruise, 0u);
  EXPECT_EQ(k.first, 0u);
  EXPECT_EQ(k.c0r, 0u);
  EXPECT_EQ(profile_constants(k, MotionSettings{2000000, 5789, 1}), kMotionRampTooLong);
  EXPECT_EQ(k.cruise, 0u);
  StepProfile p;
  p.start(1000, k);
  EXPECT_TRUE(p.done());
  EXPECT_EQ(p.next_interval(), 0u);
}

// Runs n steps, stops after `before` of them, returns the intervals after the stop.
std::vector<uint32_t> stop_after(uint32_t n, uint32_t before, const MotionSettings& s, std::vector<uint32_t>* head,
                                 uint32_t* predicted) {
  StepProfile p;
  p.start(n, s);
  for (uint32_t i = 0; i < before; ++i) head->push_back(p.next_interval());
  *predicted = p.stop_steps();
  p.stop();
  std::vector<uint32_t> tail;
  while (!p.done()) tail.push_back(p.next_interval());
  return tail;
}

TEST(StepProfile, StopMidCruiseAndMidAcceleration) {
  for (const MotionSettings& s : kAll) {
    const double ramp = ramp_steps(s);
    const uint32_t n = uint32_t(std::max(1000.0, 10 * ramp));
    for (double frac : {0.5, 0.3, 0.1, 0.02}) {  // cruise, cruise, accelerating, accelerating
      const uint32_t before = std::max<uint32_t>(1, uint32_t(frac * n));
      std::vector<uint32_t> head;
      uint32_t predicted = 0;
      const std::vector<uint32_t> tail = stop_after(n, before, s, &head, &predicted);
      ASSERT_FALSE(tail.empty()) << name(s);
      EXPECT_EQ(tail.size(), predicted) << name(s);
      // From the speed at the stop, v_now^2 / (2a) steps (the current level).
      const double v_now = double(s.tick_hz) / head.back();
      const double expected = v_now * v_now / (2.0 * s.accel);
      EXPECT_NEAR(double(tail.size()), expected, 0.05 * expected + 2) << name(s) << " before=" << before;
      // Never faster than before the stop, slowing all the way, ending at the first interval.
      EXPECT_GE(tail.front(), head.back()) << name(s);
      for (size_t i = 1; i < tail.size(); ++i) ASSERT_GE(tail[i], tail[i - 1]) << name(s) << " i=" << i;
      EXPECT_EQ(tail.back(), head.front()) << name(s);
      // The descent replays the climb: tail[j] == head[tail.size() - 1 - j].
      for (size_t j = 0; j < tail.size(); ++j) ASSERT_EQ(tail[j], head[tail.size() - 1 - j]) << name(s);
    }
  }
}

TEST(StepProfile, StopEdgeCases) {
  // Before the first step: the motor is at rest, nothing more to do.
  StepProfile p;
  p.start(1000, kMk2Base);
  EXPECT_EQ(p.stop_steps(), 0u);
  p.stop();
  EXPECT_TRUE(p.done());
  // While decelerating: no change, and stop() twice is stop() once.
  const std::vector<uint32_t> full = intervals(1000, kMk2Base);
  p.start(1000, kMk2Base);
  std::vector<uint32_t> got;
  for (int i = 0; i < 950; ++i) got.push_back(p.next_interval());
  p.stop();
  p.stop();
  while (!p.done()) got.push_back(p.next_interval());
  EXPECT_EQ(got, full);
  // At the middle of a triangle (odd and even): still symmetric and ends at rest.
  for (uint32_t n : {51u, 52u}) {
    const std::vector<uint32_t> tri = intervals(n, kMk2Base);
    p.start(n, kMk2Base);
    got.clear();
    for (uint32_t i = 0; i < n / 2; ++i) got.push_back(p.next_interval());
    p.stop();
    p.stop();
    while (!p.done()) got.push_back(p.next_interval());
    EXPECT_EQ(got.size(), n - n % 2) << n;
    for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], got[got.size() - 1 - i]) << n;
  }
}

// The worst case validate() allows at once: a first interval just below 2^22 ticks (f^2 / a
// just below 2^43) and a ramp just below 2^24 steps (256 c0 >> 21 = 511, cruise 512), run to
// the end (33.5 million steps) with streaming checks.
TEST(StepProfile, LimitsDoNotOverflow) {
  const MotionSettings s = {2965820, 5792, 1};
  ASSERT_EQ(validate(s), kMotionOk);
  const double ramp = ramp_steps(s);
  ASSERT_GT(ramp, 16.7e6);
  const uint32_t n = uint32_t(2 * ramp + 1000);
  const uint32_t cruise = uint32_t(cruise_ticks(s));
  StepProfile p;
  p.start(n, s);
  std::vector<uint64_t> sample_head, sample_tail;  // times of steps k and n - k, k = 4096 j
  uint64_t t = 0;
  uint32_t prev = 0;
  uint32_t mid = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t c = p.next_interval();
    ASSERT_GE(c, cruise) << i;
    if (i > 0 && i <= (n - 1) / 2) {
      ASSERT_LE(c, prev) << i;
    }
    if (i > n / 2 + 1) {
      ASSERT_GE(c, prev) << i;
    }
    if (i == n / 2) mid = c;
    prev = c;
    if (i % 4096 == 0) sample_head.push_back(t);  // time of step i (0 for the start)
    t += c;
    if ((n - 1 - i) % 4096 == 0) sample_tail.push_back(t);  // time of step i + 1 = n - 4096 j
  }
  EXPECT_TRUE(p.done());
  EXPECT_EQ(mid, cruise);
  // Symmetry: step k at t_k, step n - k at T - t_k.
  ASSERT_EQ(sample_head.size(), sample_tail.size());
  for (size_t j = 0; j < sample_head.size(); ++j)
    ASSERT_EQ(sample_head[j], t - sample_tail[sample_tail.size() - 1 - j]) << j;
  EXPECT_NEAR(double(t) / s.tick_hz, analytic_seconds(n, s), 0.01 * analytic_seconds(n, s));
}

TEST(StepProfile, PrintsTheMk2BaseFigures) {
  std::cout << "[ figures  ] MK2 base, 2 MHz ticks, max_rate 1000 steps/s, accel 4000 steps/s^2: first interval "
            << intervals(1, kMk2Base)[0] << " ticks, cruise " << intervals(1000, kMk2Base)[500] << " ticks, ramp "
            << ramp_steps(kMk2Base) << " steps\n";
  for (uint32_t n : {100u, 1000u}) {
    const double t = double(profile_duration_ticks(n, kMk2Base)) / kMk2Base.tick_hz;
    const double a = analytic_seconds(n, kMk2Base);
    std::cout << "[ figures  ] MK2 base, " << n << "-step move: " << t << " s, analytic " << a << " s ("
              << 100 * (t - a) / a << " %)\n";
    EXPECT_NEAR(t, a, 0.01 * a);
  }
}

// ---------------------------------------------------------------------------------------
template <int J>
void check_line(const std::vector<int32_t>& delta) {
  LineStepper<J> line;
  const uint8_t motors = uint8_t(delta.size());
  line.start(delta.data(), motors);
  uint32_t n = 0;
  for (int32_t d : delta) n = std::max<uint32_t>(n, uint32_t(std::abs(d)));
  ASSERT_EQ(line.dominant, n);
  std::vector<std::vector<uint32_t>> at(motors);  // the calls (1-based) each motor steps on
  for (uint32_t k = 1; k <= n; ++k) {
    ASSERT_FALSE(line.done());
    const uint8_t mask = line.next();
    ASSERT_EQ(mask >> motors, 0) << "bits only for the motors in use";
    for (uint8_t i = 0; i < motors; ++i)
      if (mask & (1u << i)) at[i].push_back(k);
  }
  EXPECT_TRUE(line.done());
  EXPECT_EQ(line.next(), 0);
  for (uint8_t i = 0; i < motors; ++i) {
    const uint32_t d = uint32_t(std::abs(delta[i]));
    SCOPED_TRACE("motor " + std::to_string(i) + " delta " + std::to_string(delta[i]) + " n " + std::to_string(n));
    EXPECT_EQ(bool(line.negative & (1u << i)), delta[i] < 0);
    ASSERT_EQ(at[i].size(), d);
    if (d == 0) continue;
    const double ideal = double(n) / d;
    for (size_t j = 1; j < d; ++j) {
      const double gap = at[i][j] - at[i][j - 1];
      ASSERT_LE(std::fabs(gap - ideal), 1.0) << j;
      ASSERT_TRUE(gap == std::floor(ideal) || gap == std::ceil(ideal)) << j;
    }
    // Centred: the idle calls before the first step and after the last differ by at most 1.
    const double before = at[i].front() - 1.0, after = double(n) - at[i].back();
    EXPECT_LE(std::fabs(before - after), 1.0);
  }
  // Equal |deltas| step together.
  for (uint8_t i = 0; i < motors; ++i)
    for (uint8_t j = 0; j < motors; ++j)
      if (std::abs(delta[i]) == std::abs(delta[j])) {
        EXPECT_EQ(at[i], at[j]);
      }
}

TEST(LineStepper, FixedCases) {
  check_line<3>({0, 0, 0});
  check_line<3>({5, 0, 0});
  check_line<3>({0, -17, 0});
  check_line<3>({300, 300, -300});
  check_line<3>({1000, -1, 999});
  check_line<3>({-7, 3, 2});
  check_line<3>({1, 1, 0});
  check_line<1>({-4});
  check_line<8>({100, -99, 50, -49, 33, 1, 0, -100});
}

TEST(LineStepper, RandomDeltas) {
  std::mt19937 rng(20261121);
  std::uniform_int_distribution<int32_t> big(-3000, 3000), small(-6, 6), which(0, 5);
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<int32_t> d(3);
    for (int32_t& x : d) {
      switch (which(rng)) {
        case 0: x = 0; break;
        case 1: x = small(rng); break;
        default: x = big(rng); break;
      }
    }
    if (trial % 10 == 1) d[1] = d[2] = d[0];        // equal
    if (trial % 10 == 2) d[1] = -d[0];              // equal and opposite
    if (trial % 10 == 3) d[0] = d[2] = 0;           // one axis only
    check_line<3>(d);
  }
}

TEST(LineStepper, ExtremeDeltasDoNotOverflow) {
  const int32_t delta[3] = {std::numeric_limits<int32_t>::min(), std::numeric_limits<int32_t>::max(), 1};
  LineStepper<3> line;
  line.start(delta, 3);
  EXPECT_EQ(line.dominant, 2147483648u);
  EXPECT_EQ(line.count[0], 2147483648u);
  EXPECT_EQ(line.negative, 1);
  // n = 2^31: motor 1 (2^31 - 1 steps) misses one step, in the middle; motor 2 steps once,
  // in the middle. The first calls: motors 0 and 1 step.
  for (int k = 0; k < 3; ++k) EXPECT_EQ(line.next(), 3) << k;
}

TEST(LineStepper, DrivesAProfileTogether) {
  // The firmware's loop in miniature: one profile of n intervals, one mask per interval.
  const int32_t delta[3] = {-250, 1000, 37};
  LineStepper<3> line;
  line.start(delta, 3);
  StepProfile p;
  p.start(line.dominant, kMk2Base);
  int32_t pos[3] = {0, 0, 0};
  uint64_t t = 0;
  while (!p.done()) {
    t += p.next_interval();
    const uint8_t mask = line.next();
    for (int i = 0; i < 3; ++i)
      if (mask & (1u << i)) pos[i] += (line.negative & (1u << i)) ? -1 : 1;
  }
  EXPECT_TRUE(line.done());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(pos[i], delta[i]);
  EXPECT_EQ(t, profile_duration_ticks(1000, kMk2Base));
}

}  // namespace

// The planner's level cap is floor(floor(15 r^2 / 32) / accel) - 1 for every cruise rate r a
// 16-bit rate can be, far beyond 16,921 steps/s where r^2 * 15 leaves 32 bits (the old
// formula's limit), at the accelerations the settings allow.
TEST(LevelCap, IsExactForEveryRateBelow65536) {
  for (uint32_t accel : {1u, 1000u, 100000u, 1000000u}) {
    const MotionSettings s{kStepTickHz, 4000, accel};
    for (uint32_t cruise = kMinStepTicks; cruise < 4000; ++cruise) {  // r = 100,000 .. 500 steps/s
      const uint32_t r = kStepTickHz / cruise;
      if (r > 0xFFFF) continue;
      const uint64_t n = uint64_t(r) * r * 15 / 32 / accel;
      const uint16_t want = n == 0 ? 0 : n > 0xFFFF ? 0xFFFF : uint16_t(n - 1);
      ASSERT_EQ(cruise_level_cap(s, 1, cruise), want) << "r " << r << " steps/s, accel " << accel;
    }
  }
  // every r itself, on a 16 MHz tick (cruise 256 .. 32,000: r = 62,500 .. 500)
  const MotionSettings s16{16000000, 4000, 40000};
  for (uint32_t cruise = 245; cruise < 40000; ++cruise) {
    const uint32_t r = s16.tick_hz / cruise;
    const uint64_t n = uint64_t(r) * r * 15 / 32 / s16.accel;
    ASSERT_EQ(cruise_level_cap(s16, 1, cruise), n == 0 ? 0 : n > 0xFFFF ? 0xFFFF : uint16_t(n - 1)) << "r " << r;
  }
  // where the old formula wrapped: 30,000 and 40,000 steps/s at 100,000 steps/s^2
  const MotionSettings fast{kStepTickHz, 40000, 100000};
  EXPECT_EQ(cruise_level_cap(fast, 1, kStepTickHz / 30000), uint16_t(uint64_t(30303) * 30303 * 15 / 32 / 100000 - 1));
  EXPECT_EQ(cruise_level_cap(fast, 1, kStepTickHz / 40000), uint16_t(uint64_t(40000) * 40000 * 15 / 32 / 100000 - 1));
}
