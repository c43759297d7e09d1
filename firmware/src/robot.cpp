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
// step_angle(): angle = zero + direction * round(steps * den / num), num/den = steps per
// millidegree in lowest terms (3/950 on the MK2's base, 47/34200 on its arm motors); `most`
// is the largest |steps| for which 2 |steps| den + num fits a uint32 (0: none, use
// steps_to_millideg). The last angle is kept: a report at rest, or of a motor that did not
// move, computes nothing.
struct StepScale {
  uint32_t num, den, most;
  int32_t last_steps;
  Millideg last_angle;
};
StepScale g_scale[kJoints];

void setup_scale(StepScale& k, const MotorSpec& m) {
  k.num = k.den = k.most = 0;
  k.last_steps = 0;
  k.last_angle = m.zero;
  const int64_t den64 = detail::steps_den(m);  // steps_num is below 2^31 (validate)
  if (den64 > 0x7FFFFFFFLL) return;
  uint32_t num = uint32_t(detail::steps_num(m)), den = uint32_t(den64);
  uint32_t a = num, b = den;  // gcd
  while (b != 0) {
    const uint32_t t = a % b;
    a = b;
    b = t;
  }
  num /= a;
  den /= a;
  k.num = num;
  k.den = den;
  k.most = min_of(uint32_t((0xFFFFFFFFUL - num) / (2 * den)), uint32_t(0x7FFFFFFFUL));
}

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

Millideg step_angle(uint8_t i, int32_t steps) {
  StepScale& k = g_scale[i];
  if (steps == k.last_steps) return k.last_angle;
  const MotorSpec& m = actuation.motors[i];
  const uint32_t mag = steps < 0 ? 0u - uint32_t(steps) : uint32_t(steps);
  Millideg a;
  if (mag > k.most) {  // (also when k.most is 0)
    a = steps_to_millideg(m, steps);
  } else {
    // round(mag den / num), a half away from zero, as detail::div_round_half_away.
    const uint32_t q = (2 * mag * k.den + k.num) / (2 * k.num);
    a = (steps < 0) != (m.direction < 0) ? m.zero - Millideg(q) : m.zero + Millideg(q);
  }
  // Called from the status report only (one at a time): the cache needs no lock.
  k.last_steps = steps;
  k.last_angle = a;
  return a;
}

void setup() {
  for (uint8_t i = 0; i < kJoints; ++i) setup_scale(g_scale[i], actuation.motors[i]);
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
