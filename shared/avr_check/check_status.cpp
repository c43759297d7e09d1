#include <articula/status.h>
#include "check_common.h"
using namespace articula;
void check_status() {
  // The firmware prints numbers; the texts are for the host, but must compile here too.
  g_out = long(status_text(uint8_t(g_out))[0]) + status_name(kJointLimit)[0] + kStatusCount;
}
