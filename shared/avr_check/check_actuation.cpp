#include <articula/actuation.h>
#include "check_common.h"
using namespace articula;
void check_actuation() {
  Actuation<Real, kJoints> a;
  a.num_motors = kJoints;
  for (int i = 0; i < kJoints; ++i) {
    MotorSpec m = {200, 1, 1, 108, 19, 0, -90000, 90000};
    a.motors[i] = m;
    for (int j = 0; j < kJoints; ++j) a.coupling[i][j] = i == j ? Real(1) : Real(0);
  }
  a.coupling[2][1] = -1;
  const bool inverted = invert_coupling(a);
  MotorState<kJoints> st;
  reset(st, a);
  Millideg delta = 0;
  to_millideg(delta, g_in * 1000);
  const Status s = move_relative(st, a, 1, delta);
  Real q[kJoints], u[kJoints];
  joints_from_steps(q, a, st.steps);
  actuators_from_joints(u, a, q);
  g_out = long(u[0] + quantization_error_degrees<Real>(a.motors[0], delta)) + s + inverted + validate(a.motors[0]) +
          min_steps(a.motors[1]) + max_steps(a.motors[2]) + quantize(a.motors[0], delta) +
          steps_to_millideg(a.motors[1], st.steps[1]);
}
