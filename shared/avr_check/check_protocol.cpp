#include <articula/protocol.h>
#include "check_common.h"
using namespace articula;

// What the firmware holds, at its size: a command for three joints, one line buffer.
static_assert(sizeof(BasicCommand<kJoints + 1>) == 2 + 4 * (kJoints + 1), "a firmware command holds only its joints, or T's four numbers");
static_assert(sizeof(StatusReport<kJoints>) <= 34, "a status report is built on the stack (its I: 4 bytes)");
static_assert(sizeof(RealtimeCommand) == 1 && sizeof(MachineState) == 1, "one-byte enums");

// A stand-in for the firmware's serial transmit buffer.
struct SerialOut {
  void put(char c) { g_out = g_out + c; }
};

static LineAssembler s_line;
static BasicCommand<kJoints + 1> s_command;  // the firmware's: T's four numbers

// The firmware's receive path, linked: every byte goes to realtime_command first, the others
// build lines, each parsed and answered. (A function of its own, as in the firmware: inlined
// into one with the rest, its stack frame and code would be larger than theirs.)
__attribute__((noinline)) static uint8_t receive(char c) {
  const RealtimeCommand rt = realtime_command(c);
  if (rt != kRealtimeNone) return rt;
  if (s_line.feed(c) != kLineReady) return 0;
  char reply[12];
  const Status s = parse_line(s_command, s_line, kJoints);
  return format_reply(reply, sizeof reply, s);
}

// The reports (the firmware's writers; the host's buffer formatters and readers), with the
// firmware's sizes.
__attribute__((noinline)) static bool reports(SerialOut& out, char* buf, uint16_t len) {
  StatusReport<kJoints> r = StatusReport<kJoints>();
  InfoReport info = InfoReport();
  uint8_t code = 0;
  Command host_command = Command();
  const bool read = parse_reply(code, buf, uint8_t(len)) || parse_status(r, buf, len) || parse_info(info, buf, len) ||
                    parse_line(host_command, buf, uint8_t(len), kJoints) == kOk;
  const bool sent = write_status(out, r) && write_info(out, info) && write_setting(out, code, host_command.arg[0]);
  return read && sent && format_status(buf, len, r) + format_info(buf, len, info) + format_setting(buf, len, 1, 2) > 0;
}

void check_protocol() {
  long sum = 0;
  for (const char* p = "L 1 -12.5?\nM 1 2 3\n$3=200\n"; *p; ++p) sum += receive(*p);
  SerialOut out;
  char buf[64] = "<Idle|S:0,1,2>";
  sum += reports(out, buf, uint16_t(g_out & 63));
  g_out = sum + s_command.arg[1];
}
