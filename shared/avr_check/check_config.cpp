#include <articula/config.h>
#include "check_common.h"
using namespace articula;

// What the firmware does with a configuration: checks and stages a value, reads an image into
// the core's structures, and checks its checksum.
void check_config() {
  static uint8_t image[kConfigImageSize];
  long sum = config_check(uint16_t(g_out), long(g_in)) + config_check_name("MK2 Plus", uint8_t(g_out));
  config_put(image, 101, long(g_in));
  ConfigField f;
  uint8_t b[4];
  if (config_field(uint16_t(g_out), f)) config_bytes(b, f, long(g_in));
  ConfiguredArm<kJoints> arm;
  sum += config_read(arm, image) + config_checksum(image) + arm.home[1] + b[0];
  g_out = sum;
}
