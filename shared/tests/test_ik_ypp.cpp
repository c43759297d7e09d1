// Tests shared/articula/ik_ypp.h: recognising the MK2 arm's DH model, the closed-form tool
// position against the DH chain, every IK solution checked by forward kinematics, limits,
// out-of-reach and limited targets with their nearest pose, and the float solver.
#include <articula/ik_ypp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace articula;

namespace {

using ModelD = Model<double, 3, 4>;

double deg(double d) { return d * M_PI / 180; }

// The MK2 arm, built by hand (not from a robot file):
//   row  a    alpha  d   theta
//   0    0    0      78  q0 (base)
//   1    0    +90    0   q1 (shoulder)
//   2    135  0      0   q2 (elbow, DH: relative to the upper arm)
//   3    147  0      0   -(q1 + q2) (linked: the parallelogram keeps the wrist level)
//   tool: 88 mm along x4, rotated -90 deg about x4.
ModelD mk2_model() {
  ModelD m{};
  m.num_rows = 4;
  m.num_joints = 3;
  m.num_linked = 1;
  m.rows[0] = DhRow<double>{0, 0, 78, 0};
  m.rows[1] = DhRow<double>{0, deg(90), 0, 0};
  m.rows[2] = DhRow<double>{135, 0, 0, 0};
  m.rows[3] = DhRow<double>{147, 0, 0, 0};
  m.joints[0] = JointSpec<double>{0, kParamTheta, deg(-90), deg(90)};
  m.joints[1] = JointSpec<double>{1, kParamTheta, deg(36), deg(130)};
  m.joints[2] = JointSpec<double>{2, kParamTheta, deg(-173), deg(-21)};
  m.linked[0].row = 3;
  m.linked[0].param = kParamTheta;
  m.linked[0].offset = 0;
  m.linked[0].gain[0] = 0;
  m.linked[0].gain[1] = -1;
  m.linked[0].gain[2] = -1;
  m.T_last_tool = make_transform(rot_x(deg(-90)), make_vec3(88.0, 0.0, 0.0));
  return m;
}

// Actuated limits: base yaw, upper-arm elevation, forearm elevation (deg).
constexpr double kActLo[3] = {-90, 36, -43};
constexpr double kActHi[3] = {90, 130, 15};
// The same limits on the DH variables: q2 = elevation - q1, so -43 - 130 .. 15 - 36.
constexpr double kDhLo[3] = {-90, 36, -173};
constexpr double kDhHi[3] = {90, 130, -21};

YppArm<double> mk2_arm(bool parallelogram) {
  YppArm<double> arm{};
  EXPECT_TRUE(ypp_from_model(arm, mk2_model()));
  arm.parallelogram = parallelogram;
  for (int i = 0; i < 3; ++i) {
    arm.lo[i] = deg(parallelogram ? kActLo[i] : kDhLo[i]);
    arm.hi[i] = deg(parallelogram ? kActHi[i] : kDhHi[i]);
  }
  return arm;
}

Vec3<double> dh_tool(const double* q) { return tool_position(mk2_model(), q); }

// In limits, written out from the limit table (not via ypp_within_limits).
bool in_limits_by_hand(const double* q, bool parallelogram) {
  const double act[3] = {q[0], q[1], parallelogram ? q[1] + q[2] : q[2]};
  for (int i = 0; i < 3; ++i) {
    const double lo = deg(parallelogram ? kActLo[i] : kDhLo[i]);
    const double hi = deg(parallelogram ? kActHi[i] : kDhHi[i]);
    if (act[i] < lo || act[i] > hi) return false;
  }
  return true;
}

// In limits up to a rounding tolerance (for poses the solver clamped).
bool in_limits_tol(const double* q, bool parallelogram, double tol = 1e-12) {
  const double act[3] = {q[0], q[1], parallelogram ? q[1] + q[2] : q[2]};
  for (int i = 0; i < 3; ++i) {
    const double lo = deg(parallelogram ? kActLo[i] : kDhLo[i]);
    const double hi = deg(parallelogram ? kActHi[i] : kDhHi[i]);
    if (!(act[i] >= lo - tol && act[i] <= hi + tol)) return false;
  }
  return true;
}

double angle_diff(double a, double b) { return std::fabs(std::remainder(a - b, 2 * M_PI)); }

// A random pose within the limits, as DH joint values.
void random_pose(double* q, std::mt19937& rng, bool parallelogram) {
  const double* lo = parallelogram ? kActLo : kDhLo;
  const double* hi = parallelogram ? kActHi : kDhHi;
  double act[3];
  for (int i = 0; i < 3; ++i) act[i] = deg(std::uniform_real_distribution<double>(lo[i], hi[i])(rng));
  q[0] = act[0];
  q[1] = act[1];
  q[2] = parallelogram ? act[2] - act[1] : act[2];
}

double dist(const Vec3<double>& a, const Vec3<double>& b) { return norm(a - b); }

}  // namespace

// The firmware's path: the model's arm, then the motors' limits and the coupling.
TEST(IkYpp, LimitsFromActuationRecogniseTheCoupling) {
  Actuation<double, 3> a{};
  a.num_motors = 3;
  a.motors[0] = MotorSpec{200, 1, 1, 108, 19, 0, -90000, 90000};
  a.motors[1] = MotorSpec{200, 1, 1, 47, 19, 90000, 36000, 130000};
  a.motors[2] = MotorSpec{200, 1, -1, 47, 19, 0, -43000, 15000};
  const double par[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, -1, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.coupling[i][j] = par[i][j];
  YppArm<double> arm{};
  ASSERT_TRUE(ypp_from_model(arm, mk2_model()));
  ASSERT_TRUE(ypp_limits_from_actuation(arm, a));
  EXPECT_TRUE(arm.parallelogram);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(arm.lo[i], deg(kActLo[i]), 1e-12);
    EXPECT_NEAR(arm.hi[i], deg(kActHi[i]), 1e-12);
  }
  EXPECT_DOUBLE_EQ(arm.upper, 135);  // the geometry stays
  // The limits then agree with the hand-made MK2 arm: the same solutions.
  const YppArm<double> hand = mk2_arm(true);
  YppResult<double> r1, r2;
  ypp_solve(r1, arm, make_vec3(235.0, 0.0, 213.0), false);
  ypp_solve(r2, hand, make_vec3(235.0, 0.0, 213.0), false);
  ASSERT_EQ(r1.status, kYppReached);
  ASSERT_EQ(r1.count, r2.count);
  for (int k = 0; k < r1.count; ++k)
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r1.solutions[k].q[i], r2.solutions[k].q[i], 1e-12);

  // The identity: each motor its own joint, limits on the DH variables.
  Actuation<double, 3> id = a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) id.coupling[i][j] = i == j ? 1 : 0;
  id.motors[2].min = -173000;
  id.motors[2].max = -21000;
  ASSERT_TRUE(ypp_limits_from_actuation(arm, id));
  EXPECT_FALSE(arm.parallelogram);
  EXPECT_NEAR(arm.lo[2], deg(-173), 1e-12);
  EXPECT_NEAR(arm.hi[2], deg(-21), 1e-12);

  // Anything else is refused and leaves the arm alone.
  const YppArm<double> before = arm;
  Actuation<double, 3> other = a;
  other.coupling[2][1] = -0.5;
  EXPECT_FALSE(ypp_limits_from_actuation(arm, other));
  other = a;
  other.coupling[0][1] = 1;
  EXPECT_FALSE(ypp_limits_from_actuation(arm, other));
  other = a;
  other.num_motors = 2;
  EXPECT_FALSE(ypp_limits_from_actuation(arm, other));
  EXPECT_FALSE(arm.parallelogram);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(arm.lo[i], before.lo[i]);
  // A larger host actuation with three motors in use works too.
  Actuation<double, 12> big{};
  big.num_motors = 3;
  for (int i = 0; i < 3; ++i) {
    big.motors[i] = a.motors[i];
    for (int j = 0; j < 3; ++j) big.coupling[i][j] = par[i][j];
  }
  EXPECT_TRUE(ypp_limits_from_actuation(arm, big));
  EXPECT_TRUE(arm.parallelogram);
}

TEST(IkYpp, RecognisesMk2Model) {
  const ModelD m = mk2_model();
  ASSERT_EQ(validate(m), kModelOk);
  YppArm<double> arm{};
  arm.parallelogram = true;
  ASSERT_TRUE(ypp_from_model(arm, m));
  EXPECT_DOUBLE_EQ(arm.base_height, 78);
  EXPECT_DOUBLE_EQ(arm.shoulder_offset, 0);
  EXPECT_DOUBLE_EQ(arm.upper, 135);
  EXPECT_DOUBLE_EQ(arm.fore, 147);
  EXPECT_DOUBLE_EQ(arm.tool_forward, 88);
  EXPECT_DOUBLE_EQ(arm.tool_up, 0);
  EXPECT_FALSE(arm.parallelogram);  // the model's limits are on the DH variables
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(arm.lo[i], deg(kDhLo[i]));
    EXPECT_DOUBLE_EQ(arm.hi[i], deg(kDhHi[i]));
  }
  // A shoulder offset, base height and tool lift are read from their entries.
  ModelD v = m;
  v.rows[0].d = 100;
  v.rows[1].a = 12;
  v.T_last_tool.p.y = -30;
  ASSERT_TRUE(ypp_from_model(arm, v));
  EXPECT_DOUBLE_EQ(arm.base_height, 100);
  EXPECT_DOUBLE_EQ(arm.shoulder_offset, 12);
  EXPECT_DOUBLE_EQ(arm.tool_up, -30);
}

TEST(IkYpp, RejectsOtherModels) {
  YppArm<double> arm{};
  const ModelD good = mk2_model();
  ASSERT_TRUE(ypp_from_model(arm, good));
  std::vector<ModelD> bad;
  ModelD m = good;
  m.rows[1].alpha = 0;  // shoulder axis vertical: a planar arm
  bad.push_back(m);
  m = good;
  m.rows[1].alpha = deg(-90);
  bad.push_back(m);
  m = good;
  m.rows[2].d = 5;  // elbow offset sideways
  bad.push_back(m);
  m = good;
  m.rows[3].d = 5;
  bad.push_back(m);
  m = good;
  m.rows[2].alpha = deg(10);
  bad.push_back(m);
  m = good;
  m.rows[0].a = 5;
  bad.push_back(m);
  m = good;
  m.rows[1].d = 5;
  bad.push_back(m);
  m = good;
  m.T_last_tool.p.z = 3;  // tool offset sideways
  bad.push_back(m);
  m = good;
  m.linked[0].gain[2] = 0;  // wrist not kept level
  bad.push_back(m);
  m = good;
  m.linked[0].offset = 0.1;
  bad.push_back(m);
  m = good;
  m.num_linked = 0;
  bad.push_back(m);
  m = good;
  m.joints[2].param = kParamD;
  bad.push_back(m);
  m = good;
  std::swap(m.joints[1], m.joints[2]);  // joint order matters
  bad.push_back(m);
  m = good;
  m.rows[2].a = 0;  // no upper arm
  bad.push_back(m);
  m = good;
  m.num_rows = 3;
  bad.push_back(m);
  for (size_t i = 0; i < bad.size(); ++i) EXPECT_FALSE(ypp_from_model(arm, bad[i])) << "variant " << i;
}

TEST(IkYpp, ToolPositionMatchesDhChain) {
  const YppArm<double> arm = mk2_arm(true);
  const ModelD m = mk2_model();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> any(-M_PI, M_PI);
  for (int t = 0; t < 10000; ++t) {
    const double q[3] = {any(rng), any(rng), any(rng)};  // any q, not only in limits
    const Vec3<double> a = ypp_tool_position(arm, q), b = tool_position(m, q);
    ASSERT_LT(dist(a, b), 1e-9) << q[0] << " " << q[1] << " " << q[2];
  }
  // Hand-checked pose: upper arm vertical, forearm horizontal (q2 = -90 deg):
  // tool at 147 + 88 forward, 78 + 135 up.
  const double q[3] = {0, deg(90), deg(-90)};
  const Vec3<double> p = ypp_tool_position(arm, q);
  EXPECT_NEAR(p.x, 235, 1e-12);
  EXPECT_NEAR(p.y, 0, 1e-12);
  EXPECT_NEAR(p.z, 213, 1e-12);
  const double q2[3] = {deg(90), deg(90), deg(-90)};
  const Vec3<double> p2 = dh_tool(q2);
  EXPECT_NEAR(p2.x, 0, 1e-12);
  EXPECT_NEAR(p2.y, 235, 1e-12);
  EXPECT_NEAR(p2.z, 213, 1e-12);
}

class IkYppModes : public ::testing::TestWithParam<bool> {};

TEST_P(IkYppModes, ReachableTargetsEverySolutionChecked) {
  const bool par = GetParam();
  const YppArm<double> arm = mk2_arm(par);
  std::mt19937 rng(par ? 21 : 22);
  int solutions_checked = 0, out_of_limit_solutions = 0;
  for (int t = 0; t < 20000; ++t) {
    double q[3];
    random_pose(q, rng, par);
    ASSERT_TRUE(in_limits_by_hand(q, par));
    const Vec3<double> target = dh_tool(q);
    YppResult<double> r;
    ypp_solve(r, arm, target);
    ASSERT_EQ(r.status, kYppReached) << t;
    ASSERT_GE(r.count, 1);
    ASSERT_LE(r.count, 4);
    bool found = false, seen_out = false;
    for (int i = 0; i < r.count; ++i) {
      const YppSolution<double>& s = r.solutions[i];
      ASSERT_LT(dist(dh_tool(s.q), target), 1e-6) << t << " solution " << i;
      ASSERT_EQ(s.in_limits, in_limits_by_hand(s.q, par)) << t << " solution " << i;
      // In-limits solutions come first.
      if (!s.in_limits) seen_out = true;
      ASSERT_FALSE(s.in_limits && seen_out) << t;
      if (!s.in_limits) ++out_of_limit_solutions;
      if (angle_diff(s.q[0], q[0]) < 1e-6 && angle_diff(s.q[1], q[1]) < 1e-6 && angle_diff(s.q[2], q[2]) < 1e-6)
        found = true;
      ++solutions_checked;
    }
    ASSERT_TRUE(found) << "the generating pose is missing, target " << t;
    ASSERT_TRUE(r.solutions[0].in_limits);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.nearest_q[k], r.solutions[0].q[k]);
    EXPECT_LT(dist(r.nearest, target), 1e-6);
    EXPECT_EQ(r.distance, 0);
  }
  EXPECT_GT(out_of_limit_solutions, 1000);  // the out-of-limits ones were checked as well
  std::cout << "[ solved   ] 20000 targets, " << solutions_checked << " solutions checked by FK\n";
}

// The firmware's P runs the closed form alone: the same solutions as ypp_solve, in the
// same order, its return the count within the limits, nonzero exactly when reached.
TEST_P(IkYppModes, ClosedFormIsTheStartOfSolve) {
  const bool par = GetParam();
  const YppArm<double> arm = mk2_arm(par);
  YppArm<float> armf{};
  armf.base_height = 78;
  armf.upper = 135;
  armf.fore = 147;
  armf.tool_forward = 88;
  armf.parallelogram = par;
  for (int i = 0; i < 3; ++i) {
    armf.lo[i] = float(arm.lo[i]);
    armf.hi[i] = float(arm.hi[i]);
  }
  std::mt19937 rng(par ? 31 : 32);
  std::uniform_real_distribution<double> u(-450, 450);
  int counts[3] = {0, 0, 0};  // reached, limited, out of reach
  for (int t = 0; t < 20000; ++t) {
    double q[3];
    random_pose(q, rng, par);
    const Vec3<double> target = t % 2 ? dh_tool(q) : make_vec3(u(rng), u(rng), u(rng) / 2 + 150);
    YppResult<double> full, closed;
    ypp_solve(full, arm, target, t % 3 == 0);
    const int in_limits = ypp_closed_form(closed, arm, target);
    ASSERT_EQ(closed.count, full.count) << t;
    int n = 0;
    for (int i = 0; i < closed.count; ++i) {
      n += closed.solutions[i].in_limits;
      ASSERT_EQ(closed.solutions[i].in_limits, full.solutions[i].in_limits) << t;
      for (int k = 0; k < 3; ++k) ASSERT_EQ(closed.solutions[i].q[k], full.solutions[i].q[k]) << t;
    }
    ASSERT_EQ(in_limits, n) << t;
    ASSERT_EQ(in_limits > 0, full.status == kYppReached) << t;
    ++counts[full.status];
    // The float path the Nano runs agrees with its own ypp_solve too.
    YppResult<float> ff, cf;
    const Vec3<float> tf = make_vec3(float(target.x), float(target.y), float(target.z));
    ypp_solve(ff, armf, tf, false);
    ASSERT_EQ(ypp_closed_form(cf, armf, tf) > 0, ff.status == kYppReached) << t;
    ASSERT_EQ(cf.count, ff.count) << t;
  }
  EXPECT_GT(counts[kYppReached], 10000);
  EXPECT_GT(counts[kYppLimited], 100);
  EXPECT_GT(counts[kYppOutOfReach], 100);
}

TEST_P(IkYppModes, BeyondFullReach) {
  const bool par = GetParam();
  const YppArm<double> arm = mk2_arm(par);
  const double home_act[3] = {0, deg(90), 0};  // upper arm up, forearm level
  const double home[3] = {home_act[0], home_act[1], home_act[2] - home_act[1]};
  const Vec3<double> home_p = dh_tool(home);
  const Vec3<double> targets[] = {make_vec3(1000.0, 0.0, 100.0), make_vec3(0.0, 600.0, 300.0),
                                  make_vec3(300.0, -300.0, -200.0), make_vec3(50.0, 20.0, 900.0)};
  for (const Vec3<double>& target : targets) {
    YppResult<double> r;
    ypp_solve(r, arm, target);
    EXPECT_EQ(r.status, kYppOutOfReach);
    EXPECT_EQ(r.count, 0);
    EXPECT_GT(r.distance, 0);
    EXPECT_TRUE(in_limits_tol(r.nearest_q, par)) << target.x << " " << target.y << " " << target.z;
    EXPECT_LT(dist(dh_tool(r.nearest_q), r.nearest), 1e-9);
    EXPECT_NEAR(r.distance, dist(r.nearest, target), 1e-9);
    EXPECT_LT(r.distance, dist(home_p, target));
    // Nothing within reach comes closer than (distance to the wrist's reach sphere).
    const double rho = std::hypot(target.x, target.y);
    const double w = rho - arm.tool_forward, v = target.z - arm.base_height;
    EXPECT_GE(r.distance, std::hypot(w, v) - (arm.upper + arm.fore) - 1e-9);
  }
  // (1000, 0, 100): straight ahead, so the best is the arm stretched toward it within
  // limits; its yaw is 0.
  YppResult<double> r;
  ypp_solve(r, arm, make_vec3(1000.0, 0.0, 100.0));
  EXPECT_NEAR(r.nearest_q[0], 0, 1e-12);
  EXPECT_NEAR(r.nearest.y, 0, 1e-9);
}

TEST_P(IkYppModes, LimitedBehindTheBase) {
  const bool par = GetParam();
  const YppArm<double> arm = mk2_arm(par);
  // Behind the base, low down: facing it needs yaw 180 deg (limit 90); reaching back over
  // the top needs the upper arm far below the horizontal.
  const Vec3<double> target = make_vec3(-150.0, 0.0, 0.0);
  YppResult<double> r;
  ypp_solve(r, arm, target);
  EXPECT_EQ(r.status, kYppLimited);
  EXPECT_EQ(r.count, 4);
  for (int i = 0; i < r.count; ++i) {
    EXPECT_FALSE(r.solutions[i].in_limits);
    EXPECT_FALSE(in_limits_by_hand(r.solutions[i].q, par));
    EXPECT_LT(dist(dh_tool(r.solutions[i].q), target), 1e-6);
  }
  EXPECT_TRUE(in_limits_tol(r.nearest_q, par));
  EXPECT_LT(dist(dh_tool(r.nearest_q), r.nearest), 1e-9);
  EXPECT_GT(r.distance, 0);
  EXPECT_NEAR(r.distance, dist(r.nearest, target), 1e-9);
}

TEST_P(IkYppModes, InsideTheInnerRadius) {
  const bool par = GetParam();
  const YppArm<double> arm = mk2_arm(par);
  // Where the wrist would sit on the shoulder axis when facing the target: closer than
  // |L1 - L2| = 12 mm for that facing. Facing away, the arm reaches back (yaw 180 deg,
  // beyond the base limit): geometric solutions exist, none within limits.
  const Vec3<double> target = make_vec3(88.0, 0.0, 78.0);
  YppResult<double> r;
  ypp_solve(r, arm, target);
  EXPECT_EQ(r.status, kYppLimited);
  EXPECT_EQ(r.count, 2);
  for (int i = 0; i < r.count; ++i) {
    EXPECT_NEAR(angle_diff(r.solutions[i].q[0], M_PI), 0, 1e-12);
    EXPECT_LT(dist(dh_tool(r.solutions[i].q), target), 1e-6);
  }
  EXPECT_TRUE(in_limits_tol(r.nearest_q, par));
  EXPECT_LT(dist(dh_tool(r.nearest_q), r.nearest), 1e-9);
  EXPECT_NEAR(r.distance, dist(r.nearest, target), 1e-9);
}

TEST(IkYpp, InsideInnerRadiusOfBothFacings) {
  // An arm with no tool offset: on the base axis near the shoulder both facings fail.
  YppArm<double> arm = {50, 0, 100, 60, 0, 0, false, {-M_PI, -M_PI, -M_PI}, {M_PI, M_PI, M_PI}};
  const Vec3<double> target = make_vec3(0.0, 0.0, 60.0);  // 10 mm above the shoulder: < 40
  YppResult<double> r;
  ypp_solve(r, arm, target);
  EXPECT_EQ(r.status, kYppOutOfReach);
  EXPECT_EQ(r.count, 0);
  // Folded (q2 = 180 deg) toward the target: the wrist 40 mm up, 30 mm from it.
  EXPECT_NEAR(r.distance, 30, 1e-9);
  EXPECT_NEAR(r.nearest.z, 90, 1e-9);
  EXPECT_NEAR(dist(ypp_tool_position(arm, r.nearest_q), r.nearest), 0, 1e-9);
  // The same with the longer forearm: folded, the wrist points the other way.
  arm.upper = 60;
  arm.fore = 100;
  ypp_solve(r, arm, target);
  EXPECT_EQ(r.status, kYppOutOfReach);
  EXPECT_NEAR(r.distance, 30, 1e-9);
  EXPECT_NEAR(r.nearest.z, 90, 1e-9);
}

TEST(IkYpp, FourGeometricSolutionsForAGenericPoint) {
  const Vec3<double> target = make_vec3(100.0, 50.0, 150.0);
  for (bool par : {true, false}) {
    YppArm<double> arm = mk2_arm(par);
    for (int i = 0; i < 3; ++i) {  // no limits: every solution counts
      arm.lo[i] = -10;
      arm.hi[i] = 10;
    }
    YppResult<double> r;
    ypp_solve(r, arm, target);
    EXPECT_EQ(r.status, kYppReached);
    ASSERT_EQ(r.count, 4);
    int facing_target = 0;
    for (int i = 0; i < 4; ++i) {
      EXPECT_TRUE(r.solutions[i].in_limits);
      EXPECT_LT(dist(dh_tool(r.solutions[i].q), target), 1e-9);
      if (angle_diff(r.solutions[i].q[0], std::atan2(50.0, 100.0)) < 1e-12) ++facing_target;
      for (int j = 0; j < i; ++j) {  // four distinct poses
        const double d = angle_diff(r.solutions[i].q[0], r.solutions[j].q[0]) +
                         angle_diff(r.solutions[i].q[1], r.solutions[j].q[1]) +
                         angle_diff(r.solutions[i].q[2], r.solutions[j].q[2]);
        EXPECT_GT(d, 1e-3);
      }
    }
    EXPECT_EQ(facing_target, 2);  // two elbows each way
  }
}

TEST(IkYpp, HomePoseWithLimits) {
  // Home: upper arm up, forearm level: tool at (147 + 88, 0, 78 + 135) = (235, 0, 213).
  // Facing it the wrist is (147, 135) from the shoulder: the other elbow puts the upper arm
  // at 42.56 - 47.44 = -4.9 deg (below its 36 deg limit). Facing away the wrist would be
  // (-323, 135) away, 350 mm > 282: out of reach. So two solutions, one in limits.
  for (bool par : {true, false}) {
    YppResult<double> r;
    ypp_solve(r, mk2_arm(par), make_vec3(235.0, 0.0, 213.0));
    EXPECT_EQ(r.status, kYppReached);
    ASSERT_EQ(r.count, 2);
    EXPECT_TRUE(r.solutions[0].in_limits);
    EXPECT_FALSE(r.solutions[1].in_limits);
    EXPECT_NEAR(r.solutions[0].q[0], 0, 1e-12);
    EXPECT_NEAR(r.solutions[0].q[1], deg(90), 1e-12);
    EXPECT_NEAR(r.solutions[0].q[2], deg(-90), 1e-12);
    EXPECT_NEAR(r.solutions[1].q[1], deg(90) - 2 * std::atan2(147.0, 135.0), 1e-12);
    EXPECT_NEAR(r.solutions[1].q[2], deg(90), 1e-12);
  }
}

TEST(IkYpp, FloatSolverAccuracy) {
  for (bool par : {true, false}) {
    const YppArm<double> armd = mk2_arm(par);
    YppArm<float> arm;
    arm.base_height = float(armd.base_height);
    arm.shoulder_offset = float(armd.shoulder_offset);
    arm.upper = float(armd.upper);
    arm.fore = float(armd.fore);
    arm.tool_forward = float(armd.tool_forward);
    arm.tool_up = float(armd.tool_up);
    arm.parallelogram = armd.parallelogram;
    for (int i = 0; i < 3; ++i) {
      arm.lo[i] = float(armd.lo[i]);
      arm.hi[i] = float(armd.hi[i]);
    }
    std::vector<Vec3<double>> targets;
    std::mt19937 rng(par ? 31 : 32);
    for (int t = 0; t < 20000; ++t) {
      double q[3];
      random_pose(q, rng, par);
      targets.push_back(dh_tool(q));
    }
    // The edge of the workspace: elbow straight (outside the MK2 limits, still geometric).
    std::uniform_real_distribution<double> any(-M_PI, M_PI);
    for (int t = 0; t < 2000; ++t) {
      const double q[3] = {any(rng), any(rng), 0};
      targets.push_back(dh_tool(q));
    }
    // On the base axis (x = y = 0) at several heights.
    for (int z = -150; z <= 400; z += 10) targets.push_back(make_vec3(0.0, 0.0, double(z)));
    double worst = 0;
    int reached = 0, solutions = 0;
    for (const Vec3<double>& target : targets) {
      YppResult<float> r;
      ypp_solve(r, arm, cast<float>(target));
      ASSERT_TRUE(is_finite(r.nearest.x) && is_finite(r.nearest.y) && is_finite(r.nearest.z));
      ASSERT_TRUE(is_finite(r.distance));
      reached += r.status == kYppReached;
      for (int i = 0; i < r.count; ++i) {
        const double qd[3] = {r.solutions[i].q[0], r.solutions[i].q[1], r.solutions[i].q[2]};
        for (double v : qd) ASSERT_TRUE(std::isfinite(v));
        const double e = dist(dh_tool(qd), target);
        worst = std::max(worst, e);
        ASSERT_LT(e, 0.05) << target.x << " " << target.y << " " << target.z;
        ++solutions;
      }
      // Every stretched and every in-limits target is geometrically reachable in float too.
      if (&target - targets.data() < 22000) {
        ASSERT_GE(r.count, 1) << target.x << " " << target.y << " " << target.z;
      }
    }
    EXPECT_GE(reached, 20000);
    std::cout << "[ float    ] " << (par ? "parallelogram" : "plain DH") << ": " << solutions
              << " solutions, worst FK error " << worst << " mm\n";
    ::testing::Test::RecordProperty(par ? "float_worst_mm_parallelogram" : "float_worst_mm_dh", std::to_string(worst));
  }
}

TEST(IkYpp, NearestReachablePointAgainstAGridSearch) {
  // For unreachable targets the solver's nearest point (within the limits) is compared with
  // a brute-force search over a 2-degree grid of the actuated limits. The solver may beat
  // the grid (it is continuous); it may lose to it only by a little, and rarely.
  const YppArm<double> arm = mk2_arm(true);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-450, 450);
  int unreachable = 0, behind_by_1mm = 0;
  double worst_excess = 0, without_polish_excess = 0;
  for (int i = 0; i < 120; ++i) {
    const Vec3<double> t = make_vec3(u(rng), u(rng), u(rng));
    YppResult<double> r;
    ypp_solve(r, arm, t);
    if (r.status == kYppReached) continue;
    ++unreachable;
    double grid = 1e300;
    for (double a = kActLo[0]; a <= kActHi[0]; a += 2)
      for (double b = kActLo[1]; b <= kActHi[1]; b += 2)
        for (double c = kActLo[2]; c <= kActHi[2]; c += 2) {
          const double q[3] = {deg(a), deg(b), deg(c - b)};
          grid = std::min(grid, dist(ypp_tool_position(arm, q), t));
        }
    worst_excess = std::max(worst_excess, r.distance - grid);
    behind_by_1mm += r.distance > grid + 1;
    EXPECT_TRUE(in_limits_tol(r.nearest_q, true, 1e-9));
    YppResult<double> cheap;
    ypp_solve(cheap, arm, t, false);
    EXPECT_EQ(cheap.status, r.status);
    EXPECT_GE(cheap.distance, r.distance - 1e-9);  // polishing never makes it worse
    without_polish_excess = std::max(without_polish_excess, cheap.distance - grid);
  }
  std::cout << "[ nearest  ] " << unreachable << " unreachable targets: " << behind_by_1mm
            << " more than 1 mm behind a 2-degree grid search; worst excess " << worst_excess
            << " mm (unpolished: " << without_polish_excess << " mm)\n";
  EXPECT_GT(unreachable, 100);
  EXPECT_LE(behind_by_1mm, unreachable / 30);
  EXPECT_LT(worst_excess, 10);
}

INSTANTIATE_TEST_SUITE_P(Mk2, IkYppModes, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Parallelogram" : "PlainDh"; });
