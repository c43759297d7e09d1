// Tests that firmware/tools/robot_config.py (what the Nano is built from) and the host
// loader (host/lib/robot_file.cpp) read robots/mk2plus.json as the same arm: motors,
// coupling, DH table, limits, tool and home, compared field by field and by FK.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <articula/ik_ypp.h>

#include "robot_config.h"  // generated from robots/mk2plus.json into the build tree
#include "robot_file.h"

using namespace articula;

namespace {
constexpr int N = ARTICULA_NUM_JOINTS;
constexpr int R = ARTICULA_NUM_ROWS;

const host::Robot& mk2() {
  static const host::Robot r = host::load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  return r;
}

// The firmware's model, built from the generated header as the firmware builds it.
Model<float, N, R> firmware_model() {
  const DhRow<float> rows[R] = ARTICULA_DH_ROWS;
  const JointSpec<float> joints[N] = ARTICULA_JOINTS;
  const LinkedParam<float, N> linked[] = ARTICULA_LINKED;
  const float xyz[3] = ARTICULA_TOOL_XYZ, rpy[3] = ARTICULA_TOOL_RPY;
  Model<float, N, R> m{};
  m.num_rows = R;
  m.num_joints = N;
  m.num_linked = ARTICULA_NUM_LINKED;
  for (int i = 0; i < R; ++i) m.rows[i] = rows[i];
  for (int j = 0; j < N; ++j) m.joints[j] = joints[j];
  for (int k = 0; k < ARTICULA_NUM_LINKED; ++k) m.linked[k] = linked[k];
  m.T_last_tool = make_transform(rpy_to_matrix(rpy[0], rpy[1], rpy[2]), make_vec3(xyz[0], xyz[1], xyz[2]));
  return m;
}
}  // namespace

TEST(RobotConfig, NameAndSizesMatch) {
  EXPECT_EQ(std::string(ARTICULA_ROBOT_NAME), mk2().name);
  EXPECT_EQ(N, mk2().model.num_joints);
  EXPECT_EQ(R, mk2().model.num_rows);
  EXPECT_EQ(ARTICULA_NUM_LINKED, mk2().model.num_linked);
  EXPECT_EQ(N, mk2().actuation.num_motors);
}

TEST(RobotConfig, MotorsAreIdentical) {
  // Integer fields: the firmware and the host must quantize to the same steps.
  const MotorSpec motors[N] = ARTICULA_MOTORS;
  for (int k = 0; k < N; ++k) {
    const MotorSpec& h = mk2().actuation.motors[k];
    EXPECT_EQ(motors[k].full_steps_per_rev, h.full_steps_per_rev) << k;
    EXPECT_EQ(motors[k].microsteps, h.microsteps) << k;
    EXPECT_EQ(motors[k].direction, h.direction) << k;
    EXPECT_EQ(motors[k].gear_num, h.gear_num) << k;
    EXPECT_EQ(motors[k].gear_den, h.gear_den) << k;
    EXPECT_EQ(motors[k].zero, h.zero) << k;
    EXPECT_EQ(motors[k].min, h.min) << k;
    EXPECT_EQ(motors[k].max, h.max) << k;
  }
}

TEST(RobotConfig, CouplingAndHomeMatch) {
  const float coupling[N][N] = ARTICULA_COUPLING;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) EXPECT_FLOAT_EQ(coupling[r][c], float(mk2().actuation.coupling[r][c]));
  const float home[N] = ARTICULA_HOME_Q;
  for (int j = 0; j < N; ++j) EXPECT_FLOAT_EQ(home[j], float(mk2().home[j])) << j;
}

TEST(RobotConfig, ModelMatchesFieldByFieldAndByForwardKinematics) {
  const Model<float, N, R> fw = firmware_model();
  const Model<float, N, R> host = cast_model<float>(
      // The host model has room for more rows and joints; copy the used part.
      [] {
        Model<double, N, R> m{};
        const auto& h = mk2().model;
        m.num_rows = h.num_rows;
        m.num_joints = h.num_joints;
        m.num_linked = h.num_linked;
        for (int i = 0; i < R; ++i) m.rows[i] = h.rows[i];
        for (int j = 0; j < N; ++j) m.joints[j] = h.joints[j];
        for (int k = 0; k < h.num_linked; ++k) {
          m.linked[k].row = h.linked[k].row;
          m.linked[k].param = h.linked[k].param;
          m.linked[k].offset = h.linked[k].offset;
          for (int j = 0; j < N; ++j) m.linked[k].gain[j] = h.linked[k].gain[j];
        }
        m.T_last_tool = h.T_last_tool;
        return m;
      }());
  ASSERT_EQ(validate(fw), kModelOk);
  for (int j = 0; j < N; ++j) {
    EXPECT_EQ(fw.joints[j].row, host.joints[j].row);
    EXPECT_EQ(fw.joints[j].param, host.joints[j].param);
    EXPECT_FLOAT_EQ(fw.joints[j].lo, host.joints[j].lo);
    EXPECT_FLOAT_EQ(fw.joints[j].hi, host.joints[j].hi);
  }
  // Same tool position over random poses (float both sides: bit-identical inputs).
  std::mt19937 rng(11);
  for (int i = 0; i < 1000; ++i) {
    float q[N];
    for (int j = 0; j < N; ++j)
      q[j] = std::uniform_real_distribution<float>(fw.joints[j].lo, fw.joints[j].hi)(rng);
    const Vec3<float> a = tool_position(fw, q), b = tool_position(host, q);
    ASSERT_LT(norm(a - b), 1e-3f) << i;
  }
  // And the firmware model recognises as the closed-form family, as on the host.
  YppArm<float> arm_fw, arm_host;
  EXPECT_TRUE(ypp_from_model(arm_fw, fw));
  EXPECT_TRUE(ypp_from_model(arm_host, host));
  EXPECT_FLOAT_EQ(arm_fw.upper, arm_host.upper);
  EXPECT_FLOAT_EQ(arm_fw.tool_forward, arm_host.tool_forward);
}

TEST(RobotConfig, ServoAnglesMatch) {
  EXPECT_FLOAT_EQ(ARTICULA_SERVO_OPEN_DEG, float(mk2().gripper.servo_open_deg));
  EXPECT_FLOAT_EQ(ARTICULA_SERVO_CLOSED_DEG, float(mk2().gripper.servo_closed_deg));
}
