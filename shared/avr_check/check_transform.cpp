#include <articula/transform.h>
#include "check_common.h"
using namespace articula;
void check_transform() {
  const Real x = g_in;
  const Transform<Real> a = make_transform(rpy_to_matrix(x, x, x), make_vec3(x, Real(1), Real(2)));
  const Transform<Real> b = inverse(a) * a;
  const Vec3<Real> rpy = matrix_to_rpy(b.R);
  g_out = long(1000 * (rpy.x + norm(b * make_vec3(x, x, x)) + dot(b.p, cross(a.p, b.p))));
}
