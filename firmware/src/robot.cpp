// firmware/src/robot.cpp - the robot's structures from robot_config.h.
#include "robot.h"

using namespace articula;

namespace robot {

// Initialised in place (no copy of a constant table: on the AVR that would sit in RAM twice).
const Actuation actuation = {ARTICULA_NUM_JOINTS, ARTICULA_MOTORS, ARTICULA_COUPLING, {}};
YppArm<float> arm;
bool has_ik;
Millideg home[kJoints];
int32_t home_steps[kJoints];

namespace {
#if ARTICULA_NUM_JOINTS == 3  // a yaw-pitch-pitch arm has three
typedef Model<float, kJoints, ARTICULA_NUM_ROWS> RobotModel;

// The kinematic model, only to recognise the arm's family. A constant: the optimiser works
// ypp_from_model's checks out at build time. The tool's rotation does not move the tool
// point: identity here.
const RobotModel kModel = {ARTICULA_NUM_ROWS,
                           ARTICULA_NUM_JOINTS,
                           ARTICULA_NUM_LINKED,
                           ARTICULA_DH_ROWS,
                           ARTICULA_JOINTS,
                           ARTICULA_LINKED,
                           {{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, ARTICULA_TOOL_XYZ}};

// Whether P can be solved, and the arm to solve it on.
bool setup_ik() { return ypp_from_model(arm, kModel) && ypp_limits_from_actuation(arm, actuation); }
#else
bool setup_ik() { return false; }
#endif
}  // namespace

void setup() {
  has_ik = setup_ik();
  // Home: joint values from the robot file, u = C^-1 q (C padded to 3 x 3 with the identity
  // for fewer motors), to millidegrees. solve3 rather than invert_coupling: a third of the
  // code, and the inverse itself is never needed.
  const float q_home[kJoints] = ARTICULA_HOME_Q;
  float a[3][4], u[3];
  for (uint8_t r = 0; r < 3; ++r) {
    for (uint8_t c = 0; c < 3; ++c) a[r][c] = r < kJoints && c < kJoints ? actuation.coupling[r][c] : float(r == c);
    a[r][3] = r < kJoints ? q_home[r] : 0.0f;
  }
  if (!detail::solve3(u, a))
    for (uint8_t i = 0; i < kJoints; ++i) u[i] = q_home[i];  // never: the loader rejects a singular C
  for (uint8_t i = 0; i < kJoints; ++i) {
    const MotorSpec& m = actuation.motors[i];
    Millideg h = m.zero;
    to_millideg(h, rad_to_deg(u[i]));
    home[i] = clamp(h, m.min, m.max);
    home_steps[i] = quantize_within_limits(m, home[i]);
  }
}

}  // namespace robot
