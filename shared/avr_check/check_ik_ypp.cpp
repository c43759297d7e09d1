#include <articula/ik_ypp.h>
#include "check_common.h"
using namespace articula;
void check_ik_ypp() {
  YppArm<Real> arm = {78, 0, 135, 147, 88, 0, true, {-1.5f, 0.6f, -0.75f}, {1.5f, 2.2f, 0.26f}};
  YppResult<Real> r;
  ypp_solve(r, arm, make_vec3(Real(200) * g_in, Real(10), Real(100)));
  Model<Real, kJoints, kRows> m;
  m.num_rows = 0;
  Actuation<Real, kJoints> a;
  a.num_motors = kJoints;
  for (int i = 0; i < kJoints; ++i) {
    MotorSpec ms = {200, 1, 1, 47, 19, 0, -43000, long(g_in)};
    a.motors[i] = ms;
    for (int j = 0; j < kJoints; ++j) a.coupling[i][j] = i == j ? Real(1) : Real(0);
  }
  YppResult<Real> c;
  const int in_limits = ypp_closed_form(c, arm, make_vec3(Real(100), Real(10) * g_in, Real(200)));
  g_out = long(r.nearest.x + r.distance) + r.count + r.status + ypp_from_model(arm, m) + in_limits + c.count +
          ypp_limits_from_actuation(arm, a) + long(arm.hi[2]);
}
