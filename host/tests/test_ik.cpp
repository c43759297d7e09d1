// Tests of the inverse kinematics (host/lib/ik.h) and of the forward kinematics of the
// shipped industrial robots (PUMA 560, Panda), plus the thesis's IK experiment redone
// (section 5.4; docs/ik.md shows the table the last test prints). No timing here: speed is
// measured in bench/.
#include "ik.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "records_json.h"
#include "robot_file.h"
#include "robot_view.h"

namespace {

using namespace articula;
using namespace articula::host;

const std::string kRobots = std::string(ARTICULA_SOURCE_DIR) + "/robots/";
const double kPi = 3.14159265358979323846;

double rad(double deg) { return deg * kPi / 180.0; }

const Robot& robot(const std::string& name) {
  static std::map<std::string, Robot> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, load_robot_file(kRobots + name + ".json")).first;
  return it->second;
}

Transform<double> fk(const Robot& r, const std::vector<double>& q) {
  HostFrames f;
  forward_kinematics(f, r.model, q.data());
  return f.T_base_tool;
}

// A pose within every limit: uniform joint values, or for a robot with motors uniform motor
// angles (q = C u), which is what the real arm can do.
std::vector<double> random_pose(const Robot& r, std::mt19937_64& rng) {
  const int n = r.model.num_joints;
  std::vector<double> q(static_cast<size_t>(n), 0.0);
  if (r.has_motors) {
    double u[kMaxJoints];
    for (int k = 0; k < n; ++k)
      u[k] = rad(std::uniform_real_distribution<double>(r.actuation.motors[k].min / 1000.0,
                                                        r.actuation.motors[k].max / 1000.0)(rng));
    joints_from_actuators(q.data(), r.actuation, u);
  } else {
    for (int j = 0; j < n; ++j)
      q[size_t(j)] = std::uniform_real_distribution<double>(r.model.joints[j].lo, r.model.joints[j].hi)(rng);
  }
  return q;
}

// Every limit, checked independently of the solver: joint limits exactly, motor limits (u =
// C^-1 q) up to the rounding of the product.
void expect_within_limits(const Robot& r, const std::vector<double>& q, const std::string& what) {
  ASSERT_EQ(int(q.size()), r.model.num_joints) << what;
  for (int j = 0; j < r.model.num_joints; ++j) {
    EXPECT_GE(q[size_t(j)], r.model.joints[j].lo) << what << " joint " << j;
    EXPECT_LE(q[size_t(j)], r.model.joints[j].hi) << what << " joint " << j;
  }
  if (!r.has_motors) return;
  double u[kMaxJoints];
  actuators_from_joints(u, r.actuation, q.data());
  for (int k = 0; k < r.actuation.num_motors; ++k) {
    EXPECT_GE(u[k], rad(r.actuation.motors[k].min / 1000.0) - 1e-9) << what << " motor " << k;
    EXPECT_LE(u[k], rad(r.actuation.motors[k].max / 1000.0) + 1e-9) << what << " motor " << k;
  }
}

// The result's own claims, recomputed: the tool pose and errors at q, and "reached" only
// within the tolerances.
void expect_honest(const Robot& r, const IkTarget& t, const IkResult& res, const IkOptions& o,
                   const std::string& what) {
  expect_within_limits(r, res.q, what);
  const Transform<double> T = fk(r, res.q);
  const double pos = norm(T.p - t.position);
  const double rot = t.has_rotation ? norm(orientation_error(t.rotation, T.R)) : 0.0;
  EXPECT_NEAR(res.position_error_mm, pos, 1e-9) << what;
  EXPECT_NEAR(res.orientation_error_rad, rot, 1e-9) << what;
  if (res.reached()) {
    EXPECT_LE(pos, o.position_tolerance_mm) << what;
    EXPECT_LE(rot, o.orientation_tolerance_rad) << what;
  } else {
    EXPECT_TRUE(pos > o.position_tolerance_mm || rot > o.orientation_tolerance_rad)
        << what << ": within tolerance but reported " << ik_status_name(res.status);
  }
}

// ---------------------------------------------------------------------------------------
// Forward kinematics of the industrial robots

// Craig (3rd ed.) eq. 3.14: the PUMA 560's tool position and approach vector (third
// column of 0T6) in closed form, for his modified DH table.
void puma_craig(const std::vector<double>& q, Vec3<double>& p, Vec3<double>& z6) {
  const double d1 = 660.4, a2 = 431.8, a3 = 20.32, d3 = 150.05, d4 = 431.8;  // d1: the pedestal
  const double c1 = std::cos(q[0]), s1 = std::sin(q[0]), c2 = std::cos(q[1]), s2 = std::sin(q[1]);
  const double c23 = std::cos(q[1] + q[2]), s23 = std::sin(q[1] + q[2]);
  const double c4 = std::cos(q[3]), s4 = std::sin(q[3]), c5 = std::cos(q[4]), s5 = std::sin(q[4]);
  const double reach = a2 * c2 + a3 * c23 - d4 * s23;
  p = make_vec3(c1 * reach - d3 * s1, s1 * reach + d3 * c1, d1 - a3 * s23 - a2 * s2 - d4 * c23);
  z6 = make_vec3(-c1 * (c23 * c4 * s5 + s23 * c5) - s1 * s4 * s5, -s1 * (c23 * c4 * s5 + s23 * c5) + c1 * s4 * s5,
                 s23 * c4 * s5 - c23 * c5);
}

TEST(IkForwardKinematics, Puma560MatchesCraigsClosedForm) {
  const Robot& r = robot("puma560");
  ASSERT_EQ(r.model.num_joints, 6);
  // At q = 0 by hand: the upper arm along x (a2) at the shoulder's height (d1, the pedestal),
  // the shoulder offset d3 along y, the forearm down the -z axis (d4), frame 6 turned 180 deg
  // about x.
  const Transform<double> T0 = fk(r, std::vector<double>(6, 0.0));
  EXPECT_NEAR(T0.p.x, 452.12, 1e-9);
  EXPECT_NEAR(T0.p.y, 150.05, 1e-9);
  EXPECT_NEAR(T0.p.z, 660.4 - 431.8, 1e-9);
  const double R0[3][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(T0.R.m[i][j], R0[i][j], 1e-12);
  std::mt19937_64 rng(560);
  for (int i = 0; i < 200; ++i) {
    const std::vector<double> q = random_pose(r, rng);
    Vec3<double> p, z6;
    puma_craig(q, p, z6);
    const Transform<double> T = fk(r, q);
    EXPECT_LT(norm(T.p - p), 1e-9) << i;
    EXPECT_LT(norm(T.R.col(2) - z6), 1e-12) << i;
  }
}

// The Panda exactly as published (7 rows, a4 = -82.5 mm), built in code.
HostModel panda_published() {
  const Robot& file = robot("panda");
  HostModel m{};
  const double a[7] = {0, 0, 0, 82.5, -82.5, 0, 88};
  const double d[7] = {333, 0, 316, 0, 384, 0, 0};
  const double alpha[7] = {0, -90, 90, 90, -90, 90, 90};
  m.num_rows = 7;
  m.num_joints = 7;
  for (int i = 0; i < 7; ++i) {
    m.rows[i] = DhRow<double>{a[i], rad(alpha[i]), d[i], 0.0};
    m.joints[i] = JointSpec<double>{uint8_t(i), kParamTheta, file.model.joints[i].lo, file.model.joints[i].hi};
  }
  m.T_last_tool = make_transform(identity3<double>(), make_vec3(0.0, 0.0, 107.0));
  return m;
}

TEST(IkForwardKinematics, PandaByHand) {
  const Robot& r = robot("panda");
  ASSERT_EQ(r.model.num_joints, 7);
  // q = 0: z up through 333 + 316 + 384 = 1033 mm, the 82.5 mm offsets out and back, 88 mm
  // forward at the wrist, and the flange 107 mm down: (88, 0, 926), z pointing down.
  const Transform<double> T0 = fk(r, std::vector<double>(7, 0.0));
  EXPECT_NEAR(T0.p.x, 88, 1e-9);
  EXPECT_NEAR(T0.p.y, 0, 1e-9);
  EXPECT_NEAR(T0.p.z, 926, 1e-9);
  // q4 = -90, q6 = 90: the forearm (384 mm) horizontal at 649 + 82.5 mm, the wrist 88 mm
  // further, the flange 107 mm down: (82.5 + 384 + 88, 0, 731.5 - 107).
  const Transform<double> T1 = fk(r, {0, 0, 0, rad(-90), 0, rad(90), 0});
  EXPECT_NEAR(T1.p.x, 554.5, 1e-9);
  EXPECT_NEAR(T1.p.y, 0, 1e-9);
  EXPECT_NEAR(T1.p.z, 624.5, 1e-9);
  const double R[3][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}};  // both poses
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(T0.R.m[i][j], R[i][j], 1e-12);
      EXPECT_NEAR(T1.R.m[i][j], R[i][j], 1e-12);
    }
}

TEST(IkForwardKinematics, PandaFileIsThePublishedTableAndItsNegativeAIsRight) {
  // The file holds the published rows as they are, row 5 with a = -82.5 mm. The same arm
  // with every a >= 0 takes two more rows: a fixed turn of 180 deg about z4, the row with
  // a = +82.5 mm and alpha = +90 deg, a fixed turn of -180 deg about z5
  // (Rz(pi) Rx(90) Tx(82.5) Rz(q5) Tz(384) Rz(-pi) = Rx(-90) Tx(-82.5) Rz(q5) Tz(384)).
  // Both give the same tool pose and Jacobian.
  const Robot& r = robot("panda");
  const HostModel pub = panda_published();
  ASSERT_EQ(r.model.num_rows, 7);
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(r.model.rows[i].a, pub.rows[i].a) << i;
    EXPECT_NEAR(r.model.rows[i].alpha, pub.rows[i].alpha, 1e-15) << i;
    EXPECT_EQ(r.model.rows[i].d, pub.rows[i].d) << i;
  }
  HostModel nine{};
  const double a[9] = {0, 0, 0, 82.5, 0, 82.5, 0, 0, 88};
  const double d[9] = {333, 0, 316, 0, 0, 384, 0, 0, 0};
  const double alpha[9] = {0, -90, 90, 90, 0, 90, 0, 90, 90};
  const double theta[9] = {0, 0, 0, 0, 180, 0, -180, 0, 0};
  const int joint_row[7] = {0, 1, 2, 3, 5, 7, 8};
  nine.num_rows = 9;
  nine.num_joints = 7;
  for (int i = 0; i < 9; ++i) nine.rows[i] = DhRow<double>{a[i], rad(alpha[i]), d[i], rad(theta[i])};
  for (int j = 0; j < 7; ++j)
    nine.joints[j] = JointSpec<double>{uint8_t(joint_row[j]), kParamTheta, pub.joints[j].lo, pub.joints[j].hi};
  nine.T_last_tool = pub.T_last_tool;
  ASSERT_EQ(validate(nine), kModelOk);
  std::mt19937_64 rng(7);
  for (int i = 0; i < 200; ++i) {
    const std::vector<double> q = random_pose(r, rng);
    HostFrames fa, fb;
    forward_kinematics(fa, r.model, q.data());
    forward_kinematics(fb, nine, q.data());
    EXPECT_LT(norm(fa.T_base_tool.p - fb.T_base_tool.p), 1e-9);
    for (int c = 0; c < 3; ++c) EXPECT_LT(norm(fa.T_base_tool.R.col(c) - fb.T_base_tool.R.col(c)), 1e-12);
    double Ja[6][kMaxJoints], Jb[6][kMaxJoints];
    jacobian(Ja, r.model, fa);
    jacobian(Jb, nine, fb);
    for (int row = 0; row < 6; ++row)
      for (int j = 0; j < 7; ++j) EXPECT_NEAR(Ja[row][j], Jb[row][j], 1e-9);
  }
}

// ---------------------------------------------------------------------------------------
// Small parts

TEST(IkBasics, MethodAndStatusNames) {
  for (IkMethod m :
       {IkMethod::kAuto, IkMethod::kLevenbergMarquardt, IkMethod::kJacobianTranspose, IkMethod::kClosedForm}) {
    IkMethod back = IkMethod::kAuto;
    EXPECT_TRUE(parse_ik_method(ik_method_name(m), back));
    EXPECT_EQ(back, m);
  }
  IkMethod x;
  EXPECT_FALSE(parse_ik_method("newton", x));
  EXPECT_STREQ(ik_status_name(IkStatus::kReached), "reached");
  EXPECT_STREQ(ik_status_name(IkStatus::kUnreachable), "unreachable");
  EXPECT_STREQ(ik_status_name(IkStatus::kLimited), "limited");
  EXPECT_STREQ(ik_status_name(IkStatus::kBudget), "budget");
}

TEST(IkBasics, OrientationErrorIsTheRotationVector) {
  const Mat3<double> I = identity3<double>();
  EXPECT_LT(norm(orientation_error(I, I)), 1e-15);
  // Target = Rz(a) * current: the error is a about z, at every angle up to pi.
  for (double a : {1e-9, 1e-4, 0.3, kPi / 2, 3.0, kPi - 1e-7, kPi}) {
    const Mat3<double> Rc = rpy_to_matrix(0.2, -0.4, 1.0);
    const Vec3<double> e = orientation_error(rot_z(a) * Rc, Rc);
    EXPECT_NEAR(e.x, 0, 1e-9) << a;
    EXPECT_NEAR(e.y, 0, 1e-9) << a;
    EXPECT_NEAR(std::fabs(e.z), a, 1e-9) << a;
    if (a < 3) {
      EXPECT_GT(e.z, 0) << a;
    }
  }
  // About an oblique axis, near pi.
  const Vec3<double> axis = (1 / std::sqrt(14.0)) * make_vec3(1.0, -2.0, 3.0);
  const double angle = kPi - 1e-5;
  // Rodrigues: R = I + sin K + (1 - cos) K^2.
  const double K[3][3] = {{0, -axis.z, axis.y}, {axis.z, 0, -axis.x}, {-axis.y, axis.x, 0}};
  Mat3<double> R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double k2 = 0;
      for (int k = 0; k < 3; ++k) k2 += K[i][k] * K[k][j];
      R.m[i][j] = (i == j ? 1 : 0) + std::sin(angle) * K[i][j] + (1 - std::cos(angle)) * k2;
    }
  const Vec3<double> e = orientation_error(R, I);
  EXPECT_LT(norm(e - angle * axis), 1e-8);
}

TEST(IkBasics, ReachBound) {
  const InverseKinematics mk2(robot("mk2plus"));
  EXPECT_NEAR(mk2.reach_bound(), 135 + 147 + 88, 1e-9);
  EXPECT_NEAR(mk2.reach_centre().z, 78, 1e-12);
  EXPECT_TRUE(mk2.has_closed_form());
  const InverseKinematics arm8(robot("three-link-8dof"));
  EXPECT_NEAR(arm8.reach_bound(), 210, 1e-9);
  EXPECT_NEAR(norm(arm8.reach_centre()), 0, 1e-12);
  EXPECT_FALSE(arm8.has_closed_form());
  // Every pose of every robot lies within its bound.
  for (const char* name : {"mk2plus", "thesis-example", "three-link-8dof", "puma560", "panda"}) {
    const Robot& r = robot(name);
    const InverseKinematics ik(r);
    std::mt19937_64 rng(3);
    for (int i = 0; i < 500; ++i)
      EXPECT_LE(norm(fk(r, random_pose(r, rng)).p - ik.reach_centre()), ik.reach_bound() + 1e-9) << name;
  }
}

TEST(IkBasics, BadInputsThrow) {
  const Robot& r = robot("panda");
  const InverseKinematics ik(r);
  const IkTarget t = IkTarget::at(make_vec3(300.0, 0.0, 500.0));
  EXPECT_THROW(ik.solve(t, std::vector<double>(6, 0.0)), std::invalid_argument);
  IkOptions o;
  o.weights = {1, 1, 1};
  EXPECT_THROW(ik.solve(t, r.home, o), std::invalid_argument);
  o.weights = {1, 1, 1, -1, 1, 1, 1};
  EXPECT_THROW(ik.solve(t, r.home, o), std::invalid_argument);
  o.weights = {};
  o.method = IkMethod::kClosedForm;  // not a yaw-pitch-pitch arm
  EXPECT_THROW(ik.solve(t, r.home, o), std::invalid_argument);
  EXPECT_THROW(ik.solve(IkTarget::at(make_vec3(std::nan(""), 0.0, 0.0)), r.home), std::invalid_argument);
  // A frozen joint must start within its limits (it can neither move nor stay otherwise).
  IkOptions frozen;
  frozen.weights = {1, 1, 1, 0, 1, 1, 1};
  std::vector<double> start = r.home;
  start[3] = 0;  // q4 is limited to -176..-4 deg
  EXPECT_THROW(ik.solve(t, start, frozen), std::invalid_argument);
  // Not frozen, the same start is clamped into the limits and solved from there.
  const IkResult res = ik.solve(t, start);
  expect_within_limits(r, res.q, "clamped start");
}

// ---------------------------------------------------------------------------------------
// Round trips: FK of a random pose within the limits, IK from the home pose, FK again.

struct RoundTrip {
  const char* robot;
  bool full_pose;
  IkMethod method;
};

void round_trips(const RoundTrip& rt, int count) {
  const Robot& r = robot(rt.robot);
  const InverseKinematics ik(r);
  IkOptions o;
  o.method = rt.method;
  std::mt19937_64 rng(1234);
  int reached = 0;
  for (int i = 0; i < count; ++i) {
    const std::vector<double> q = random_pose(r, rng);
    const Transform<double> T = fk(r, q);
    const IkTarget t = rt.full_pose ? IkTarget::pose(T) : IkTarget::at(T.p);
    const IkResult res = ik.solve(t, r.home, o);
    const std::string what = std::string(rt.robot) + (rt.full_pose ? " pose " : " point ") + std::to_string(i);
    expect_honest(r, t, res, o, what);
    EXPECT_TRUE(res.reached()) << what << ": " << ik_status_name(res.status) << ", " << res.position_error_mm << " mm, "
                               << res.orientation_error_rad << " rad";
    if (rt.method != IkMethod::kAuto) {
      EXPECT_EQ(res.method, rt.method) << what;
    }
    reached += res.reached();
  }
  std::printf("  %s %s (%s): %d of %d reached\n", rt.robot, rt.full_pose ? "full pose" : "position",
              ik_method_name(rt.method), reached, count);
}

TEST(IkRoundTrip, PositionOnlyEveryRobot) {
  for (const char* name : {"mk2plus", "thesis-example", "three-link-8dof", "puma560", "panda"})
    round_trips({name, false, IkMethod::kAuto}, 100);
}

TEST(IkRoundTrip, FullPoseWhereTheRobotHasTheDof) {
  // Six or more independent variables: the PUMA (6), the Panda (7), the 8-variable robots.
  for (const char* name : {"puma560", "panda", "thesis-example", "three-link-8dof"})
    round_trips({name, true, IkMethod::kAuto}, 100);
}

TEST(IkRoundTrip, NumericSolverOnTheMk2) {
  // The MK2's motors drive the joints through the parallelogram: the numeric solver moves
  // the motors and keeps their limits, like the closed form.
  round_trips({"mk2plus", false, IkMethod::kLevenbergMarquardt}, 100);
  round_trips({"mk2plus", false, IkMethod::kClosedForm}, 100);
}

TEST(IkRoundTrip, AutoPicksTheClosedFormForYawPitchPitchArms) {
  const Robot& r = robot("mk2plus");
  const IkResult res = solve_ik(r, IkTarget::at(fk(r, r.home).p + make_vec3(10.0, 20.0, -30.0)), r.home);
  EXPECT_EQ(res.method, IkMethod::kClosedForm);
  EXPECT_TRUE(res.reached());
  EXPECT_EQ(res.iterations, 0);
  // A full pose, or a frozen joint, goes to the numeric solver.
  IkOptions o;
  o.weights = {0, 1, 1};
  EXPECT_EQ(solve_ik(r, IkTarget::at(fk(r, r.home).p), r.home, o).method, IkMethod::kLevenbergMarquardt);
  EXPECT_EQ(solve_ik(r, IkTarget::pose(fk(r, r.home)), r.home).method, IkMethod::kLevenbergMarquardt);
  EXPECT_EQ(solve_ik(robot("panda"), IkTarget::at(make_vec3(400.0, 0.0, 400.0)), robot("panda").home).method,
            IkMethod::kLevenbergMarquardt);
}

TEST(IkRoundTrip, ClosedFormTakesTheSolutionNearestTheStart) {
  const Robot& r = robot("mk2plus");
  const InverseKinematics ik(r);
  std::mt19937_64 rng(5);
  for (int i = 0; i < 50; ++i) {
    const std::vector<double> q = random_pose(r, rng);
    // Started at the pose itself, the closed form returns that pose (not another elbow).
    const IkResult res = ik.solve(IkTarget::at(fk(r, q).p), q);
    ASSERT_TRUE(res.reached());
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(res.q[size_t(j)], q[size_t(j)], 1e-9) << i;
  }
}

TEST(IkRoundTrip, AnyMixOfThetaDAlphaAndLinkedParameters) {
  // A SCARA-like arm built in code: two theta joints, a prismatic d (mm), an alpha joint,
  // and a theta linked to the first joint (the tool sits off that row's axis, so the link
  // moves it). Position round trips with both numeric paths.
  HostModel m{};
  m.num_rows = 4;
  m.num_joints = 4;
  m.num_linked = 1;
  m.rows[0] = DhRow<double>{0, 0, 100, 0};
  m.rows[1] = DhRow<double>{150, 0, 0, 0};
  m.rows[2] = DhRow<double>{120, kPi, 0, 0};
  m.rows[3] = DhRow<double>{0, 0, 0, 0};
  m.joints[0] = JointSpec<double>{0, kParamTheta, rad(-150), rad(150)};
  m.joints[1] = JointSpec<double>{1, kParamTheta, rad(-140), rad(140)};
  m.joints[2] = JointSpec<double>{2, kParamD, 20, 150};  // mm
  m.joints[3] = JointSpec<double>{3, kParamAlpha, rad(-90), rad(90)};
  m.linked[0].row = 3;
  m.linked[0].param = kParamTheta;
  m.linked[0].offset = 0;
  m.linked[0].gain[0] = 0.5;
  m.T_last_tool = make_transform(identity3<double>(), make_vec3(30.0, 0.0, 20.0));
  ASSERT_EQ(validate(m), kModelOk);
  const InverseKinematics ik(m);
  std::mt19937_64 rng(17);
  const std::vector<double> start = {0, 0, 50, 0};
  for (IkMethod method : {IkMethod::kAuto, IkMethod::kLevenbergMarquardt}) {
    IkOptions o;
    o.method = method;
    for (int i = 0; i < 50; ++i) {
      std::vector<double> q(4);
      for (int j = 0; j < 4; ++j)
        q[size_t(j)] = std::uniform_real_distribution<double>(m.joints[j].lo, m.joints[j].hi)(rng);
      HostFrames f;
      forward_kinematics(f, m, q.data());
      EXPECT_LE(norm(f.T_base_tool.p - ik.reach_centre()), ik.reach_bound() + 1e-9);
      const IkTarget t = IkTarget::at(f.T_base_tool.p);
      const IkResult res = ik.solve(t, start, o);
      EXPECT_TRUE(res.reached()) << i << " " << ik_status_name(res.status) << " " << res.position_error_mm;
      EXPECT_TRUE(ik.within_all_limits(res.q));
      EXPECT_GE(res.q[2], 20.0);
      EXPECT_LE(res.q[2], 150.0);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Weights

TEST(IkWeights, AZeroWeightJointDoesNotMove) {
  const Robot& r = robot("panda");
  const InverseKinematics ik(r);
  std::mt19937_64 rng(11);
  for (IkMethod m : {IkMethod::kLevenbergMarquardt, IkMethod::kJacobianTranspose}) {
    IkOptions o;
    o.method = m;
    o.weights = {0, 1, 1, 0, 1, 1, 1};  // q1 and q4 frozen
    if (m == IkMethod::kJacobianTranspose) o.position_tolerance_mm = 1;
    for (int i = 0; i < 20; ++i) {
      // A target the arm can reach with q1 and q4 where they start.
      std::vector<double> q = random_pose(r, rng);
      q[0] = r.home[0], q[3] = r.home[3];
      if (m == IkMethod::kJacobianTranspose) {  // near the start: the slow method's easy case
        for (int j = 0; j < 7; ++j) q[size_t(j)] = r.home[size_t(j)] + 0.1 * (q[size_t(j)] - r.home[size_t(j)]);
      }
      const IkTarget t = IkTarget::at(fk(r, q).p);
      const IkResult res = ik.solve(t, r.home, o);
      expect_honest(r, t, res, o, "weights");
      EXPECT_EQ(res.q[0], r.home[0]);
      EXPECT_EQ(res.q[3], r.home[3]);
      EXPECT_TRUE(res.reached()) << ik_method_name(m) << " " << i << ": " << ik_status_name(res.status) << " "
                                 << res.position_error_mm;
    }
  }
}

TEST(IkWeights, WeightsOfACoupledArmAreMotorWeights) {
  // The MK2 with the base motor frozen: the base stays, the other two motors reach what
  // lies in the arm's plane.
  const Robot& r = robot("mk2plus");
  IkOptions o;
  o.weights = {0, 1, 1};
  std::mt19937_64 rng(12);
  for (int i = 0; i < 20; ++i) {
    std::vector<double> q = random_pose(r, rng);
    q[0] = r.home[0];
    const IkTarget t = IkTarget::at(fk(r, q).p);
    const IkResult res = solve_ik(r, t, r.home, o);
    expect_honest(r, t, res, o, "mk2 weights");
    EXPECT_EQ(res.q[0], r.home[0]);
    EXPECT_TRUE(res.reached()) << i;
  }
  // Out of the plane, the frozen base makes it unreachable.
  const IkTarget side = IkTarget::at(fk(r, {rad(45), rad(90), rad(-90)}).p);
  const IkResult res = solve_ik(r, side, r.home, o);
  EXPECT_FALSE(res.reached());
  EXPECT_EQ(res.q[0], r.home[0]);
}

TEST(IkWeights, LowWeightJointsMoveLess) {
  // With a redundant arm, a joint of weight 0.01 takes a smaller part of a small move.
  const Robot& r = robot("panda");
  const IkTarget t = IkTarget::at(fk(r, r.home).p + make_vec3(30.0, 30.0, -20.0));
  IkOptions even, light;
  light.weights = {0.01, 1, 1, 1, 1, 1, 1};
  const IkResult a = solve_ik(r, t, r.home, even), b = solve_ik(r, t, r.home, light);
  ASSERT_TRUE(a.reached());
  ASSERT_TRUE(b.reached());
  EXPECT_LT(std::fabs(b.q[0] - r.home[0]), std::fabs(a.q[0] - r.home[0]));
}

// ---------------------------------------------------------------------------------------
// Limits and statuses

TEST(IkLimits, NeverViolatedWhateverTheTarget) {
  // Reachable and unreachable points and poses, every solver that applies.
  for (const char* name : {"mk2plus", "thesis-example", "three-link-8dof", "puma560", "panda"}) {
    const Robot& r = robot(name);
    const InverseKinematics ik(r);
    std::mt19937_64 rng(99);
    std::vector<IkMethod> methods = {IkMethod::kAuto, IkMethod::kLevenbergMarquardt, IkMethod::kJacobianTranspose};
    if (ik.has_closed_form()) methods.push_back(IkMethod::kClosedForm);
    for (int i = 0; i < 15; ++i) {
      Vec3<double> p;
      for (int k = 0; k < 3; ++k)
        p[k] = ik.reach_centre()[k] + std::uniform_real_distribution<double>(-1.3, 1.3)(rng) * ik.reach_bound();
      const Transform<double> T = fk(r, random_pose(r, rng));
      for (const IkTarget& t : {IkTarget::at(p), IkTarget::pose(make_transform(T.R, p))})
        for (IkMethod m : methods) {
          if (m == IkMethod::kClosedForm && t.has_rotation) continue;
          IkOptions o;
          o.method = m;
          o.max_iterations = m == IkMethod::kJacobianTranspose ? 300 : 200;
          const IkResult res = ik.solve(t, random_pose(r, rng), o);
          expect_honest(r, t, res, o, std::string(name) + " " + ik_method_name(m) + " " + std::to_string(i));
        }
    }
  }
}

TEST(IkStatus, UnreachableStretchesTowardTheTarget) {
  // The 8-variable arm: no limit binds, so the nearest pose is the arm stretched straight at
  // the target, 500 - 210 mm short.
  const Robot& r = robot("three-link-8dof");
  for (IkMethod m : {IkMethod::kLevenbergMarquardt, IkMethod::kAuto}) {
    IkOptions o;
    o.method = m;
    const IkTarget t = IkTarget::at(make_vec3(300.0, -400.0, 0.0));
    const IkResult res = solve_ik(r, t, r.home, o);
    expect_honest(r, t, res, o, "unreachable");
    EXPECT_EQ(res.status, IkStatus::kUnreachable);
    EXPECT_TRUE(res.beyond_reach);
    EXPECT_NEAR(res.position_error_mm, 500 - 210, 1e-3);
    EXPECT_NEAR(res.tool.p.x, 210 * 0.6, 1e-2);
    EXPECT_NEAR(res.tool.p.y, -210 * 0.8, 1e-2);
    EXPECT_TRUE(res.limited_joints.empty());
  }
  // The PUMA, far away: unreachable, beyond its reach; the wrist centre ends on the line
  // to the target. In full pose some wrist limit may hold the orientation back at the
  // nearest pose (then "limited"), but it is never "reached".
  const Robot& puma = robot("puma560");
  const double bound = InverseKinematics(puma).reach_bound();
  const Vec3<double> far = make_vec3(2000.0, 0.0, 660.4);  // at the shoulder's height
  IkResult res = solve_ik(puma, IkTarget::at(far), puma.home);
  EXPECT_EQ(res.status, IkStatus::kUnreachable);
  EXPECT_TRUE(res.beyond_reach);
  EXPECT_GT(res.position_error_mm, 2000 - bound);
  EXPECT_LT(res.position_error_mm, 2000 - 800);  // stretched out: the arm reaches over 800 mm
  res = solve_ik(puma, IkTarget::pose(make_transform(identity3<double>(), far)), puma.home);
  EXPECT_TRUE(res.status == IkStatus::kUnreachable || res.status == IkStatus::kLimited) << ik_status_name(res.status);
  EXPECT_TRUE(res.beyond_reach);
}

TEST(IkStatus, ClosedFormOutOfReachAndLimited) {
  const Robot& r = robot("mk2plus");
  // Far out: the geometry cannot reach it.
  const IkResult far = solve_ik(r, IkTarget::at(make_vec3(1000.0, 0.0, 100.0)), r.home);
  EXPECT_EQ(far.method, IkMethod::kClosedForm);
  EXPECT_EQ(far.status, IkStatus::kUnreachable);
  EXPECT_TRUE(far.beyond_reach);
  expect_within_limits(r, far.q, "far");
  // Behind the base: the geometry reaches it with the base turned 180 deg, the motors
  // (base +-90) do not: limited, and the base motor is at a limit that holds it back.
  const IkTarget behind = IkTarget::at(make_vec3(-250.0, 0.0, 150.0));
  for (IkMethod m : {IkMethod::kAuto, IkMethod::kLevenbergMarquardt}) {
    IkOptions o;
    o.method = m;
    const IkResult res = solve_ik(r, behind, r.home, o);
    expect_honest(r, behind, res, o, "behind");
    EXPECT_EQ(res.status, IkStatus::kLimited) << ik_method_name(m);
    EXPECT_FALSE(res.beyond_reach);
    EXPECT_FALSE(res.limited_motors.empty()) << ik_method_name(m);
    EXPECT_GT(res.position_error_mm, 1);
  }
}

TEST(IkStatus, LimitedReportsTheJointAtItsLimit) {
  // A robot without motors: a planar RR arm whose elbow cannot bend past 90 deg cannot fold
  // onto a point near its shoulder; the elbow's limit holds it back.
  HostModel m{};
  m.num_rows = 2;
  m.num_joints = 2;
  m.rows[0] = DhRow<double>{0, 0, 0, 0};
  m.rows[1] = DhRow<double>{100, 0, 0, 0};
  m.joints[0] = JointSpec<double>{0, kParamTheta, rad(-180), rad(180)};
  m.joints[1] = JointSpec<double>{1, kParamTheta, rad(-90), rad(90)};
  m.T_last_tool = make_transform(identity3<double>(), make_vec3(100.0, 0.0, 0.0));
  const InverseKinematics ik(m);
  const IkResult res = ik.solve(IkTarget::at(make_vec3(30.0, 0.0, 0.0)), {0.0, 0.0});
  EXPECT_EQ(res.status, IkStatus::kLimited);
  ASSERT_EQ(res.limited_joints.size(), 1u);
  EXPECT_EQ(res.limited_joints[0], 1);
  EXPECT_NEAR(std::fabs(res.q[1]), rad(90), 1e-12);
  // The nearest point with the elbow at 90 deg: the tool on a circle of radius 100 sqrt 2.
  EXPECT_NEAR(res.position_error_mm, 100 * std::sqrt(2.0) - 30, 1e-3);
}

TEST(IkStatus, BudgetSpent) {
  const Robot& r = robot("panda");
  std::mt19937_64 rng(4);
  const IkTarget t = IkTarget::pose(fk(r, random_pose(r, rng)));
  IkOptions o;
  o.max_iterations = 2;
  IkResult res = solve_ik(r, t, r.home, o);
  EXPECT_EQ(res.status, IkStatus::kBudget);
  EXPECT_LE(res.iterations, 2);
  expect_honest(r, t, res, o, "budget");
  o.method = IkMethod::kJacobianTranspose;
  o.max_iterations = 5;
  res = solve_ik(r, t, r.home, o);
  EXPECT_EQ(res.status, IkStatus::kBudget);
  EXPECT_EQ(res.iterations, 5);
  // A time budget already over stops at once (before any iteration).
  IkOptions timed;
  timed.time_budget_s = 1e-12;
  res = solve_ik(r, t, r.home, timed);
  EXPECT_EQ(res.status, IkStatus::kBudget);
  expect_honest(r, t, res, timed, "time budget");
}

TEST(IkStatus, DeterministicWithASeed) {
  // Targets that need restarts (poses the Panda cannot take, inside its reach bound),
  // solved twice with one seed: the same answer to the bit.
  const Robot& r = robot("panda");
  std::mt19937_64 rng(8);
  for (int i = 0; i < 5; ++i) {
    // 900 mm from the shoulder: inside the reach bound (986 mm), beyond the real arm.
    const IkTarget t = IkTarget::pose(make_transform(fk(r, random_pose(r, rng)).R, make_vec3(900.0, 0.0, 333.0)));
    IkOptions o;
    o.seed = 42;
    const IkResult a = solve_ik(r, t, r.home, o), b = solve_ik(r, t, r.home, o);
    EXPECT_GT(a.attempts, 1);
    EXPECT_EQ(a.q, b.q);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.iterations, b.iterations);
  }
}

// ---------------------------------------------------------------------------------------
// The Jacobian transpose (thesis 2.2)

TEST(IkJacobianTranspose, ConvergesOnEasyTargets) {
  // Targets a few cm from the start, on the MK2 and the 8-variable arm.
  for (const char* name : {"mk2plus", "three-link-8dof"}) {
    const Robot& r = robot(name);
    const InverseKinematics ik(r);
    IkOptions o;
    o.method = IkMethod::kJacobianTranspose;
    o.position_tolerance_mm = 0.1;
    std::mt19937_64 rng(21);
    int reached = 0;
    for (int i = 0; i < 20; ++i) {
      std::vector<double> q = random_pose(r, rng);
      for (size_t j = 0; j < q.size(); ++j) q[j] = r.home[j] + 0.15 * (q[j] - r.home[j]);
      const IkTarget t = IkTarget::at(fk(r, q).p);
      const IkResult res = ik.solve(t, r.home, o);
      expect_honest(r, t, res, o, std::string("jt ") + name);
      EXPECT_EQ(res.method, IkMethod::kJacobianTranspose);
      reached += res.reached();
    }
    EXPECT_EQ(reached, 20) << name;
  }
}

TEST(IkJacobianTranspose, FailureModesAreClassified) {
  // Far away, too strong a gain (oscillation), a tiny budget: never a crash, never a false
  // "reached", always a status that says why.
  const Robot& r = robot("three-link-8dof");
  const InverseKinematics ik(r);
  IkOptions o;
  o.method = IkMethod::kJacobianTranspose;
  const IkTarget far = IkTarget::at(make_vec3(0.0, 400.0, 0.0));
  IkResult res = ik.solve(far, r.home, o);
  expect_honest(r, far, res, o, "jt far");
  EXPECT_NE(res.status, IkStatus::kReached);
  EXPECT_TRUE(res.beyond_reach);
  o.jt_gain = 50;  // far beyond stable
  const IkTarget near = IkTarget::at(make_vec3(100.0, 50.0, 20.0));
  res = ik.solve(near, r.home, o);
  expect_honest(r, near, res, o, "jt gain");
  for (double v : res.q) EXPECT_TRUE(std::isfinite(v));
  // Started stretched exactly at the target's line: J^T e = 0 from the first step, the
  // method "believes it needs no more rotations" and stops (the thesis's "fell in line").
  o.jt_gain = 0.5;
  const IkTarget in_line = IkTarget::at(make_vec3(100.0, 0.0, 0.0));
  res = ik.solve(in_line, r.home, o);
  expect_honest(r, in_line, res, o, "jt in line");
  EXPECT_EQ(res.status, IkStatus::kUnreachable);
  EXPECT_FALSE(res.beyond_reach);
  EXPECT_NEAR(res.position_error_mm, 110, 1e-9);
  // The default solver is not fooled by the same start.
  EXPECT_TRUE(solve_ik(r, in_line, r.home).reached());
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The thesis's IK experiment (section 5.4, Tables 6 and 7, appendix J), redone: ten random
// targets each for the MK2 arm and the 3-link 8-DOF robot, every run starting where the
// previous one ended unless that run failed (then from the untangled start, as the thesis
// did when a start was "too disadvantageous"). The Jacobian transpose of section 2.2 against
// the default solver, with the thesis's outcome categories; docs/ik.md shows the table this
// prints and how each category is detected.

namespace experiment {

struct Target {
  Vec3<double> p;
  bool reachable;  // within the arm's reach and limits
  double nearest;  // mm: the least distance any pose within the limits leaves (0 if reachable)
};

// The categories of appendix J ("collision loop" needs the physics: issue #5).
std::string category(const IkResult& r, const Target& t) {
  if (r.reached()) return "Yes";
  if (!t.reachable && r.status != IkStatus::kBudget && r.position_error_mm <= t.nearest + 1.0)
    return "Yes (out of reach, stretches toward it)";
  if (r.status == IkStatus::kBudget) return "Overtime";
  if (r.status == IkStatus::kLimited) return "Local minimum (at a joint limit)";
  return "Fell in line with destination";
}

bool success(const std::string& c) { return c.rfind("Yes", 0) == 0; }

struct Arm {
  const char* name;
  std::vector<double> untangled;
  std::vector<Target> targets;
};

Arm mk2_arm() {
  const Robot& r = robot("mk2plus");
  Arm a{"mk2plus", r.home, {}};
  const InverseKinematics ik(r);
  std::mt19937_64 rng(54);
  for (int i = 0; i < 10; ++i) {
    Vec3<double> p;
    if (std::uniform_real_distribution<double>(0, 1)(rng) < 0.7) {
      p = fk(r, random_pose(r, rng)).p;  // a point the arm can reach
    } else {
      p = make_vec3(std::uniform_real_distribution<double>(-450, 450)(rng),
                    std::uniform_real_distribution<double>(-450, 450)(rng),
                    std::uniform_real_distribution<double>(0, 450)(rng));
    }
    // The closed form decides, and for an unreachable point gives the nearest pose (the
    // best of its polished candidates).
    const IkResult c = ik.solve(IkTarget::at(p), r.home);
    a.targets.push_back({p, c.reached(), c.reached() ? 0.0 : c.position_error_mm});
  }
  return a;
}

Arm arm8() {
  // Untangled: a gentle curve in the horizontal plane, every alpha 0.
  Arm a{"three-link-8dof", {0, 0, rad(20), 0, rad(20), 0, rad(20), 0}, {}};
  std::mt19937_64 rng(54);
  while (a.targets.size() < 10) {
    // Uniform in a ball of 1.25 x the reach: about half of the points are out of reach.
    const Vec3<double> p = make_vec3(std::uniform_real_distribution<double>(-1, 1)(rng),
                                     std::uniform_real_distribution<double>(-1, 1)(rng),
                                     std::uniform_real_distribution<double>(-1, 1)(rng));
    if (norm(p) > 1) continue;
    const Vec3<double> t = 262.5 * p;
    // Every direction of every link is possible (theta and alpha both within +-180), so the
    // reachable set is the ball of radius 210 and the nearest point of a far target is on it.
    a.targets.push_back({t, norm(t) <= 210, std::max(0.0, norm(t) - 210)});
  }
  return a;
}

std::string fmt(const char* f, double a, double b, double c) {
  char s[128];
  std::snprintf(s, sizeof s, f, a, b, c);
  return s;
}

}  // namespace experiment

TEST(IkExperiment, ThesisSection54Redone) {
  using namespace experiment;
  int default_failures = 0;
  for (const Arm& arm : {mk2_arm(), arm8()}) {
    const Robot& r = robot(arm.name);
    const InverseKinematics ik(r);
    IkOptions jt, dflt;
    jt.method = IkMethod::kJacobianTranspose;  // h = 0.5 / L^2, 2,000 iterations at most
    // The thesis counted a run a success when the gripper touched the target: 1 mm here,
    // for both solvers.
    jt.position_tolerance_mm = dflt.position_tolerance_mm = 1.0;
    std::vector<double> start_jt = arm.untangled, start_d = arm.untangled;
    std::printf("\n%s (%s), start: untangled pose; tolerance 1 mm\n\n", r.name.c_str(), arm.name);
    std::printf("| run | target x, y, z (mm) | reachable | Jacobian transpose | iterations | distance (mm) "
                "| default (%s) | iterations | distance (mm) |\n",
                ik.has_closed_form() ? "closed form" : "lm");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    int jt_ok = 0, d_ok = 0;
    for (size_t i = 0; i < arm.targets.size(); ++i) {
      const Target& t = arm.targets[i];
      const IkTarget target = IkTarget::at(t.p);
      const IkResult a = ik.solve(target, start_jt, jt);
      const IkResult b = ik.solve(target, start_d, dflt);
      expect_honest(r, target, a, jt, "experiment jt");
      expect_honest(r, target, b, dflt, "experiment default");
      const std::string ca = category(a, t), cb = category(b, t);
      jt_ok += success(ca);
      d_ok += success(cb);
      std::printf("| %zu | %s | %s | %s%s | %d | %.1f | %s | %d | %.1f |\n", i + 1,
                  fmt("%.0f, %.0f, %.0f", t.p.x, t.p.y, t.p.z).c_str(),
                  t.reachable ? "yes" : fmt("no (%.1f mm short)", t.nearest, 0, 0).c_str(), ca.c_str(),
                  start_jt == arm.untangled && i > 0 ? " (restarted untangled)" : "", a.iterations, a.position_error_mm,
                  cb.c_str(), b.iterations, b.position_error_mm);
      // The default solver reaches every reachable target and classifies every other one.
      if (t.reachable) {
        EXPECT_TRUE(b.reached()) << arm.name << " run " << i + 1;
      } else {
        EXPECT_TRUE(b.status == IkStatus::kUnreachable || b.status == IkStatus::kLimited)
            << arm.name << " run " << i + 1;
        EXPECT_LE(b.position_error_mm, t.nearest + 1.0) << arm.name << " run " << i + 1;
      }
      default_failures += !success(cb);
      // Where the next run starts.
      start_jt = success(ca) ? a.q : arm.untangled;
      start_d = success(cb) ? b.q : arm.untangled;
    }
    std::printf("\nsuccesses: Jacobian transpose %d of 10, default %d of 10\n", jt_ok, d_ok);
  }
  EXPECT_EQ(default_failures, 0);
}

// Why a point is not reached, as a student reads it (the blocks' problem, the IK panel): what
// holds the tool back, each joint or motor once, where it stands and its range; how near it comes.
TEST(IkWords, AMissSaysWhatHoldsTheToolBackAndHowNearItComes) {
  const Robot mearm = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mearm.json");
  const InverseKinematics ik(mearm);
  const IkResult low = ik.solve(IkTarget::at({170, 0, 20}), ik_start(mearm, nullptr));
  ASSERT_EQ(low.status, IkStatus::kLimited);
  const std::string w = ik_miss_words(mearm, low);
  EXPECT_EQ(w.rfind("held back by the shoulder ", 0), 0u) << w;
  EXPECT_NE(w.find("(its range 30\xC2\xB0 to 135\xC2\xB0)"), std::string::npos) << w;
  EXPECT_NE(w.find("; the nearest the tool comes is 23.2 mm away"), std::string::npos) << w;
  EXPECT_EQ(w.find("shoulder", w.find("shoulder") + 1), std::string::npos) << "named twice: " << w;
  EXPECT_EQ(ik_result_json(mearm, low)["why"], w);
  const IkResult far = ik.solve(IkTarget::at({900, 0, 0}), ik_start(mearm, nullptr));
  EXPECT_EQ(ik_miss_words(mearm, far).rfind("it is farther than the arm is long; the nearest the tool comes is ", 0), 0u);
  const IkResult near = ik.solve(IkTarget::at({180, 0, 60}), ik_start(mearm, nullptr));
  ASSERT_TRUE(near.reached());
  EXPECT_EQ(ik_miss_words(mearm, near), "");
  EXPECT_FALSE(ik_result_json(mearm, near).contains("why"));
}
