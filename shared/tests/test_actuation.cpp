// Tests shared/articula/actuation.h: step quantization and its rounding rule, the whole-step
// limit range, drift-free relative moves, the all-or-nothing state updates, the coupling
// inverse (MK2 parallelogram), motor validation, to_millideg, float vs double.
#include <articula/actuation.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <string>

using namespace articula;

namespace articula {
// Readable failure messages (uint8_t enums would print as characters).
void PrintTo(Status s, std::ostream* os) { *os << int(s) << " (" << status_name(s) << ")"; }
void PrintTo(MotorError e, std::ostream* os) { *os << int(e) << " (" << motor_error_text(e) << ")"; }
}  // namespace articula

namespace {

// The MK2 arm's motors (1.8 deg steppers, full steps), millidegrees.
const MotorSpec kBase = {200, 1, 1, 108, 19, 0, -90000, 90000};
const MotorSpec kShoulder = {200, 1, 1, 47, 19, 90000, 36000, 130000};
const MotorSpec kElbow = {200, 1, 1, 47, 19, 0, -43000, 15000};
// 1:1 gear, 200 steps: 1.8 deg a step, so 0.9 deg is exactly half a step.
const MotorSpec kDirect = {200, 1, 1, 1, 1, 0, -180000, 180000};

// The degrees per step worked out by hand: 360 deg * 19 / (200 * 108), 360 * 19 / (200 * 47).
constexpr double kBaseDegPerStep = 6840.0 / 21600.0;  // 0.31666...
constexpr double kArmDegPerStep = 6840.0 / 9400.0;    // 0.72765957...

Actuation<double, 3> mk2() {
  Actuation<double, 3> a{};
  a.num_motors = 3;
  a.motors[0] = kBase;
  a.motors[1] = kShoulder;
  a.motors[2] = kElbow;
  const double c[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, -1, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.coupling[i][j] = c[i][j];
  return a;
}

MotorSpec with_direction(MotorSpec m, int8_t dir) {
  m.direction = dir;
  return m;
}

// Exact rational comparison of the angle of step s with a limit, all in integers:
// angle(s) = zero + dir * s * 360000 * den / (steps_per_rev * microsteps * num) millideg.
// Returns the sign of angle(s) - limit_mdeg.
int compare_step_angle(const MotorSpec& m, int64_t s, int64_t limit_mdeg) {
  const int64_t num = int64_t(m.full_steps_per_rev) * m.microsteps * m.gear_num;
  const int64_t lhs = int64_t(m.direction) * s * 360000 * m.gear_den;  // (angle - zero) * num
  const int64_t rhs = (limit_mdeg - m.zero) * num;
  return lhs < rhs ? -1 : (lhs > rhs ? 1 : 0);
}

}  // namespace

TEST(Actuation, DegreesPerStep) {
  EXPECT_NEAR(degrees_per_step<double>(kBase), 0.3166666666666667, 1e-15);
  EXPECT_NEAR(degrees_per_step<double>(kBase), kBaseDegPerStep, 1e-15);
  EXPECT_NEAR(degrees_per_step<double>(kShoulder), kArmDegPerStep, 1e-15);
  EXPECT_NEAR(degrees_per_step<double>(kElbow), 0.7276595744680851, 1e-15);
  EXPECT_DOUBLE_EQ(degrees_per_step<double>(kDirect), 1.8);
  MotorSpec half = kBase;
  half.microsteps = 2;
  EXPECT_NEAR(degrees_per_step<double>(half), kBaseDegPerStep / 2, 1e-15);
  half = kShoulder;
  half.microsteps = 16;
  EXPECT_NEAR(degrees_per_step<double>(half), kArmDegPerStep / 16, 1e-15);
}

TEST(Actuation, QuantizeHandComputed) {
  // Base: steps = a * 21600 / (360000 * 19) = 3a / 950 (a in millidegrees).
  EXPECT_EQ(quantize(kBase, 10000), 32);    // 31.58
  EXPECT_EQ(quantize(kBase, -10000), -32);  // -31.58
  EXPECT_EQ(quantize(kBase, 90000), 284);   // 284.21
  EXPECT_EQ(quantize(kBase, 0), 0);
  EXPECT_EQ(quantize(kBase, 158), 0);   // 0.4989
  EXPECT_EQ(quantize(kBase, 159), 1);   // 0.5021
  EXPECT_EQ(quantize(kBase, 474), 1);   // 1.4968
  EXPECT_EQ(quantize(kBase, 475), 2);   // 1.5 exactly: away from zero
  EXPECT_EQ(quantize(kBase, -475), -2);
  EXPECT_EQ(quantize(kBase, -474), -1);
  // Shoulder: steps = (a - 90000) * 47 / 34200.
  EXPECT_EQ(quantize(kShoulder, 90000), 0);
  EXPECT_EQ(quantize(kShoulder, 100000), 14);  // 13.74
  EXPECT_EQ(quantize(kShoulder, 36000), -74);  // -74.21
  EXPECT_EQ(quantize(kShoulder, 130000), 55);  // 54.97
  // 1.8 deg steps: exact halves.
  EXPECT_EQ(quantize(kDirect, 900), 1);
  EXPECT_EQ(quantize(kDirect, -900), -1);
  EXPECT_EQ(quantize(kDirect, 899), 0);
  EXPECT_EQ(quantize(kDirect, -899), 0);
  EXPECT_EQ(quantize(kDirect, 2700), 2);  // 1.5
  EXPECT_EQ(quantize(kDirect, -2700), -2);
  EXPECT_EQ(quantize(kDirect, 1800), 1);
  EXPECT_EQ(quantize(kDirect, 4500), 3);  // 2.5
}

TEST(Actuation, QuantizeDirectionAndZero) {
  const MotorSpec rev = with_direction(kDirect, -1);
  EXPECT_EQ(quantize(rev, 900), -1);
  EXPECT_EQ(quantize(rev, -900), 1);
  EXPECT_EQ(quantize(rev, 899), 0);
  EXPECT_EQ(quantize(rev, 3600), -2);
  MotorSpec offset = kDirect;
  offset.zero = 10000;  // step 0 at 10 deg
  EXPECT_EQ(quantize(offset, 10000), 0);
  EXPECT_EQ(quantize(offset, 10900), 1);
  EXPECT_EQ(quantize(offset, 9100), -1);
  EXPECT_EQ(quantize(offset, 10899), 0);
  EXPECT_EQ(quantize(offset, 0), -6);  // -10 / 1.8 = -5.56
  offset.direction = -1;
  EXPECT_EQ(quantize(offset, 0), 6);
  EXPECT_DOUBLE_EQ(steps_to_degrees<double>(offset, 6), 10 - 6 * 1.8);
  // Shoulder and elbow against each other: the same angle relative to their zeros.
  const MotorSpec rev_elbow = with_direction(kElbow, -1);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int32_t> dist(-43000, 15000);
  for (int i = 0; i < 1000; ++i) {
    const int32_t a = dist(rng);
    EXPECT_EQ(quantize(rev_elbow, a), -quantize(kElbow, a)) << a;
    EXPECT_EQ(quantize(kShoulder, a + 90000), quantize(kElbow, a)) << a;
  }
}

TEST(Actuation, RoundTripWithinHalfStep) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int32_t> dist(-1000000, 1000000);  // +-1000 deg
  const MotorSpec motors[] = {kBase, kShoulder, kElbow, kDirect, with_direction(kShoulder, -1)};
  for (const MotorSpec& m : motors) {
    const double half = degrees_per_step<double>(m) / 2;
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      const int32_t a = dist(rng);
      const int32_t s = quantize(m, a);
      const double reached = steps_to_degrees<double>(m, s);
      const double diff = reached - a / 1000.0;
      ASSERT_LE(std::fabs(diff), half + 1e-12) << a;
      const double err = quantization_error_degrees<double>(m, a);
      ASSERT_NEAR(err, diff, 1e-9) << a;
      ASSERT_LE(std::fabs(err), half + 1e-12) << a;
      worst = std::max(worst, std::fabs(err));
      // Nearest step: its neighbours are no closer.
      ASSERT_GE(std::fabs(steps_to_degrees<double>(m, s + 1) - a / 1000.0), std::fabs(diff) - 1e-12);
      ASSERT_GE(std::fabs(steps_to_degrees<double>(m, s - 1) - a / 1000.0), std::fabs(diff) - 1e-12);
    }
    // The error spreads over the whole half step (so the bound above is not loose by luck).
    EXPECT_GT(worst, 0.95 * half);
  }
}

TEST(Actuation, StepsToMillidegHandComputedAndRoundTrips) {
  // 32 base steps: 32 * 0.316666.. = 10.1333.. deg; -8 elbow steps: -5.8212.. deg.
  EXPECT_EQ(steps_to_millideg(kBase, 32), 10133);
  EXPECT_EQ(steps_to_millideg(kElbow, -8), -5821);
  EXPECT_EQ(steps_to_millideg(kShoulder, 0), 90000);
  EXPECT_EQ(steps_to_millideg(kShoulder, 54), 129294);  // 90 + 54 * 0.7276.. = 129.2936..
  EXPECT_EQ(steps_to_millideg(with_direction(kBase, -1), 32), -10133);
  // Ties round away from zero: 400 steps a turn through a 1000:1 gear is 0.9 millideg a
  // step, so step 5 is at 4.5 millideg (-> 5) and step -5 at -4.5 (-> -5).
  const MotorSpec fine = {400, 1, 1, 1000, 1, 0, -180000, 180000};
  EXPECT_EQ(steps_to_millideg(fine, 5), 5);
  EXPECT_EQ(steps_to_millideg(fine, -5), -5);
  EXPECT_EQ(steps_to_millideg(fine, 3), 3);  // 2.7 -> 3
  // Every step within the limits: exact to half a millidegree (checked against the exact
  // rational angle), and back to the same step.
  for (const MotorSpec& m : {kBase, kShoulder, kElbow, kDirect, with_direction(kElbow, -1)}) {
    for (int32_t st = min_steps(m); st <= max_steps(m); ++st) {
      const Millideg a = steps_to_millideg(m, st);
      const int64_t num = int64_t(m.full_steps_per_rev) * m.microsteps * m.gear_num;
      const int64_t exact2 = 2 * (int64_t(m.direction) * st * 360000 * m.gear_den);  // 2 (angle - zero) num
      const int64_t err2 = 2 * (int64_t(a) - m.zero) * num - exact2;                 // 2 (a - exact) num
      EXPECT_LE(std::llabs(err2), num) << st;
      EXPECT_EQ(quantize(m, a), st);
      EXPECT_GE(a, m.min);
      EXPECT_LE(a, m.max);
    }
  }
}

TEST(Actuation, MinMaxStepsHandComputed) {
  EXPECT_EQ(max_steps(kBase), 284);   // floor(284.21)
  EXPECT_EQ(min_steps(kBase), -284);  // ceil(-284.21)
  EXPECT_EQ(max_steps(kShoulder), 54);   // floor(54.97)
  EXPECT_EQ(min_steps(kShoulder), -74);  // ceil(-74.21)
  EXPECT_EQ(max_steps(kElbow), 20);      // floor(20.61)
  EXPECT_EQ(min_steps(kElbow), -59);     // ceil(-59.09)
  // Limits exactly on a step: the step itself is allowed.
  MotorSpec m = kDirect;
  m.min = -9000;
  m.max = 9000;
  EXPECT_EQ(max_steps(m), 5);
  EXPECT_EQ(min_steps(m), -5);
  // Reversed with an offset: angle = 1 - 1.8 s deg; 1 - 1.8 s <= 9 <=> s >= -4.44,
  // 1 - 1.8 s >= -9 <=> s <= 5.56.
  m.zero = 1000;
  m.direction = -1;
  EXPECT_EQ(min_steps(m), -4);
  EXPECT_EQ(max_steps(m), 5);
}

// Random limits within +-400 degrees, and the zero clamped between them.
static void random_limits(MotorSpec& m, std::mt19937& rng) {
  std::uniform_int_distribution<int32_t> lim(-400000, 400000);
  int32_t a = lim(rng), b = lim(rng), z = lim(rng);
  if (a > b) std::swap(a, b);
  m.min = a, m.max = b, m.zero = std::min(std::max(z, a), b);
}

TEST(Actuation, MinMaxStepsNeverBeyondALimit) {
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> gear(1, 120);
  std::uniform_int_distribution<int> micro(0, 4);
  int checked = 0;
  for (int i = 0; i < 5000; ++i) {
    MotorSpec m = {200, uint8_t(1 << micro(rng)), int8_t(i % 2 ? 1 : -1), gear(rng), gear(rng), 0, 0, 0};
    random_limits(m, rng);
    ASSERT_EQ(validate(m), kMotorOk);
    const int32_t lo = min_steps(m), hi = max_steps(m);
    // The angles of steps lo and hi lie inside [min, max]; one step further lies outside.
    // Which end a step count approaches depends on the direction.
    // Step 0 sits at zero, inside the limits, so the range is never empty.
    ASSERT_LE(lo, 0);
    ASSERT_GE(hi, 0);
    const int64_t outer_lo = int64_t(lo) - 1, outer_hi = int64_t(hi) + 1;
    ASSERT_GE(compare_step_angle(m, lo, m.min), 0);
    ASSERT_LE(compare_step_angle(m, lo, m.max), 0);
    ASSERT_GE(compare_step_angle(m, hi, m.min), 0);
    ASSERT_LE(compare_step_angle(m, hi, m.max), 0);
    if (m.direction > 0) {
      ASSERT_LT(compare_step_angle(m, outer_lo, m.min), 0);
      ASSERT_GT(compare_step_angle(m, outer_hi, m.max), 0);
    } else {
      ASSERT_GT(compare_step_angle(m, outer_lo, m.max), 0);
      ASSERT_LT(compare_step_angle(m, outer_hi, m.min), 0);
    }
    // The same in degrees, as a user would check it.
    const double dlo = steps_to_degrees<double>(m, lo), dhi = steps_to_degrees<double>(m, hi);
    EXPECT_GE(std::min(dlo, dhi), m.min / 1000.0 - 1e-9);
    EXPECT_LE(std::max(dlo, dhi), m.max / 1000.0 + 1e-9);
    ++checked;
  }
  EXPECT_EQ(checked, 5000);
  // Direction -1 on the MK2 base: the range mirrors.
  EXPECT_EQ(min_steps(with_direction(kBase, -1)), -284);
  EXPECT_EQ(max_steps(with_direction(kBase, -1)), 284);
  EXPECT_EQ(min_steps(with_direction(kShoulder, -1)), -54);
  EXPECT_EQ(max_steps(with_direction(kShoulder, -1)), 74);
  EXPECT_GE(steps_to_degrees<double>(with_direction(kShoulder, -1), 74), 36.0);
  EXPECT_LT(steps_to_degrees<double>(with_direction(kShoulder, -1), 75), 36.0);
  EXPECT_LE(steps_to_degrees<double>(with_direction(kShoulder, -1), -54), 130.0);
  EXPECT_GT(steps_to_degrees<double>(with_direction(kShoulder, -1), -55), 130.0);
}

// quantize_within_limits checks a step past a limit without min_steps' and max_steps' divisions
// (the Nano's flash): the same step as clamping to them, for random motors of both directions,
// fine and coarse, at random angles and at the limits and a millidegree inside them, and at the
// largest spans a validated motor may have.
TEST(Actuation, QuantizeWithinLimitsIsTheNearestStepClampedToTheLimits) {
  std::mt19937 rng(2026);
  std::uniform_int_distribution<int> gear(1, 5000);
  std::uniform_int_distribution<int> micro(0, 5);
  int clamped = 0;
  auto check = [&](const MotorSpec& m, Millideg angle) {
    const int32_t want = clamp(quantize(m, angle), min_steps(m), max_steps(m));
    ASSERT_EQ(quantize_within_limits(m, angle), want) << "angle " << angle << " dir " << int(m.direction) << " gear "
                                                      << m.gear_num << "/" << m.gear_den;
    clamped += want != quantize(m, angle);
  };
  for (int i = 0; i < 20000; ++i) {
    MotorSpec m = {uint16_t(i % 3 ? 200 : 48), uint8_t(1 << micro(rng)), int8_t(i % 2 ? 1 : -1), gear(rng), gear(rng), 0, 0, 0};
    random_limits(m, rng);
    if (validate(m) != kMotorOk) continue;
    for (Millideg angle : {m.min, m.max, Millideg(m.min + 1), Millideg(m.max - 1), m.zero,
                           Millideg(std::uniform_int_distribution<int32_t>(m.min, m.max)(rng))})
      check(m, std::min(std::max(angle, m.min), m.max));
  }
  EXPECT_GT(clamped, 1000);  // (the limits' nearest steps often lie past them)
  // The widest a validated motor may be: a million degrees each way, one step per degree.
  const MotorSpec wide = {360, 1, -1, 1, 1, 0, -kMaxAbsMillideg, kMaxAbsMillideg};
  ASSERT_EQ(validate(wide), kMotorOk);
  for (Millideg angle : {-kMaxAbsMillideg, kMaxAbsMillideg, Millideg(-kMaxAbsMillideg + 499), Millideg(kMaxAbsMillideg - 501)})
    check(wide, angle);
}

TEST(Actuation, RelativeMovesDoNotDrift) {
  Actuation<double, 3> a = mk2();
  a.motors[0].min = -kMaxAbsMillideg;  // +-1,000,000 deg: room for a long random walk
  a.motors[0].max = kMaxAbsMillideg;
  ASSERT_EQ(validate(a.motors[0]), kMotorOk);
  MotorState<3> st;
  reset(st, a);
  std::mt19937_64 rng(2024);
  std::uniform_int_distribution<int32_t> delta(-10000, 10000);  // +-10 deg, 3 decimals
  int64_t sum = 0;
  int64_t naive_steps = 0;  // quantizing each delta on its own and adding steps
  const int kMoves = 1000000;
  for (int i = 0; i < kMoves; ++i) {
    const int32_t d = delta(rng);
    ASSERT_EQ(move_relative(st, a, 0, d), kOk) << i;
    sum += d;
    naive_steps += quantize(a.motors[0], a.motors[0].zero + d);
  }
  const int32_t exact = quantize(a.motors[0], int32_t(a.motors[0].zero + sum));
  EXPECT_EQ(st.commanded[0], a.motors[0].zero + sum);
  EXPECT_EQ(st.steps[0], exact);
  // The other motors never moved.
  EXPECT_EQ(st.steps[1], 0);
  EXPECT_EQ(st.commanded[1], kShoulder.zero);
  EXPECT_EQ(st.steps[2], 0);
  // Per-move rounding drifts: its error is a random walk of up to half a step a move.
  EXPECT_NE(naive_steps, exact);
  std::cout << "[ drift    ] " << kMoves << " relative moves, sum " << sum / 1000.0 << " deg: exact "
            << exact << " steps, per-move rounding " << naive_steps << " steps (off by "
            << naive_steps - exact << " steps = " << (naive_steps - exact) * kBaseDegPerStep << " deg)\n";
  ::testing::Test::RecordProperty("exact_steps", std::to_string(exact));
  ::testing::Test::RecordProperty("naive_steps", std::to_string(naive_steps));
}

TEST(Actuation, TenSmallMovesLandOnTheNearestStep) {
  // docs/protocol.md's example: ten `L 0 0.1` on the base (0.31667 deg a step) end at
  // 1 deg commanded, step round(3.158) = 3 (0.95 deg); quantizing each 0.1 deg move
  // (0.316 steps) on its own would never leave step 0.
  const Actuation<double, 3> a = mk2();
  MotorState<3> st;
  reset(st, a);
  // After k moves: round(0.3158 k) = 0.32, 0.63, 0.95, 1.26, 1.58, 1.89, 2.21, 2.53, 2.84, 3.16.
  const int32_t expected[10] = {0, 1, 1, 1, 2, 2, 2, 3, 3, 3};
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(move_relative(st, a, 0, 100), kOk);
    EXPECT_EQ(st.steps[0], expected[i]) << i;
  }
  EXPECT_EQ(st.commanded[0], 1000);
  EXPECT_EQ(st.steps[0], 3);
  EXPECT_NEAR(steps_to_degrees<double>(kBase, st.steps[0]), 0.95, 1e-12);
  EXPECT_EQ(quantize(kBase, 100), 0);
}

TEST(Actuation, StateInvariantUnderRandomMoves) {
  // steps == quantize(commanded) after every accepted or rejected move.
  const Actuation<double, 3> a = mk2();
  MotorState<3> st;
  reset(st, a);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(st.commanded[i], a.motors[i].zero);
    EXPECT_EQ(st.steps[i], 0);
  }
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> delta(-60000, 60000);
  std::uniform_int_distribution<int> motor(0, 2);
  int accepted = 0, rejected = 0;
  for (int i = 0; i < 20000; ++i) {
    const int k = motor(rng);
    const MotorState<3> before = st;
    const Status s = move_relative(st, a, uint8_t(k), delta(rng));
    if (s == kOk) {
      ++accepted;
      ASSERT_GE(st.commanded[k], a.motors[k].min);
      ASSERT_LE(st.commanded[k], a.motors[k].max);
    } else {
      ++rejected;
      ASSERT_EQ(s, kJointLimit);
      for (int j = 0; j < 3; ++j) {
        ASSERT_EQ(st.commanded[j], before.commanded[j]);
        ASSERT_EQ(st.steps[j], before.steps[j]);
      }
    }
    for (int j = 0; j < 3; ++j) {
      ASSERT_EQ(st.steps[j], quantize_within_limits(a.motors[j], st.commanded[j]));
      ASSERT_GE(st.steps[j], min_steps(a.motors[j]));
      ASSERT_LE(st.steps[j], max_steps(a.motors[j]));
    }
  }
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(rejected, 1000);
}

TEST(Actuation, LimitsRejectAndLeaveStateUnchanged) {
  const Actuation<double, 3> a = mk2();
  MotorState<3> st;
  reset(st, a);
  ASSERT_EQ(move_relative(st, a, 0, 45000), kOk);
  EXPECT_EQ(st.commanded[0], 45000);
  EXPECT_EQ(st.steps[0], 142);  // 3 * 45000 / 950 = 142.1
  const MotorState<3> before = st;
  auto unchanged = [&] {
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(st.commanded[j], before.commanded[j]);
      EXPECT_EQ(st.steps[j], before.steps[j]);
    }
  };
  EXPECT_EQ(move_relative(st, a, 0, 46000), kJointLimit);  // 91 deg
  unchanged();
  EXPECT_EQ(move_relative(st, a, 0, -136000), kJointLimit);  // -91 deg
  unchanged();
  EXPECT_EQ(move_relative(st, a, 1, -54001), kJointLimit);  // 35.999 deg, min 36
  unchanged();
  EXPECT_EQ(move_relative(st, a, 2, 15001), kJointLimit);  // 15.001 deg, max 15
  unchanged();
  // Beyond a limit by one millidegree, although that angle's nearest step (284, at
  // 89.93 deg) lies within: the commanded angle itself must respect the limit.
  EXPECT_EQ(move_relative(st, a, 0, 45001), kJointLimit);
  unchanged();
  // Exactly at a limit whose nearest step lies within: accepted.
  ASSERT_EQ(move_relative(st, a, 0, 45000), kOk);
  EXPECT_EQ(st.commanded[0], 90000);
  EXPECT_EQ(st.steps[0], 284);
  // Exactly at the shoulder's upper limit, whose nearest step (55, at 130.02 deg) lies
  // beyond it: accepted, and the motor takes the last whole step inside (54, 129.29 deg).
  ASSERT_EQ(max_steps(kShoulder), 54);
  ASSERT_EQ(quantize(kShoulder, 130000), 55);
  ASSERT_EQ(move_relative(st, a, 1, 40000), kOk);
  EXPECT_EQ(st.commanded[1], 130000);
  EXPECT_EQ(st.steps[1], 54);
  EXPECT_EQ(quantize_within_limits(kShoulder, 130000), 54);
  // Back inside, the nearest step again.
  ASSERT_EQ(move_relative(st, a, 1, -400), kOk);  // 129.6 deg: step 54 (129.29 deg)
  EXPECT_EQ(st.steps[1], 54);
  ASSERT_EQ(move_relative(st, a, 1, -1000), kOk);  // 128.6 deg: 38.6 / 0.72766 = 53.05 -> 53
  EXPECT_EQ(st.steps[1], 53);
  ASSERT_EQ(move_relative(st, a, 1, -1000), kOk);  // 127.6 deg: 51.67 -> 52
  EXPECT_EQ(st.steps[1], 52);
  // Bad motor index.
  const MotorState<3> s2 = st;
  EXPECT_EQ(move_relative(st, a, 3, 1000), kBadJoint);
  EXPECT_EQ(move_relative(st, a, 255, 1000), kBadJoint);
  for (int j = 0; j < 3; ++j) EXPECT_EQ(st.commanded[j], s2.commanded[j]);
}

TEST(Actuation, MoveAbsoluteIsAllOrNothing) {
  const Actuation<double, 3> a = mk2();
  MotorState<3> st;
  reset(st, a);
  const Millideg good[3] = {10000, 100000, -20000};
  ASSERT_EQ(move_absolute(st, a, good), kOk);
  EXPECT_EQ(st.steps[0], 32);
  EXPECT_EQ(st.steps[1], 14);
  EXPECT_EQ(st.steps[2], quantize(kElbow, -20000));
  EXPECT_EQ(st.steps[2], -27);  // -20000 * 47 / 34200 = -27.49
  const MotorState<3> before = st;
  const Millideg bad[3][3] = {{95000, 100000, -20000}, {0, 100000, -50000}, {0, 30000, 0}};
  for (const auto& t : bad) {
    EXPECT_EQ(move_absolute(st, a, t), kJointLimit);
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(st.commanded[j], before.commanded[j]);
      EXPECT_EQ(st.steps[j], before.steps[j]);
    }
  }
  const Millideg huge[3] = {0, 100000, kMaxAbsMillideg + 1};
  EXPECT_EQ(move_absolute(st, a, huge), kValueOutOfRange);
  for (int j = 0; j < 3; ++j) EXPECT_EQ(st.commanded[j], before.commanded[j]);
}

TEST(Actuation, FarTargetNeverWrapsIntoRange) {
  // 128 microsteps and 100:1: 64/9 steps a millidegree, so 603979.776 deg is exactly 2^32
  // steps, which an int32 step count would wrap to 0 (inside the +-10 deg limits).
  Actuation<double, 3> a{};
  a.num_motors = 1;
  a.motors[0] = {200, 128, 1, 100, 1, 0, -10000, 10000};  // 2^32 steps at 603979.776 deg
  a.coupling[0][0] = 1;
  ASSERT_EQ(validate(a.motors[0]), kMotorOk);
  MotorState<3> st;
  reset(st, a);
  const Millideg far[1] = {603979776};
  EXPECT_EQ(move_absolute(st, a, far), kJointLimit);
  EXPECT_EQ(st.commanded[0], 0);
  EXPECT_EQ(move_relative(st, a, 0, 603979776), kJointLimit);
  EXPECT_EQ(st.commanded[0], 0);
}

TEST(Actuation, OverflowIsValueOutOfRange) {
  // 360 steps a turn, 1:1: one step a degree, so +-1,000,000 deg lies exactly on a step.
  Actuation<double, 3> a{};
  a.num_motors = 1;
  a.motors[0] = {360, 1, 1, 1, 1, 0, -kMaxAbsMillideg, kMaxAbsMillideg};
  a.coupling[0][0] = 1;
  ASSERT_EQ(validate(a.motors[0]), kMotorOk);
  EXPECT_EQ(max_steps(a.motors[0]), 1000000);
  EXPECT_EQ(min_steps(a.motors[0]), -1000000);
  MotorState<3> st;
  reset(st, a);
  ASSERT_EQ(move_relative(st, a, 0, kMaxAbsMillideg - 1000), kOk);
  ASSERT_EQ(move_relative(st, a, 0, 1000), kOk);  // exactly 1,000,000 deg
  EXPECT_EQ(st.commanded[0], kMaxAbsMillideg);
  EXPECT_EQ(st.steps[0], 1000000);
  EXPECT_EQ(move_relative(st, a, 0, 1), kValueOutOfRange);
  EXPECT_EQ(move_relative(st, a, 0, 2147483647), kValueOutOfRange);  // no int32 wrap
  EXPECT_EQ(st.commanded[0], kMaxAbsMillideg);
  ASSERT_EQ(move_relative(st, a, 0, -2 * kMaxAbsMillideg), kOk);
  EXPECT_EQ(st.commanded[0], -kMaxAbsMillideg);
  EXPECT_EQ(st.steps[0], -1000000);
  EXPECT_EQ(move_relative(st, a, 0, -1), kValueOutOfRange);
  EXPECT_EQ(move_relative(st, a, 0, -2147483647 - 1), kValueOutOfRange);
  EXPECT_EQ(st.commanded[0], -kMaxAbsMillideg);
  const Millideg beyond[1] = {-kMaxAbsMillideg - 1};
  EXPECT_EQ(move_absolute(st, a, beyond), kValueOutOfRange);
  // The MK2 base over the same range: 3e9 / 950 = 3157894.7 steps, no overflow anywhere.
  MotorSpec wide = kBase;
  wide.min = -kMaxAbsMillideg;
  wide.max = kMaxAbsMillideg;
  EXPECT_EQ(quantize(wide, kMaxAbsMillideg), 3157895);
  EXPECT_EQ(quantize(wide, -kMaxAbsMillideg), -3157895);
  EXPECT_EQ(max_steps(wide), 3157894);
  EXPECT_EQ(min_steps(wide), -3157894);
}

TEST(Actuation, CouplingInverseMk2) {
  Actuation<double, 3> a = mk2();
  ASSERT_TRUE(invert_coupling(a));
  const double expected[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 1, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.coupling_inv[i][j], expected[i][j], 1e-15) << i << "," << j;
}

TEST(Actuation, CouplingSingular) {
  Actuation<double, 3> a = mk2();
  a.coupling[2][0] = 0;
  a.coupling[2][1] = 1;
  a.coupling[2][2] = 0;  // row 2 equals row 1
  EXPECT_FALSE(invert_coupling(a));
  Actuation<double, 3> z{};
  z.num_motors = 3;
  EXPECT_FALSE(invert_coupling(z));
  // Rank 2 without equal rows: row 2 = row 0 + row 1.
  Actuation<double, 3> r = mk2();
  r.coupling[0][1] = 2;
  r.coupling[2][0] = 1;
  r.coupling[2][1] = 3;
  r.coupling[2][2] = 0;
  EXPECT_FALSE(invert_coupling(r));
  Actuation<double, 3> n = mk2();
  n.coupling[1][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(invert_coupling(n));
  n.coupling[1][1] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(invert_coupling(n));
}

TEST(Actuation, CouplingGeneralInverse) {
  // Random well-conditioned matrices (plus a lead-screw entry in mm/rad): C * C^-1 = I.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> e(-2, 2);
  for (int t = 0; t < 200; ++t) {
    Actuation<double, 3> a{};
    a.num_motors = 3;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a.coupling[i][j] = e(rng) + (i == j ? 5 : 0);
    ASSERT_TRUE(invert_coupling(a));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double v = 0;
        for (int k = 0; k < 3; ++k) v += a.coupling[i][k] * a.coupling_inv[k][j];
        ASSERT_NEAR(v, i == j ? 1 : 0, 1e-12);
      }
  }
  // A permutation needs the pivoting (zero on the diagonal).
  Actuation<double, 3> p{};
  p.num_motors = 3;
  p.coupling[0][1] = 1;
  p.coupling[1][2] = 2;
  p.coupling[2][0] = 4;
  ASSERT_TRUE(invert_coupling(p));
  EXPECT_DOUBLE_EQ(p.coupling_inv[1][0], 1);
  EXPECT_DOUBLE_EQ(p.coupling_inv[2][1], 0.5);
  EXPECT_DOUBLE_EQ(p.coupling_inv[0][2], 0.25);
  EXPECT_DOUBLE_EQ(p.coupling_inv[0][0], 0);
}

TEST(Actuation, JointsFromStepsMk2) {
  Actuation<double, 3> a = mk2();
  ASSERT_TRUE(invert_coupling(a));
  const int32_t steps[3] = {0, 10, -5};
  double q[3];
  joints_from_steps(q, a, steps);
  // u1 = 90 + 10 * 0.7276596 = 97.276596 deg, u2 = -5 * 0.7276596 = -3.638298 deg,
  // theta3 = u2 - u1 = -100.914894 deg.
  const double u1 = 90 + 10 * kArmDegPerStep, u2 = -5 * kArmDegPerStep;
  EXPECT_NEAR(u1, 97.276596, 1e-6);
  EXPECT_NEAR(u2 - u1, -100.914894, 1e-6);
  EXPECT_NEAR(q[0], 0, 1e-15);
  EXPECT_NEAR(q[1], u1 * M_PI / 180, 1e-12);
  EXPECT_NEAR(q[2], (u2 - u1) * M_PI / 180, 1e-12);
  const int32_t steps2[3] = {-100, 0, 0};  // base -31.667 deg, arm at zero: q2 = -90 deg
  joints_from_steps(q, a, steps2);
  EXPECT_NEAR(q[0], -100 * kBaseDegPerStep * M_PI / 180, 1e-12);
  EXPECT_NEAR(q[1], M_PI / 2, 1e-12);
  EXPECT_NEAR(q[2], -M_PI / 2, 1e-12);
}

TEST(Actuation, ActuatorsFromJointsInverts) {
  Actuation<double, 3> a = mk2();
  ASSERT_TRUE(invert_coupling(a));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ang(-3, 3);
  for (int t = 0; t < 1000; ++t) {
    const double u[3] = {ang(rng), ang(rng), ang(rng)};
    double q[3], back[3];
    joints_from_actuators(q, a, u);
    EXPECT_NEAR(q[2], u[2] - u[1], 1e-15);  // theta3 = forearm elevation - shoulder
    EXPECT_DOUBLE_EQ(q[0], u[0]);
    EXPECT_DOUBLE_EQ(q[1], u[1]);
    actuators_from_joints(back, a, q);
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(back[i], u[i], 1e-14);
  }
}

TEST(Actuation, ValidateErrors) {
  EXPECT_EQ(validate(kBase), kMotorOk);
  EXPECT_EQ(validate(kShoulder), kMotorOk);
  EXPECT_EQ(validate(kElbow), kMotorOk);
  MotorSpec m = kBase;
  m.full_steps_per_rev = 0;
  EXPECT_EQ(validate(m), kMotorBadSteps);
  m = kBase;
  m.microsteps = 0;
  EXPECT_EQ(validate(m), kMotorBadSteps);
  m = kBase;
  m.gear_num = 0;
  EXPECT_EQ(validate(m), kMotorBadGear);
  m = kBase;
  m.gear_den = -19;
  EXPECT_EQ(validate(m), kMotorBadGear);
  m = kBase;
  m.gear_num = -108;
  m.gear_den = -19;  // a positive ratio from two negatives is still rejected
  EXPECT_EQ(validate(m), kMotorBadGear);
  m = kBase;
  m.direction = 0;
  EXPECT_EQ(validate(m), kMotorBadDirection);
  m.direction = 2;
  EXPECT_EQ(validate(m), kMotorBadDirection);
  m = kBase;
  m.min = 1000;
  m.max = -1000;
  EXPECT_EQ(validate(m), kMotorBadLimits);
  m = kShoulder;
  m.zero = 35999;  // below min
  EXPECT_EQ(validate(m), kMotorBadLimits);
  m.zero = 130001;  // above max
  EXPECT_EQ(validate(m), kMotorBadLimits);
  m = kBase;
  m.min = -kMaxAbsMillideg - 1;
  EXPECT_EQ(validate(m), kMotorBadLimits);
  m = kBase;
  m.max = kMaxAbsMillideg + 1;
  EXPECT_EQ(validate(m), kMotorBadLimits);
  m.max = kMaxAbsMillideg;
  m.min = -kMaxAbsMillideg;
  EXPECT_EQ(validate(m), kMotorOk);
  // 65535 * 255 * 200 = 3.3e9 steps per motor turn times the gear: beyond 2^31.
  m = {65535, 255, 1, 200, 1, 0, -1000, 1000};
  EXPECT_EQ(validate(m), kMotorTooFine);
  // Fine enough for a turn but not for its limits: 2,560,000 steps a joint turn over
  // +-1,000,000 deg is 7.1e9 steps, more than an int32 holds.
  m = {200, 128, 1, 100, 1, 0, -kMaxAbsMillideg, kMaxAbsMillideg};
  EXPECT_EQ(validate(m), kMotorTooFine);
  // 64/9 steps a millidegree: 301989888 mdeg is exactly 2^31 steps, one too many.
  m.min = -1000;
  m.max = 301989888;
  EXPECT_EQ(validate(m), kMotorTooFine);
  m.max = 301989887;  // 2147483641.0 steps
  EXPECT_EQ(validate(m), kMotorOk);
  EXPECT_EQ(quantize(m, m.max), 2147483641);
  m.max = 1000;
  m.min = -301989888;  // the span below zero counts the same
  EXPECT_EQ(validate(m), kMotorTooFine);
  m.zero = -1000;  // ... measured from zero
  EXPECT_EQ(validate(m), kMotorOk);
  // Every error has its own text.
  std::set<std::string> texts;
  for (int e = kMotorOk; e <= kMotorTooFine; ++e) {
    const std::string t = motor_error_text(MotorError(e));
    EXPECT_FALSE(t.empty());
    EXPECT_NE(t, "unknown motor error");
    texts.insert(t);
  }
  EXPECT_EQ(texts.size(), size_t(kMotorTooFine) + 1);
  EXPECT_STREQ(motor_error_text(MotorError(99)), "unknown motor error");
}

TEST(Actuation, ToMillideg) {
  Millideg out = 12345;
  ASSERT_TRUE(to_millideg(out, 1.0));
  EXPECT_EQ(out, 1000);
  ASSERT_TRUE(to_millideg(out, -12.3456));
  EXPECT_EQ(out, -12346);
  ASSERT_TRUE(to_millideg(out, 12.3454));
  EXPECT_EQ(out, 12345);
  // Exact halves of a millidegree (the product is exactly x.5: checked first).
  ASSERT_EQ(0.0005 * 1000, 0.5);
  ASSERT_TRUE(to_millideg(out, 0.0005));
  EXPECT_EQ(out, 1);
  ASSERT_TRUE(to_millideg(out, -0.0005));
  EXPECT_EQ(out, -1);
  ASSERT_EQ(0.0025 * 1000, 2.5);
  ASSERT_TRUE(to_millideg(out, 0.0025));
  EXPECT_EQ(out, 3);
  ASSERT_TRUE(to_millideg(out, -0.0025));
  EXPECT_EQ(out, -3);
  // Just below a half: down.
  const double x = std::nextafter(0.0005, 0.0);
  ASSERT_LT(x * 1000, 0.5);
  ASSERT_TRUE(to_millideg(out, x));
  EXPECT_EQ(out, 0);
  ASSERT_TRUE(to_millideg(out, -x));
  EXPECT_EQ(out, 0);
  // Range: +-1,000,000 deg inclusive.
  ASSERT_TRUE(to_millideg(out, 1000000.0));
  EXPECT_EQ(out, kMaxAbsMillideg);
  ASSERT_TRUE(to_millideg(out, -1000000.0));
  EXPECT_EQ(out, -kMaxAbsMillideg);
  out = 77;
  EXPECT_FALSE(to_millideg(out, 1000000.001));
  EXPECT_FALSE(to_millideg(out, -1000000.001));
  EXPECT_FALSE(to_millideg(out, 1e300));
  EXPECT_FALSE(to_millideg(out, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(to_millideg(out, std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(to_millideg(out, -std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(to_millideg(out, std::numeric_limits<float>::quiet_NaN()));
  EXPECT_EQ(out, 77);  // untouched on failure
}

TEST(Actuation, ToMillidegFloatMatchesExactRounding) {
  // The float path rounds the float product m = degrees * 1000 half away from zero, at
  // every magnitude (above 2^23 a float holds only integers, and m + 0.5 would tie to even).
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> deg(-1000000.f, 1000000.f);
  std::uniform_real_distribution<float> small(-400.f, 400.f);
  for (int i = 0; i < 200000; ++i) {
    const float d = i % 2 ? deg(rng) : small(rng);
    const float m = d * 1000.f;
    const double md = double(m);  // exact
    const double expected = md >= 0 ? std::floor(md + 0.5) : -std::floor(-md + 0.5);  // exact in double
    Millideg out = 0;
    ASSERT_TRUE(to_millideg(out, d));
    ASSERT_EQ(out, Millideg(expected)) << d;
  }
  Millideg out = 0;
  ASSERT_TRUE(to_millideg(out, 8388.609f));  // m is the odd integer 8388609
  EXPECT_EQ(double(8388.609f * 1000.f), 8388609.0);
  EXPECT_EQ(out, 8388609);
}

TEST(Actuation, FloatAndDoubleAgree) {
  // quantize is integer arithmetic: the same on both (no Scalar involved); the angle a
  // step gives agrees to float precision.
  const MotorSpec motors[] = {kBase, kShoulder, kElbow, with_direction(kShoulder, -1)};
  for (const MotorSpec& m : motors) {
    for (int32_t s = min_steps(m) - 10; s <= max_steps(m) + 10; ++s) {
      const double d = steps_to_degrees<double>(m, s);
      const float f = steps_to_degrees<float>(m, s);
      ASSERT_NEAR(double(f), d, 1e-4) << s;
    }
    EXPECT_NEAR(double(degrees_per_step<float>(m)), degrees_per_step<double>(m), 1e-7);
    std::mt19937 rng(1);
    std::uniform_int_distribution<int32_t> dist(m.min, m.max);
    for (int i = 0; i < 1000; ++i) {
      const int32_t angle = dist(rng);
      ASSERT_NEAR(double(quantization_error_degrees<float>(m, angle)), quantization_error_degrees<double>(m, angle),
                  1e-4);
    }
  }
  // The float state machine lands on the same steps as the double one.
  Actuation<float, 3> af{};
  const Actuation<double, 3> ad = mk2();
  af.num_motors = 3;
  for (int i = 0; i < 3; ++i) af.motors[i] = ad.motors[i];
  MotorState<3> sf, sd;
  reset(sf, af);
  reset(sd, ad);
  std::mt19937 rng(8);
  std::uniform_int_distribution<int32_t> delta(-30000, 30000);
  for (int i = 0; i < 5000; ++i) {
    const uint8_t k = uint8_t(i % 3);
    const int32_t d = delta(rng);
    ASSERT_EQ(move_relative(sf, af, k, d), move_relative(sd, ad, k, d));
    for (int j = 0; j < 3; ++j) ASSERT_EQ(sf.steps[j], sd.steps[j]);
  }
}
