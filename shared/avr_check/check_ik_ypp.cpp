#include <articula/ik_ypp.h>
#include "check_common.h"
using namespace articula;
void check_ik_ypp() {
  YppArm<Real> arm = {78, 0, 135, 147, 88, 0, true, {-1.5f, 0.6f, -0.75f}, {1.5f, 2.2f, 0.26f}};
  YppResult<Real> r;
  ypp_solve(r, arm, make_vec3(Real(200) * g_in, Real(10), Real(100)));
  Model<Real, kJoints, kRows> m;
  m.num_rows = 0;
  g_out = long(r.nearest.x + r.distance) + r.count + r.status + ypp_from_model(arm, m);
}
