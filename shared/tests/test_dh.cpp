// Tests shared/articula/dh.h: forward kinematics against hand-derived poses, the geometric
// Jacobian against finite differences, linked parameters, validation, float vs double.
#include <articula/dh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

using namespace articula;

namespace {
constexpr int J = 12;
constexpr int R = 8;
using ModelD = Model<double, J, R>;
using FramesD = Frames<double, R>;

double deg(double d) { return d * M_PI / 180; }

DhRow<double> row(double a, double alpha_deg, double d, double theta_deg) {
  return DhRow<double>{a, deg(alpha_deg), d, deg(theta_deg)};
}

void add_joint(ModelD& m, int r, DhParam p, double lo = -10, double hi = 10) {
  m.joints[m.num_joints++] = JointSpec<double>{uint8_t(r), uint8_t(p), lo, hi};
}

ModelD empty_model() {
  ModelD m{};
  m.T_last_tool = Transform<double>::identity();
  return m;
}

// The 4-row robot of thesis Table 1 (section 4.1.2), 1 Unity unit = 10 mm, with theta and
// alpha variable on every row as in the thesis GUI: joint 2k is theta(k+1), 2k+1 alpha(k).
ModelD thesis_example() {
  ModelD m = empty_model();
  m.num_rows = 4;
  m.rows[0] = row(0, 0, 0, 0);
  m.rows[1] = row(60, 0, 7, 0);
  m.rows[2] = row(30, 0, -7, 0);
  m.rows[3] = row(20, 0, 0, 0);
  for (int r = 0; r < 4; ++r) {
    add_joint(m, r, kParamTheta, -M_PI, M_PI);
    add_joint(m, r, kParamAlpha, -M_PI, M_PI);
  }
  return m;
}

// PUMA 560 in Craig's modified DH (Craig, Introduction to Robotics, 3.7), mm.
constexpr double a2 = 431.8, a3 = 20.32, d3 = 150.05, d4 = 431.8;
ModelD puma560() {
  ModelD m = empty_model();
  m.num_rows = 6;
  m.rows[0] = row(0, 0, 0, 0);
  m.rows[1] = row(0, -90, 0, 0);
  m.rows[2] = row(a2, 0, d3, 0);
  m.rows[3] = row(a3, -90, d4, 0);
  m.rows[4] = row(0, 90, 0, 0);
  m.rows[5] = row(0, -90, 0, 0);
  for (int r = 0; r < 6; ++r) add_joint(m, r, kParamTheta, -M_PI, M_PI);
  return m;
}

// The MK2 Plus arm (toolchain notes): yaw, shoulder, elbow, and a linked row that keeps
// the gripper level, theta4 = -(theta2 + theta3).
template <typename S>
Model<S, 3, 4> mk2() {
  Model<S, 3, 4> m{};
  m.num_rows = 4;
  m.num_joints = 3;
  m.num_linked = 1;
  m.rows[0] = DhRow<S>{S(0), S(0), S(78), S(0)};
  m.rows[1] = DhRow<S>{S(0), S(M_PI / 2), S(0), S(0)};
  m.rows[2] = DhRow<S>{S(135), S(0), S(0), S(0)};
  m.rows[3] = DhRow<S>{S(147), S(0), S(0), S(0)};
  for (int j = 0; j < 3; ++j) m.joints[j] = JointSpec<S>{uint8_t(j), kParamTheta, S(-M_PI), S(M_PI)};
  m.linked[0].row = 3;
  m.linked[0].param = kParamTheta;
  m.linked[0].offset = S(0);
  m.linked[0].gain[0] = S(0);
  m.linked[0].gain[1] = S(-1);
  m.linked[0].gain[2] = S(-1);
  m.T_last_tool = make_transform(rot_x(S(-M_PI / 2)), make_vec3(S(88), S(0), S(0)));
  return m;
}

void expect_vec_near(const Vec3<double>& a, double x, double y, double z, double tol) {
  EXPECT_NEAR(a.x, x, tol);
  EXPECT_NEAR(a.y, y, tol);
  EXPECT_NEAR(a.z, z, tol);
}
}  // namespace

TEST(DhFk, ThesisTable1StraightRobot) {
  // All angles zero: frames stack along x, with the d offsets +0.7 and -0.7 along z.
  const ModelD m = thesis_example();
  const double q[8] = {0};
  FramesD f;
  forward_kinematics(f, m, q);
  ASSERT_EQ(f.count, 5);
  expect_vec_near(f.T_base_frame[1].p, 0, 0, 0, 1e-12);
  expect_vec_near(f.T_base_frame[2].p, 60, 0, 7, 1e-12);
  expect_vec_near(f.T_base_frame[3].p, 90, 0, 0, 1e-12);
  expect_vec_near(f.T_base_frame[4].p, 110, 0, 0, 1e-12);
  expect_vec_near(f.T_base_tool.p, 110, 0, 0, 1e-12);
}

TEST(DhFk, ThesisTable2RotatedRobot) {
  // Table 2: theta = 90, -110, 0, 0 and alpha = 0, 0, 90, 0. By hand: frame 1 turns the
  // chain by 90 deg, so row 2's a = 60 goes along +y; theta2 = -110 leaves x1 at -20 deg
  // from the world x; alpha(1) = 90 on row 3 turns z3 to -y1 = (-sin20, -cos20, 0), and
  // d3 = -7 runs along it; row 4's a = 20 continues along x1.
  const ModelD m = thesis_example();
  double q[8] = {0};
  q[0] = deg(90);    // theta1
  q[2] = deg(-110);  // theta2
  q[5] = deg(90);    // alpha(2), on row 3
  FramesD f;
  forward_kinematics(f, m, q);
  const double c = std::cos(deg(20)), s = std::sin(deg(20));
  expect_vec_near(f.T_base_frame[2].p, 0, 60, 7, 1e-9);
  expect_vec_near(f.T_base_frame[3].p, 30 * c + 7 * s, 60 - 30 * s + 7 * c, 7, 1e-9);
  expect_vec_near(f.T_base_tool.p, 50 * c + 7 * s, 60 - 50 * s + 7 * c, 7, 1e-9);
  // Frame 3's z axis is -y1, by hand.
  const Vec3<double> z3 = f.T_base_frame[3].R.col(2);
  expect_vec_near(z3, -s, -c, 0, 1e-12);
}

TEST(DhFk, Puma560AtZeroAndFolded) {
  const ModelD m = puma560();
  double q[6] = {0};
  FramesD f;
  forward_kinematics(f, m, q);
  // q = 0: the wrist centre is at (a2 + a3, d3, -d4) and the flange frame is Rx(180).
  expect_vec_near(f.T_base_tool.p, a2 + a3, d3, -d4, 1e-9);
  const Mat3<double>& Rt = f.T_base_tool.R;
  EXPECT_NEAR(Rt.m[0][0], 1, 1e-12);
  EXPECT_NEAR(Rt.m[1][1], -1, 1e-12);
  EXPECT_NEAR(Rt.m[2][2], -1, 1e-12);

  // theta1 = 90 deg turns everything about the vertical: (x, y) -> (-y, x).
  q[0] = deg(90);
  forward_kinematics(f, m, q);
  expect_vec_near(f.T_base_tool.p, -d3, a2 + a3, -d4, 1e-9);

  // theta3 = 90 deg: a3 now points along -z and d4 along -x from the elbow at (a2, d3, 0).
  q[0] = 0;
  q[2] = deg(90);
  forward_kinematics(f, m, q);
  expect_vec_near(f.T_base_tool.p, a2 - d4, d3, -a3, 1e-9);
}

TEST(DhFk, LinkedParameterKeepsTheMk2GripperLevel) {
  const Model<double, 3, 4> m = mk2<double>();
  Frames<double, 4> f;
  // Home: upper arm up (90), forearm horizontal (theta3 = -90).
  const double home[3] = {0, deg(90), deg(-90)};
  forward_kinematics(f, m, home);
  expect_vec_near(f.T_base_frame[4].p, 147, 0, 78 + 135, 1e-9);
  expect_vec_near(f.T_base_tool.p, 235, 0, 213, 1e-9);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 100; ++i) {
    const double q[3] = {u(rng), u(rng), u(rng)};
    forward_kinematics(f, m, q);
    // The tool frame (rotated so that z is up) keeps z vertical whatever the pose.
    EXPECT_NEAR(f.T_base_tool.R.m[2][2], 1, 1e-12);
    // And the tool lies 88 mm from the wrist, horizontally.
    const Vec3<double> d = f.T_base_tool.p - f.T_base_frame[4].p;
    EXPECT_NEAR(d.z, 0, 1e-9);
    EXPECT_NEAR(norm(d), 88, 1e-9);
  }
}

namespace {
// A random robot: 1..7 rows, random constants, and on each row each of theta, d, alpha
// independently a joint variable, linked to the variables so far, or constant.
ModelD random_robot(std::mt19937& rng) {
  std::uniform_real_distribution<double> len(-200, 200), ang(-M_PI, M_PI), u(0, 1);
  ModelD m = empty_model();
  m.num_rows = uint8_t(1 + rng() % 7);
  for (int r = 0; r < m.num_rows; ++r) {
    m.rows[r] = DhRow<double>{std::fabs(len(rng)), ang(rng), len(rng), ang(rng)};
    for (DhParam p : {kParamTheta, kParamD, kParamAlpha}) {
      const double pick = u(rng);
      if (pick < 0.45 && m.num_joints < J) {
        add_joint(m, r, p);
      } else if (pick < 0.6 && m.num_joints > 0) {
        LinkedParam<double, J>& l = m.linked[m.num_linked++];
        l.row = uint8_t(r);
        l.param = p;
        l.offset = ang(rng);
        for (int j = 0; j < J; ++j) l.gain[j] = (j < m.num_joints && u(rng) < 0.5) ? len(rng) / 100 : 0;
      }
    }
  }
  m.T_last_tool = make_transform(rpy_to_matrix(ang(rng), ang(rng), ang(rng)), make_vec3(len(rng), len(rng), len(rng)));
  return m;
}

// Angular velocity from a rotation's central difference: skew(w) = dR/dq * R^T.
Vec3<double> omega_fd(const Mat3<double>& Rp, const Mat3<double>& Rm, const Mat3<double>& R, double h) {
  Mat3<double> dR;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) dR.m[i][j] = (Rp.m[i][j] - Rm.m[i][j]) / (2 * h);
  const Mat3<double> W = dR * transpose(R);
  return make_vec3((W.m[2][1] - W.m[1][2]) / 2, (W.m[0][2] - W.m[2][0]) / 2, (W.m[1][0] - W.m[0][1]) / 2);
}
}  // namespace

TEST(DhJacobian, MatchesCentralDifferencesOnRandomMixedRobots) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> qd(-2, 2);
  int robots = 0, columns = 0, with_alpha = 0, with_d = 0, with_linked = 0;
  while (robots < 300) {
    const ModelD m = random_robot(rng);
    if (m.num_joints == 0) continue;
    ASSERT_EQ(validate(m), kModelOk);
    ++robots;
    with_linked += m.num_linked > 0;
    double q[J];
    for (int j = 0; j < m.num_joints; ++j) q[j] = qd(rng) * (m.joints[j].param == kParamD ? 50 : 1);
    FramesD f;
    forward_kinematics(f, m, q);
    double Jac[6][J];
    jacobian(Jac, m, f);
    for (int j = 0; j < m.num_joints; ++j) {
      with_alpha += m.joints[j].param == kParamAlpha;
      with_d += m.joints[j].param == kParamD;
      const double h = 1e-6;
      double qp[J], qm[J];
      for (int k = 0; k < m.num_joints; ++k) qp[k] = qm[k] = q[k];
      qp[j] += h;
      qm[j] -= h;
      FramesD fp, fm;
      forward_kinematics(fp, m, qp);
      forward_kinematics(fm, m, qm);
      const Vec3<double> v = (1 / (2 * h)) * (fp.T_base_tool.p - fm.T_base_tool.p);
      const Vec3<double> w = omega_fd(fp.T_base_tool.R, fm.T_base_tool.R, f.T_base_tool.R, h);
      const Vec3<double> jv = make_vec3(Jac[0][j], Jac[1][j], Jac[2][j]);
      const Vec3<double> jw = make_vec3(Jac[3][j], Jac[4][j], Jac[5][j]);
      // Relative tolerance 1e-6 of the column's size (finite differences with h = 1e-6 in
      // double are good to about 1e-9 relative).
      const double scale_v = std::max(1.0, norm(jv)), scale_w = std::max(1.0, norm(jw));
      EXPECT_LT(norm(v - jv) / scale_v, 1e-6) << "robot " << robots << " joint " << j;
      EXPECT_LT(norm(w - jw) / scale_w, 1e-6) << "robot " << robots << " joint " << j;
      ++columns;
    }
  }
  // The sample really mixed the kinds of variable.
  EXPECT_GT(with_alpha, 50);
  EXPECT_GT(with_d, 50);
  EXPECT_GT(with_linked, 50);
  std::cout << "checked " << columns << " Jacobian columns on " << robots << " random robots (" << with_alpha
            << " alpha, " << with_d << " d variables; " << with_linked << " robots with linked parameters)\n";
}

TEST(DhFk, FloatAgainstDoubleOnTheMk2OverItsJointRanges) {
  // The Nano computes in float; the host's reference is double. Sweep the arm's actuated
  // ranges (base +-90, shoulder 36..130, forearm elevation -43..15 deg) on a grid.
  const Model<double, 3, 4> md = mk2<double>();
  const Model<float, 3, 4> mf = cast_model<float>(md);
  double worst = 0;
  double worst_at[3] = {0, 0, 0};
  int poses = 0;
  for (double base = -90; base <= 90; base += 2.5)
    for (double shoulder = 36; shoulder <= 130; shoulder += 2)
      for (double fore = -43; fore <= 15; fore += 2) {
        const double q[3] = {deg(base), deg(shoulder), deg(fore - shoulder)};
        const float qf[3] = {float(q[0]), float(q[1]), float(q[2])};
        const Vec3<double> pd = tool_position(md, q);
        const Vec3<double> pf = cast<double>(tool_position(mf, qf));
        const double e = norm(pd - pf);
        ++poses;
        if (e > worst) {
          worst = e;
          worst_at[0] = base;
          worst_at[1] = shoulder;
          worst_at[2] = fore;
        }
      }
  std::cout << "MK2 float vs double FK over " << poses << " poses: worst difference " << worst * 1000
            << " um at base " << worst_at[0] << ", shoulder " << worst_at[1] << ", forearm " << worst_at[2]
            << " deg\n";
  RecordProperty("mk2_float_vs_double_worst_mm", std::to_string(worst));
  // A full step of the base is 0.317 deg, 1.3 mm at full reach: float must be far finer.
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(worst, 0);  // float really was used
}

TEST(DhModel, ValidateCatchesEachProblem) {
  ModelD m = puma560();
  EXPECT_EQ(validate(m), kModelOk);
  ModelD bad = m;
  bad.joints[2].row = 9;
  EXPECT_EQ(validate(bad), kModelBadRow);
  bad = m;
  bad.joints[2].param = 7;
  EXPECT_EQ(validate(bad), kModelBadParam);
  bad = m;
  bad.joints[3].row = 2;
  EXPECT_EQ(validate(bad), kModelDuplicate);
  bad = m;
  bad.joints[1].lo = 2;
  bad.joints[1].hi = 1;
  EXPECT_EQ(validate(bad), kModelBadLimits);
  bad = m;
  bad.rows[3].d = NAN;
  EXPECT_EQ(validate(bad), kModelNotFinite);
  bad = m;
  bad.joints[0].hi = INFINITY;
  EXPECT_EQ(validate(bad), kModelBadLimits);
  bad = m;
  bad.num_rows = R + 1;
  EXPECT_EQ(validate(bad), kModelTooManyRows);
  // A link on a parameter that a joint already drives is a duplicate too.
  bad = m;
  bad.num_linked = 1;
  bad.linked[0] = LinkedParam<double, J>{0, kParamTheta, 0, {0}};
  EXPECT_EQ(validate(bad), kModelDuplicate);
  for (ModelError e : {kModelOk, kModelTooManyRows, kModelTooManyJoints, kModelBadRow, kModelBadParam,
                       kModelDuplicate, kModelBadLimits, kModelNotFinite})
    EXPECT_GT(std::string(model_error_text(e)).size(), 1u);
}

TEST(DhModel, WithinLimitsRejectsNan) {
  const ModelD m = puma560();
  double q[6] = {0, 0, 0, 0, 0, 0};
  EXPECT_TRUE(within_limits(m, q));
  q[4] = 4;
  EXPECT_FALSE(within_limits(m, q));
  q[4] = NAN;
  EXPECT_FALSE(within_limits(m, q));
}

TEST(DhModel, DhTableFillsVariablesAndLinks) {
  const Model<double, 3, 4> m = mk2<double>();
  const double q[3] = {0.1, 0.2, 0.3};
  DhRow<double> t[4];
  dh_table(t, m, q);
  EXPECT_EQ(t[0].theta, 0.1);
  EXPECT_EQ(t[1].theta, 0.2);
  EXPECT_EQ(t[2].theta, 0.3);
  EXPECT_DOUBLE_EQ(t[3].theta, -0.5);
  EXPECT_EQ(t[3].a, 147);
}

// ---- The host's forward kinematics (detail::ForwardKinematics<true>: angle kinds, batched
// sincos, frame in registers) against the compact one the Nano builds (<false>: the table,
// then the chain with every multiplication). They must give the same values (equal as
// doubles; only the sign of a zero may differ).
namespace {
// A random robot whose constant angles are often exactly 0, +-90 or +-180 deg and whose
// a and d are often zero, so that every pair of angle kinds and every shortcut occurs;
// theta, d and alpha variables and linked parameters as in random_robot.
template <typename S>
Model<S, J, R> random_kinds_robot(std::mt19937& rng) {
  std::uniform_real_distribution<double> len(-200, 200), ang(-M_PI, M_PI), u(0, 1);
  const double exact[5] = {0, M_PI / 2, -M_PI / 2, M_PI, -M_PI};
  auto angle = [&]() { return u(rng) < 0.6 ? S(exact[rng() % 5]) : S(ang(rng)); };
  auto length = [&]() { return u(rng) < 0.4 ? S(0) : S(len(rng)); };
  Model<S, J, R> m{};
  m.num_rows = uint8_t(rng() % (R + 1));  // 0 rows too
  for (int r = 0; r < m.num_rows; ++r) {
    m.rows[r] = DhRow<S>{S(std::fabs(double(length()))), angle(), length(), angle()};
    for (DhParam p : {kParamTheta, kParamD, kParamAlpha}) {
      const double pick = u(rng);
      if (pick < 0.3 && m.num_joints < J) {
        m.joints[m.num_joints++] = JointSpec<S>{uint8_t(r), uint8_t(p), S(-10), S(10)};
      } else if (pick < 0.4 && m.num_joints > 0) {
        LinkedParam<S, J>& l = m.linked[m.num_linked++];
        l.row = uint8_t(r);
        l.param = p;
        l.offset = angle();
        for (int j = 0; j < J; ++j) l.gain[j] = (j < m.num_joints && u(rng) < 0.5) ? S(len(rng) / 100) : S(0);
      }
    }
  }
  m.T_last_tool = u(rng) < 0.5 ? make_transform(identity3<S>(), make_vec3(S(0), S(0), S(len(rng))))
                               : make_transform(rpy_to_matrix(S(ang(rng)), S(ang(rng)), S(ang(rng))),
                                                make_vec3(S(len(rng)), S(len(rng)), S(len(rng))));
  return m;
}

template <typename S>
void fast_and_compact_agree(int robots, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> qd(-4, 4), u(0, 1);
  long values = 0;
  bool pairs[25] = {};  // kind(alpha) * 5 + kind(theta) seen in the chain (rows after the first)
  for (int n = 0; n < robots; ++n) {
    const Model<S, J, R> m = random_kinds_robot<S>(rng);
    ASSERT_EQ(validate(m), kModelOk);
    for (int pose = 0; pose < 10; ++pose) {
      S q[J];
      for (int j = 0; j < m.num_joints; ++j) {
        const double exact = 90.0 * int(rng() % 5) - 180.0;  // joints at exact right angles too
        q[j] = m.joints[j].param == kParamD ? S(50 * qd(rng)) : u(rng) < 0.3 ? deg_to_rad(S(exact)) : S(qd(rng));
      }
      DhRow<S> t[R];
      dh_table(t, m, q);
      for (int i = 1; i < m.num_rows; ++i) pairs[detail::dh_angle_kind(t[i].alpha) * 5 + detail::dh_angle_kind(t[i].theta)] = true;
      Frames<S, R> fast, compact;
      detail::ForwardKinematics<true>::run(fast, m, q);
      detail::ForwardKinematics<false>::run(compact, m, q);
      ASSERT_EQ(fast.count, compact.count);
      for (int i = 0; i <= m.num_rows + 1; ++i) {
        const Transform<S>& a = i <= m.num_rows ? fast.T_base_frame[i] : fast.T_base_tool;
        const Transform<S>& b = i <= m.num_rows ? compact.T_base_frame[i] : compact.T_base_tool;
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) ASSERT_EQ(a.R.m[r][c], b.R.m[r][c]) << "robot " << n << " frame " << i;
          ASSERT_EQ(a.p[r], b.p[r]) << "robot " << n << " frame " << i;
        }
        values += 12;
      }
    }
  }
  for (int k = 0; k < 25; ++k) EXPECT_TRUE(pairs[k]) << "pair of angle kinds " << k << " never chained";
  std::cout << "fast and compact forward kinematics equal in " << values << " values (" << sizeof(S) * 8 << "-bit)\n";
}
}  // namespace

TEST(DhFk, HostPathEqualsCompactPathOnRandomRobotsOfEveryAngleKind) {
  fast_and_compact_agree<double>(3000, 11);
  fast_and_compact_agree<float>(1000, 12);
}

TEST(DhFk, ExactRightAnglesStayExact) {
  // Joints at exactly 0, +-90 and 180 deg (as deg_to_rad gives them) and constant twists
  // of 0, +-90 and 180 deg: every rotation entry is exactly 0 or +-1, every position a sum
  // of the integer lengths, with no rounding at all.
  ModelD m = empty_model();
  m.num_rows = 6;
  m.rows[0] = row(0, 0, 100, 0);
  m.rows[1] = row(10, 90, 0, 0);
  m.rows[2] = row(200, -90, 30, 0);
  m.rows[3] = row(0, 180, 40, 0);
  m.rows[4] = row(50, 90, 0, 180);  // a fixed turn
  m.rows[5] = row(7, 0, 3, 0);
  for (int r = 0; r < 6; ++r)
    if (r != 4) add_joint(m, r, kParamTheta, -4, 4);
  m.T_last_tool = make_transform(identity3<double>(), make_vec3(0.0, 0.0, 11.0));
  const double angles[5] = {0, 90, -90, 180, -180};
  for (int pose = 0; pose < 625; ++pose) {
    double q[5];
    for (int j = 0, p = pose; j < 5; ++j, p /= 5) q[j] = deg_to_rad(angles[p % 5]);
    FramesD f;
    forward_kinematics(f, m, q);
    for (int i = 0; i <= 7; ++i) {
      const Transform<double>& T = i <= 6 ? f.T_base_frame[i] : f.T_base_tool;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          const double v = T.R.m[r][c];
          ASSERT_TRUE(v == 0 || v == 1 || v == -1) << "pose " << pose << " frame " << i << " R" << r << c << " = " << v;
        }
        ASSERT_EQ(T.p[r], std::round(T.p[r])) << "pose " << pose << " frame " << i;
      }
    }
  }
}
