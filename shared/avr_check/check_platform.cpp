#include <articula/platform.h>
#include "check_common.h"
using namespace articula;
void check_platform() {
  const Real x = g_in;
  g_out = long(1000 * (Math<Real>::sin(x) + Math<Real>::atan2(x, Real(1)) + Math<double>::cos(x) +
                       deg_to_rad(x) + rad_to_deg(x) + clamp(x, Real(0), Real(1))));
  g_out += is_finite(x) ? 1 : 0;
}
