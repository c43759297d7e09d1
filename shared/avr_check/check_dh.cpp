#include <articula/dh.h>
#include "check_common.h"
using namespace articula;
void check_dh() {
  Model<Real, kJoints, kRows> m;
  m.num_rows = kRows;
  m.num_joints = kJoints;
  m.num_linked = 1;
  for (int i = 0; i < kRows; ++i) {
    DhRow<Real> r = {Real(100) * g_in, Real(0), Real(0), Real(0)};
    m.rows[i] = r;
  }
  for (int j = 0; j < kJoints; ++j) {
    m.joints[j].row = uint8_t(j);
    m.joints[j].param = kParamTheta;
    m.joints[j].lo = Real(-3);
    m.joints[j].hi = Real(3);
  }
  m.linked[0].row = 3;
  m.linked[0].param = kParamTheta;
  m.linked[0].offset = 0;
  m.linked[0].gain[0] = 0;
  m.linked[0].gain[1] = -1;
  m.linked[0].gain[2] = -1;
  m.T_last_tool = Transform<Real>::identity();
  const Real q[kJoints] = {g_in, g_in, g_in};
  Frames<Real, kRows> f;
  forward_kinematics(f, m, q);
  Real J[6][kJoints];
  jacobian(J, m, f);
  const Model<double, kJoints, kRows> md = cast_model<double>(m);
  // The double model is the host's; here it only has to compile.
  g_out = long(J[0][0] + f.T_base_tool.p.x + md.rows[0].a) + validate(m) + within_limits(m, q);
}
