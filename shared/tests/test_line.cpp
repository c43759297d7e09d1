// The straight-line command's rule (articula/line.h) on the MK2's arm, in float as on the
// Nano: where the segments' ends lie, how far the tool strays between them, what is refused,
// and the speeds of the segments (with motion.h's cruise cap).
#include <articula/line.h>
#include <articula/motion.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace articula;

namespace {

// The MK2 (robots/mk2plus.json): base 78 mm, upper arm 135, forearm 147, tool 88 mm ahead of
// the wrist; the parallelogram's actuated limits (deg): base -90..90, upper arm 36..130,
// forearm -43..15.
YppArm<float> mk2() {
  YppArm<float> a{};
  a.base_height = 78;
  a.upper = 135;
  a.fore = 147;
  a.tool_forward = 88;
  a.parallelogram = true;
  const float lo[3] = {-90, 36, -43}, hi[3] = {90, 130, 15};
  for (int i = 0; i < 3; ++i) {
    a.lo[i] = deg_to_rad(lo[i]);
    a.hi[i] = deg_to_rad(hi[i]);
  }
  return a;
}

struct Arm {
  YppArm<float> arm = mk2();
  MotorSpec motors[3];
  Arm() {
    const Millideg lo[3] = {-90000, 36000, -43000}, hi[3] = {90000, 130000, 15000};
    for (int i = 0; i < 3; ++i) {
      motors[i] = MotorSpec{200, 1, 1, 1, 1, 0, lo[i], hi[i]};
    }
  }
  YppLineSolver solver() const { return YppLineSolver{&arm, motors}; }
  Vec3<double> tool(const double* act_deg) const {
    float q[3] = {deg_to_rad(float(act_deg[0])), deg_to_rad(float(act_deg[1])), deg_to_rad(float(act_deg[2] - act_deg[1]))};
    const Vec3<float> p = ypp_tool_position(arm, q);
    return make_vec3(double(p.x), double(p.y), double(p.z));
  }
};

double distance_to_line(const Vec3<double>& p, const Vec3<double>& a, const Vec3<double>& b) {
  const Vec3<double> ab = b - a;
  const double t = std::fmax(0.0, std::fmin(1.0, dot(p - a, ab) / dot(ab, ab)));
  return norm(p - (a + t * ab));
}

struct Cut {
  Status status = kOk;
  std::vector<std::vector<Millideg>> ends;  // the start, then each segment's end
  double worst_mm = 0;                     // the tool's worst distance from the line, sampled
  std::vector<float> lengths;
};

// Cuts from the tool at `at` to `to`, and samples each segment (straight in actuator space)
// at 64 points through the forward kinematics.
Cut cut_line(const Arm& a, const Millideg* at, const float* to, float tol) {
  Cut c;
  const YppLineSolver s = a.solver();
  float from[3];
  s.tool(from, at);
  LineCutter<float, 3> cut;
  cut.start(from, to, at, 3, tol);
  c.ends.push_back(std::vector<Millideg>(at, at + 3));
  Millideg end[3];
  while (!cut.done()) {
    c.status = cut.next(s, end);
    if (c.status != kOk) return c;
    c.ends.push_back(std::vector<Millideg>(end, end + 3));
    c.lengths.push_back(cut.segment_length());
  }
  const Vec3<double> A = make_vec3(double(from[0]), double(from[1]), double(from[2]));
  const Vec3<double> B = make_vec3(double(to[0]), double(to[1]), double(to[2]));
  for (size_t k = 1; k < c.ends.size(); ++k)
    for (int j = 0; j <= 64; ++j) {
      double act[3];
      for (int i = 0; i < 3; ++i)
        act[i] = (c.ends[k - 1][size_t(i)] + (c.ends[k][size_t(i)] - c.ends[k - 1][size_t(i)]) * j / 64.0) / 1000.0;
      c.worst_mm = std::fmax(c.worst_mm, distance_to_line(a.tool(act), A, B));
    }
  return c;
}

const Millideg kPowerUp[3] = {0, 90000, 0};  // the tool at (235, 0, 213)

}  // namespace

TEST(LineCutter, EveryEndIsOnTheLineAndTheToolStaysNearIt) {
  const Arm a;
  const float to[3] = {240, 0, 140};
  const Cut c = cut_line(a, kPowerUp, to, 0.1f);
  ASSERT_EQ(c.status, kOk);
  ASSERT_GE(c.ends.size(), 3u);  // a line of 73 mm down and out is more than one move
  // Within the tolerance and a little: the rule measures at the midpoint, where a move bows
  // most; a millidegree of rounding at the ends adds about 5 um.
  EXPECT_LE(c.worst_mm, 0.1 * 1.25 + 0.005) << c.ends.size() - 1 << " segments";
  // The last end is the target's solution (P's).
  Millideg p[3];
  ASSERT_EQ(ypp_point_angles(p, a.arm, a.motors, make_vec3(240.0f, 0.0f, 140.0f), c.ends[c.ends.size() - 2].data()), kOk);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(c.ends.back()[size_t(i)], p[i]);
}

TEST(LineCutter, TheSameMoveWithoutSegmentsStraysFarFromTheLine) {
  // What T is for: (250, -100, 100) to (250, 100, 100) bows 19 mm as one move; the points on
  // either side of the dead zone make this line refused, so a line that passes in front of it.
  const Arm a;
  Millideg at[3];
  ASSERT_EQ(ypp_point_angles(at, a.arm, a.motors, make_vec3(300.0f, -100.0f, 150.0f), kPowerUp), kOk);
  const float to[3] = {300, 100, 150};
  const Cut c = cut_line(a, at, to, 0.1f);
  ASSERT_EQ(c.status, kOk);
  EXPECT_LE(c.worst_mm, 0.13);
  const Cut one = cut_line(a, at, to, 1000.0f);  // a tolerance no move exceeds: one move
  ASSERT_EQ(one.status, kOk);
  EXPECT_EQ(one.ends.size(), 2u);
  EXPECT_GT(one.worst_mm, 5.0);
  EXPECT_GT(c.ends.size(), 6u);
}

TEST(LineCutter, AFinerToleranceGivesMoreAndShorterSegments) {
  const Arm a;
  const float to[3] = {200, 100, 150};
  const Cut coarse = cut_line(a, kPowerUp, to, 0.5f), fine = cut_line(a, kPowerUp, to, 0.05f);
  ASSERT_EQ(coarse.status, kOk);
  ASSERT_EQ(fine.status, kOk);
  EXPECT_GT(fine.ends.size(), coarse.ends.size());
  EXPECT_LE(fine.worst_mm, 0.05 * 1.25 + 0.005);
  EXPECT_LE(coarse.worst_mm, 0.5 * 1.25 + 0.005);
}

TEST(LineCutter, ALineThroughTheDeadZoneIsRefusedWhereItFails) {
  // Both ends within reach; (250, 0, 100), half way, is not (too close for the elbow).
  const Arm a;
  Millideg at[3];
  ASSERT_EQ(ypp_point_angles(at, a.arm, a.motors, make_vec3(250.0f, -100.0f, 100.0f), kPowerUp), kOk);
  Millideg there[3];
  ASSERT_EQ(ypp_point_angles(there, a.arm, a.motors, make_vec3(250.0f, 100.0f, 100.0f), at), kOk);
  const YppLineSolver s = a.solver();
  float from[3];
  s.tool(from, at);
  const float to[3] = {250, 100, 100};
  LineCutter<float, 3> cut;
  cut.start(from, to, at, 3, 0.1f);
  Millideg end[3];
  Status st = kOk;
  while (!cut.done() && st == kOk) st = cut.next(s, end);
  EXPECT_EQ(st, kUnreachable);
  EXPECT_FALSE(cut.done());
  // The refused try lies inside the dead zone's span of the line.
  const float y = from[1] + cut.refused_fraction() * (to[1] - from[1]);
  EXPECT_GT(y, -60.0f);
  EXPECT_LT(y, 60.0f);
}

TEST(LineCutter, ALineOfNoLengthHasNoSegment) {
  const Arm a;
  float here[3];
  a.solver().tool(here, kPowerUp);
  LineCutter<float, 3> cut;
  cut.start(here, here, kPowerUp, 3, 0.1f);
  EXPECT_TRUE(cut.done());
}

TEST(LineSpeed, ASegmentsCruiseCoversItAtTheToolSpeed) {
  // 10 mm at 50 mm/s is 0.2 s, 400,000 ticks at 2 MHz: 100,000 in units of 4.
  EXPECT_EQ(segment_ticks4(10.0f, 50.0f, 2000000), 100000u);
  EXPECT_EQ(segment_cruise4(40, 100000), 2500);  // 40 steps: 10,000 ticks apart
  EXPECT_EQ(segment_cruise4(0, 100000), 0);
  EXPECT_EQ(segment_cruise4(1, 100000), 0xFFFF);  // slower than a cruise holds: the slowest
  EXPECT_EQ(segment_ticks4(10.0f, 0.0f, 2000000), 0u);
}

TEST(LineSpeed, TheCapIsALevelBelowTheCruiseOnTheRamp) {
  // Climbing from rest, the interval at the cap's level is still no shorter than the cruise,
  // for cruises from just below $0's to far slower, at several accelerations; and the cap is
  // not far below the level where the ramp passes the cruise (within a tenth, and two levels).
  for (uint32_t accel : {500u, 2000u, 20000u}) {
    const MotionSettings s{2000000, 4000, accel};
    ProfileConstants k;
    ASSERT_EQ(profile_constants(k, s), kMotionOk);
    for (uint32_t cruise = k.cruise + 1; cruise < 400000; cruise = cruise * 5 / 4 + 1) {
      const uint16_t cap = cruise_level_cap(s, k.cruise, cruise);
      if (cap == 0) continue;  // from rest: always allowed (the first interval is then the cruise's)
      StepProfile p;
      p.start(100000, k);
      uint32_t interval = 0;
      for (uint32_t n = 0; n <= cap; ++n) interval = p.next_interval();  // the level-cap step
      EXPECT_GE(interval, cruise) << "accel " << accel << ", cruise " << cruise << ", cap " << cap;
      uint32_t level = cap;
      while (p.next_interval() >= cruise) ++level;
      EXPECT_LE(level, cap + 2 + cap / 10u) << "accel " << accel << ", cruise " << cruise;
    }
    EXPECT_EQ(cruise_level_cap(s, k.cruise, k.cruise), 0xFFFF);
  }
}

TEST(LineSpeed, AMoveCruisesAtItsOwnIntervalAndFollowsOntoASlowerOne) {
  const MotionSettings s{2000000, 600, 2000};
  ProfileConstants k;
  ASSERT_EQ(profile_constants(k, s), kMotionOk);
  const uint32_t slow = 8000, slower = 12000;  // 250 and 167 steps/s, below $0's 600
  const uint16_t cap_slow = cruise_level_cap(s, k.cruise, slow), cap_slower = cruise_level_cap(s, k.cruise, slower);
  ASSERT_GT(cap_slow, cap_slower);
  // As the planner plans them: the junction at the lower of the two caps.
  StepProfile p;
  p.start(200, k, cap_slower, slow);
  uint32_t shortest = 0xFFFFFFFF;
  while (!p.done()) shortest = std::min(shortest, p.next_interval());
  EXPECT_EQ(shortest, slow);  // it cruised at its own interval, never faster
  EXPECT_EQ(p.level(), uint32_t(cap_slower));
  p.follow(100, 0, slower);
  shortest = 0xFFFFFFFF;
  while (!p.done()) shortest = std::min(shortest, p.next_interval());
  EXPECT_EQ(shortest, slower);  // from the junction on, never faster than its own cruise
}
