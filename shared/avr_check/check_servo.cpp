#include <articula/servo.h>
#include "check_common.h"
using namespace articula;
void check_servo() {
  // The firmware's gripper: an aperture to a pulse, in float.
  g_out = long(servo_pulse_us<Real>(Real(g_in), Real(g_in) + 90, long(g_out)));
}
