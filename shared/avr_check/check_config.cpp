#include <articula/config.h>
#include "check_common.h"
using namespace articula;

// What the firmware does with a configuration: makes its built-in one, stages a value, reads
// an image into the core's structures, and checks its checksum.
void check_config() {
  static uint8_t image[kConfigImageSize];
  Model<Real, kJoints, kRows> m;
  m.num_rows = 0;
  Actuation<Real, kJoints> a = Actuation<Real, kJoints>();
  a.num_motors = kJoints;
  for (int i = 0; i < kJoints; ++i) {
    MotorSpec ms = {200, 1, 1, 47, 19, 0, -43000, long(g_in)};
    a.motors[i] = ms;
    a.coupling[i][i] = Real(1);
  }
  const Real home[kJoints] = {0, Real(g_in), 0};
  long sum = config_make(image, m, a, home, Real(90), Real(150), "MK2");
  sum += config_check(uint16_t(g_out), long(g_in)) + config_check_name("MK2 Plus", uint8_t(g_out));
  config_put(image, 101, long(g_in));
  ConfiguredArm<kJoints> arm;
  sum += config_read(arm, image) + config_checksum(image) + arm.home[1];
  g_out = sum;
}
