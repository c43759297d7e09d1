// Tests firmware/src/robot.cpp and the commands that use the arm's geometry: P (the shared
// closed-form inverse kinematics on the robot's YPP arm; the tool ends within a step's
// worth of the target, checked with the shared forward kinematics in double; unreachable
// points refused), the home pose from the robot file (H without endstops, Z), and the
// power-up state. The robot file is read by the host library (CMake builds only: PlatformIO's
// native environment, which has no host library, skips this folder).
#include <articula/actuation.h>
#include <articula/dh.h>
#include <articula/ik_ypp.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"
#include "robot_file.h"

using namespace articula;

namespace {

const int kJ = articula::kMaxConfigMotors;  // the arms tested here have the three motors a Nano drives
typedef Model<double, 3, 4> ModelD;

// The robot file, read by the host's loader (not through the firmware's configuration).
const host::Robot& robot_file() {
  static const host::Robot r = host::load_robot_file(sim::robot_file());
  return r;
}

ModelD model() {
  const host::Robot& r = robot_file();
  ModelD m{};
  m.num_rows = r.model.num_rows;
  m.num_joints = r.model.num_joints;
  m.num_linked = r.model.num_linked;
  for (int i = 0; i < m.num_rows; ++i) m.rows[i] = r.model.rows[i];
  for (int j = 0; j < m.num_joints; ++j) m.joints[j] = r.model.joints[j];
  for (int k = 0; k < m.num_linked; ++k) {
    m.linked[k].row = r.model.linked[k].row;
    m.linked[k].param = r.model.linked[k].param;
    m.linked[k].offset = r.model.linked[k].offset;
    for (int j = 0; j < 3; ++j) m.linked[k].gain[j] = r.model.linked[k].gain[j];
  }
  m.T_last_tool = r.model.T_last_tool;
  return m;
}

Actuation<double, 3> actuation() {
  const host::Robot& r = robot_file();
  Actuation<double, 3> a{};
  a.num_motors = r.actuation.num_motors;
  for (int i = 0; i < 3; ++i) {
    a.motors[i] = r.actuation.motors[i];
    for (int j = 0; j < 3; ++j) a.coupling[i][j] = r.actuation.coupling[i][j];
  }
  EXPECT_TRUE(invert_coupling(a));
  return a;
}

Vec3<double> tool_at_steps(const int32_t* steps) {
  double q[3];
  joints_from_steps(q, actuation(), steps);
  return tool_position(model(), q);
}

Vec3<double> tool_at_angles(const double* deg) {
  const Actuation<double, 3> a = actuation();
  double u[3], q[3];
  for (int i = 0; i < kJ; ++i) u[i] = deg_to_rad(deg[i]);
  joints_from_actuators(q, a, u);
  return tool_position(model(), q);
}

// How far the tool moves for one step of each motor, summed: "a step's worth" near a pose.
double step_worth(const double* deg) {
  const Vec3<double> p = tool_at_angles(deg);
  double sum = 0;
  for (int i = 0; i < kJ; ++i) {
    double d[3] = {deg[0], deg[1], deg[2]};
    d[i] += degrees_per_step<double>(robot::motor(uint8_t(i)));
    sum += norm(tool_at_angles(d) - p);
  }
  return sum;
}

std::string p_line(const Vec3<double>& p) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "P %.3f %.3f %.3f", p.x, p.y, p.z);
  return buf;
}

}  // namespace

TEST(Robot, StructuresFromTheConfig) {
  sim::boot();
  EXPECT_EQ(robot::actuation().num_motors, kJ);
  EXPECT_STREQ(robot::config().name, robot_file().name.c_str());
  EXPECT_EQ(robot::config().servo_open_deg, float(robot_file().gripper.servo_open_deg));
  EXPECT_EQ(robot::config().servo_closed_deg, float(robot_file().gripper.servo_closed_deg));
  ASSERT_TRUE(robot::config().has_point);  // both test robots are yaw-pitch-pitch arms
  YppArm<double> arm{};
  ASSERT_TRUE(ypp_from_model(arm, model()));
  ASSERT_TRUE(ypp_limits_from_actuation(arm, actuation()));
  EXPECT_FLOAT_EQ(robot::config().arm.upper, float(arm.upper));
  EXPECT_FLOAT_EQ(robot::config().arm.fore, float(arm.fore));
  EXPECT_FLOAT_EQ(robot::config().arm.base_height, float(arm.base_height));
  EXPECT_FLOAT_EQ(robot::config().arm.tool_forward, float(arm.tool_forward));
  EXPECT_EQ(robot::config().arm.parallelogram, arm.parallelogram);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FLOAT_EQ(robot::config().arm.lo[i], float(arm.lo[i]));
    EXPECT_FLOAT_EQ(robot::config().arm.hi[i], float(arm.hi[i]));
  }
  // Home: the robot file's joint values through C^-1, in millidegrees.
  const double q_home[3] = {robot_file().home[0], robot_file().home[1], robot_file().home[2]};
  double u[3];
  actuators_from_joints(u, actuation(), q_home);
  for (int i = 0; i < kJ; ++i) {
    EXPECT_EQ(robot::config().home[i], Millideg(std::lround(rad_to_deg(u[i]) * 1000))) << i;
    EXPECT_EQ(robot::home_steps()[i], quantize_within_limits(robot::motor(uint8_t(i)), robot::config().home[i]));
  }
}

// The status report's angles (robot::step_angle, 32-bit arithmetic on a reduced fraction)
// are steps_to_millideg's, for every step within the limits and far beyond (a homing search
// may count past them).
TEST(Robot, StepAngleIsStepsToMillideg) {
  sim::boot();
  for (int i = 0; i < kJ; ++i) {
    const MotorSpec& m = robot::motor(uint8_t(i));
    const int32_t lo = min_steps(m), hi = max_steps(m), span = hi - lo;
    for (int32_t s = lo - 3 * span - 20; s <= hi + 3 * span + 20; ++s)
      ASSERT_EQ(robot::step_angle(uint8_t(i), s), steps_to_millideg(m, s)) << "motor " << i << " step " << s;
    for (int32_t s : {1000000, -1000000, 3000000, -3000000})
      ASSERT_EQ(robot::step_angle(uint8_t(i), s), steps_to_millideg(m, s)) << "motor " << i << " step " << s;
  }
}

TEST(Robot, PowerUpAtStepZeroIdle) {
  sim::boot();
  const sim::Status st = sim::status();
  EXPECT_EQ(st.state, kStateIdle);
  for (int i = 0; i < kJ; ++i) {
    EXPECT_EQ(st.steps[i], 0);
    EXPECT_EQ(st.millideg[i], robot::motor(uint8_t(i)).zero);
  }
  EXPECT_EQ(st.gripper, 0);
  EXPECT_FALSE(st.coils);
}

// Points the arm reaches (from poses spread over the motors' ranges): the tool ends within
// a step's worth of each, with every motor within its limits.
TEST(Robot, PointReachedWithinAStep) {
  sim::boot();
  int tried = 0;
  for (double f0 : {0.15, 0.5, 0.8})
    for (double f1 : {0.2, 0.45, 0.75})
      for (double f2 : {0.25, 0.6, 0.9}) {
        const double f[3] = {f0, f1, f2};
        double deg[3];
        for (int i = 0; i < kJ; ++i) {
          const MotorSpec& m = robot::motor(uint8_t(i));
          deg[i] = (m.min + (m.max - m.min) * f[i]) / 1000.0;
        }
        const Vec3<double> target = tool_at_angles(deg);
        const std::string line = p_line(target);
        ASSERT_EQ(sim::command(line), "ok") << line;
        ASSERT_TRUE(sim::run_until_at_rest());
        const sim::Status st = sim::status();
        for (int i = 0; i < kJ; ++i) {
          EXPECT_GE(st.steps[i], min_steps(robot::motor(uint8_t(i))));
          EXPECT_LE(st.steps[i], max_steps(robot::motor(uint8_t(i))));
        }
        const double err = norm(tool_at_steps(st.steps) - target);
        EXPECT_LE(err, step_worth(deg)) << line;
        ++tried;
      }
  EXPECT_EQ(tried, 27);
  EXPECT_EQ(sim::hal_errors(), "");
}

TEST(Robot, UnreachablePointsAreRefused) {
  sim::boot();
  ASSERT_EQ(sim::command("L 0 5"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const sim::Status before = sim::status();
  const double reach = robot::config().arm.upper + robot::config().arm.fore + robot::config().arm.tool_forward;
  for (const Vec3<double>& p : {make_vec3(reach + 100, 0.0, 78.0), make_vec3(0.0, 0.0, -1000.0),
                                make_vec3(-200.0, 0.0, 100.0),  // behind the base: beyond its +-90 degrees
                                make_vec3(0.0, 0.0, 78.0)}) {
    EXPECT_EQ(sim::command(p_line(p)), "error:10") << p_line(p);
  }
  sim::run_until([] { return false; }, 100 * sim::kPollTicks);
  const sim::Status after = sim::status();
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(after.steps[i], before.steps[i]);
  // The commanded angles did not change either: 5 + 1 degrees.
  ASSERT_EQ(sim::command("L 0 1"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(robot::motor(0), robot::motor(0).zero + 6000));
}

// H without endstops moves to the home pose (state Home meanwhile); Z declares the current
// position to be the home pose without moving.
TEST(Robot, HomeAndZero) {
  sim::boot();
  ASSERT_EQ(sim::command("L 0 20"), "ok");
  ASSERT_EQ(sim::command("L 1 -10"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  ASSERT_EQ(sim::command("H"), "ok");
  sim::tick();
  EXPECT_EQ(sim::status().state, kStateHome);
  ASSERT_TRUE(sim::run_until_at_rest());
  sim::Status st = sim::status();
  EXPECT_EQ(st.state, kStateIdle);
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(st.steps[i], robot::home_steps()[i]) << i;
  // The commanded angles are the home angles: 0.1 degree more lands where home + 0.1 does.
  ASSERT_EQ(sim::command("L 2 0.4"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::status().steps[2], quantize_within_limits(robot::motor(2), robot::config().home[2] + 400));
  // Z: no move, the steps become the home steps, the pins stay where they are.
  ASSERT_EQ(sim::command("L 0 -15"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const std::vector<int64_t> pins(sitl::hw().position, sitl::hw().position + kJ);
  const size_t writes = sitl::hw().coil_log.size();
  ASSERT_EQ(sim::command("Z"), "ok");
  EXPECT_EQ(sitl::hw().coil_log.size(), writes);
  st = sim::status();
  for (int i = 0; i < kJ; ++i) {
    EXPECT_EQ(st.steps[i], robot::home_steps()[i]);
    EXPECT_EQ(st.millideg[i], steps_to_millideg(robot::motor(uint8_t(i)), robot::home_steps()[i]));
  }
  ASSERT_EQ(sim::command("L 0 3"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const int32_t moved = quantize_within_limits(robot::motor(0), robot::config().home[0] + 3000) - robot::home_steps()[0];
  EXPECT_EQ(sitl::hw().position[0] - pins[0], moved);
  EXPECT_EQ(sim::hal_errors(), "");
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
