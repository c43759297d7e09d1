#include <articula/protocol.h>
#include "check_common.h"
using namespace articula;
void check_protocol() {
  LineAssembler in;
  const char* text = "L 1 -12.5\n";
  Command c;
  Status s = kOk;
  for (const char* p = text; *p; ++p)
    if (in.feed(*p) == kLineReady) s = parse_line(c, in.line(), in.length(), 3);
  char reply[12];
  uint8_t code = 0;
  const uint8_t n = format_reply(reply, sizeof reply, s);
  g_out = long(c.arg[1]) + n + parse_reply(code, reply, n) + code;
}
