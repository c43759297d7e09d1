// Tests host/lib/run.cpp: programs on the kinematic model, exact joint values (no steps),
// RoboSim's statements, and protocol lines with the controller's limit checks.
#include <gtest/gtest.h>

#include <cmath>

#include "program.h"
#include "robot_file.h"
#include "test_robots.h"
#include "run.h"

using namespace articula;
using namespace articula::host;

namespace {

// A planar two-link arm without motors whose first link RoboSim's `l` may change.
Robot planar() {
  return parse_robot(R"({"name": "planar", "dh": [
      {"a": 0, "alpha": 0, "d": 0, "theta": {"joint": "j1", "min": -90, "max": 90}},
      {"a": {"value": 150, "min": 100, "max": 200}, "alpha": 0, "d": 0, "theta": {"joint": "j2", "min": -90, "max": 90}}],
    "tool": {"xyz": [100, 0, 0]}})",
                     "planar.json");
}

double rad(double deg) {
  return deg * M_PI / 180;
}

// The MK2's tool point from its actuator angles, by its geometry (see test_predict.cpp).
Vec3<double> mk2_tool(double base, double upper, double fore) {
  const double r = 135 * std::cos(rad(upper)) + 147 * std::cos(rad(fore)) + 88;
  const double z = 78 + 135 * std::sin(rad(upper)) + 147 * std::sin(rad(fore));
  return make_vec3(r * std::cos(rad(base)), r * std::sin(rad(base)), z);
}

void expect_near(const Vec3<double>& a, const Vec3<double>& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Statement robosim(Statement::Kind kind, std::vector<double> values) {
  Statement s;
  s.kind = kind;
  s.values = std::move(values);
  s.line = 1;
  return s;
}

}  // namespace

TEST(Run, ProtocolLinesUseExactAngles) {
  KinematicModel m(mk2());
  RunRecord r = m.execute_line("L 0 10");
  ASSERT_EQ(r.reply, kOk);
  EXPECT_DOUBLE_EQ(r.joints[0], 10);  // no step: exactly what was commanded
  expect_near(r.tool.p, mk2_tool(10, 90, 0), 1e-9);
  EXPECT_NEAR(r.rpy_deg.z, 10, 1e-9);  // the gripper stays level and turns with the base
  EXPECT_NEAR(r.rpy_deg.x, 0, 1e-9);
  r = m.execute_line("L 1 50");  // 140 deg: beyond the shoulder's 130
  EXPECT_EQ(r.reply, kJointLimit);
  EXPECT_DOUBLE_EQ(r.joints[1], 90);
  r = m.execute_line("M -45 75 5");
  ASSERT_EQ(r.reply, kOk);
  EXPECT_NEAR(r.joints[2], 5 - 75, 1e-9);  // the DH elbow: forearm elevation - upper arm
  expect_near(r.tool.p, mk2_tool(-45, 75, 5), 1e-9);
  r = m.execute_line("P 200 -150 150");
  ASSERT_EQ(r.reply, kOk);
  EXPECT_EQ(r.ik_status, "reached");
  EXPECT_LT(r.target_error_mm, 0.01);
  r = m.execute_line("P 900 0 0");
  EXPECT_EQ(r.reply, kUnreachable);
  EXPECT_LT(r.target_error_mm, 0.01 + norm(make_vec3(900.0, 0.0, 0.0) - make_vec3(200.0, -150.0, 150.0)));
  r = m.execute_line("G 25");
  EXPECT_EQ(r.gripper_percent, 25);
  r = m.execute_line("H");
  expect_near(r.tool.p, make_vec3(235.0, 0.0, 213.0), 1e-9);
}

TEST(Run, ZeroKeepsThePoseAndShiftsTheCommands) {
  KinematicModel m(mk2());
  m.execute_line("L 0 10");
  RunRecord r = m.execute_line("Z");
  EXPECT_NEAR(r.joints[0], 10, 1e-9);  // nothing moved
  r = m.execute_line("L 0 -10");
  EXPECT_NEAR(r.joints[0], 0, 1e-9);
  r = m.execute_line("M 0 90 0");  // the "home" the arm was told of: 10 deg to the left
  EXPECT_NEAR(r.joints[0], 10, 1e-9);
}

TEST(Run, RoboSimStatements) {
  KinematicModel m(mk2());
  RunRecord r = m.execute(robosim(Statement::Kind::kJoints, {10, 60, -80}));
  ASSERT_EQ(r.reply, kOk);
  EXPECT_EQ(r.text, "m 10 60 -80");
  expect_near(r.tool.p, mk2_tool(10, 60, -20), 1e-9);
  // Beyond the forearm motor's limit (-60 < -43): the model goes there, with a note.
  r = m.execute(robosim(Statement::Kind::kJoints, {0, 90, -150}));
  EXPECT_EQ(r.reply, kOk);
  EXPECT_NEAR(r.joints[2], -150, 1e-9);
  EXPECT_NE(r.note.find("error:9"), std::string::npos) << r.note;

  r = m.execute(robosim(Statement::Kind::kTarget, {200, 200, 160}));
  ASSERT_EQ(r.reply, kOk);
  EXPECT_EQ(r.ik_status, "reached");
  expect_near(r.tool.p, make_vec3(200.0, 200.0, 160.0), 0.01);
  // Out of reach: the best pose, and how far it is.
  r = m.execute(robosim(Statement::Kind::kTarget, {900, 0, 0}));
  EXPECT_EQ(r.reply, kOk);
  EXPECT_NE(r.ik_status, "reached");
  EXPECT_GT(r.target_error_mm, 400);
  EXPECT_NEAR(r.target_error_mm, norm(r.tool.p - make_vec3(900.0, 0.0, 0.0)), 1e-9);
  EXPECT_NE(r.note.find("best pose"), std::string::npos);

  r = m.execute(robosim(Statement::Kind::kHand, {0.25}));
  EXPECT_EQ(r.gripper_percent, 50);
}

TEST(Run, RobotWithoutMotors) {
  KinematicModel m(planar());
  RunRecord r = m.execute_line("L 0 30");  // joint variables: j1 += 30 deg
  ASSERT_EQ(r.reply, kOk);
  EXPECT_NEAR(r.joints[0], 30, 1e-12);
  expect_near(r.tool.p, make_vec3(250 * std::cos(rad(30)), 250 * std::sin(rad(30)), 0.0), 1e-9);
  EXPECT_EQ(m.execute_line("L 0 70").reply, kJointLimit);
  r = m.execute_line("M 0 90");
  expect_near(r.tool.p, make_vec3(150.0, 100.0, 0.0), 1e-9);
  // l: the first link 50 mm longer.
  r = m.execute(robosim(Statement::Kind::kLinkLengths, {200}));
  expect_near(r.tool.p, make_vec3(200.0, 100.0, 0.0), 1e-9);
  r = m.execute(robosim(Statement::Kind::kTarget, {200, 150, 0}));
  EXPECT_EQ(r.ik_status, "reached");
  expect_near(r.tool.p, make_vec3(200.0, 150.0, 0.0), 0.01);
}

TEST(Run, ShippedProgramsRun) {
  for (const char* name : {"demo.arm", "thesis-repeatability.arm", "robosim-example.robosim"}) {
    const Program prog = load_program(std::string(ARTICULA_SOURCE_DIR) + "/programs/" + name, mk2());
    const std::vector<RunRecord> records = run_program(mk2(), prog);
    ASSERT_EQ(records.size(), prog.statements.size()) << name;
    for (const auto& r : records) {
      EXPECT_EQ(r.reply, kOk) << name << ":" << r.line;
      if (r.has_target) {
        EXPECT_EQ(r.ik_status, "reached") << name << ":" << r.line;
      }
    }
  }
}

// T on robots the Nano cannot run it on: the same rule through each robot's own IK. The Panda
// (7 joints, no closed form) and the PUMA 560 follow a straight line: every segment end is on
// it, and the tool half way through each segment (straight in joints) within the tolerance of
// it (0.1 mm, $7) and a little.
TEST(Run, AStraightLineOnEveryRobot) {
  for (const char* name : {"panda", "puma560"}) {
    const Robot r = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/" + name + ".json");
    KinematicModel m(r);
    ASSERT_EQ(m.execute_line("T 500 100 400 50").reply, kOk) << name;
    const Vec3<double> a = m.execute_line("I").tool.p;  // (nothing moves: where the tool is)
    const RunRecord rec = m.execute_line("T 500 -100 400 50");
    ASSERT_EQ(rec.reply, kOk) << name << ": " << rec.note;
    ASSERT_GE(rec.via_joints.size(), 2u) << name;
    EXPECT_NEAR(rec.line_length_mm, 200.0, 0.01) << name;
    EXPECT_NEAR(norm(rec.tool.p - make_vec3(500.0, -100.0, 400.0)), 0.0, 0.01) << name;
    const Vec3<double> b = make_vec3(500.0, -100.0, 400.0);
    auto off = [&](const std::vector<double>& joints) {
      std::vector<double> q(joints.size());
      for (size_t j = 0; j < q.size(); ++j) q[j] = joint_to_model(r, int(j), joints[j]);
      const Vec3<double> p = tool_position(r.model, q.data());
      const double f = std::clamp(dot(p - a, b - a) / dot(b - a, b - a), 0.0, 1.0);
      return norm(p - (a + f * (b - a)));
    };
    std::vector<double> before(rec.via_joints.front().size());
    {
      KinematicModel m2(r);
      before = m2.execute_line("T 500 100 400 50").joints;
    }
    for (const auto& via : rec.via_joints) {
      EXPECT_LT(off(via), 0.01) << name;
      std::vector<double> mid(via.size());
      for (size_t j = 0; j < via.size(); ++j) mid[j] = (before[j] + via[j]) / 2;
      EXPECT_LT(off(mid), 0.1 + 0.01) << name;
      before = via;
    }
  }
}
