#include <articula/settings.h>
#include "check_common.h"
using namespace articula;
// The firmware's settings check: a value in thousandths against the table.
void check_settings() {
  g_out = long(check_setting(int32_t(g_in), int32_t(g_out), 3)) + long(setting_range(uint8_t(g_in), 3).fallback);
}
