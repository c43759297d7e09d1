// articula/protocol.h - the serial protocol codec: bytes to lines, lines to commands,
// statuses and reports to reply lines and back. docs/protocol.md is the specification; this
// is its code, shared by the firmware (parsing lines, formatting replies) and the host
// (formatting commands, reading replies and reports).
//
// Grammar of a line (case-insensitive; spaces and tabs separate words):
//   line     = [ word { sep arg } ] [ "#" comment ]     terminated by LF, CR before it ignored
//   word     = letter | "$"                             a "$" is a word by itself: "$1=5" is
//                                                       the words "$" and "1=5"
//   arg      = joint | pin | number | bit | setting
//   joint    = digit { digit }                          0-based index, below the joint count
//   pin      = digit { digit }                          a header pin: D0..D13 are 0..13, A0..A5 14..19
//   number   = [ "+" | "-" ] digits [ "." [ digits ] ] | [ "+" | "-" ] "." digits
//              parsed exactly into thousandths; more decimals round half away from zero
//   bit      = "0" | "1"
//   setting  = digits "=" number                        one word: no blanks around "="
// A line holds at most kMaxLineLength bytes before its LF; a longer one is read to its end
// and rejected as a whole.
//
// Realtime bytes ('?' status report, '!' stop) act at once and are never part of a line:
// the firmware passes every received byte to realtime_command() before LineAssembler, which
// drops them wherever they are (mid-line, inside a comment); parse_line drops them too, so
// "L 0 1?0" is "L 0 10" on both paths. They do not count towards the line length.
//
// Commands are rows of one table (kCommandTable): a word, a type, and a pattern of argument
// kinds. A new command is a new row (and a handler in the firmware).
#ifndef ARTICULA_PROTOCOL_H
#define ARTICULA_PROTOCOL_H

#include "status.h"

namespace articula {

// 1: the original L and S. 2: M, P, G, H, Z, I, settings, realtime bytes, reports.
// 3: D (dwell). 4: the robot configuration (N, $1xx). 5: digital I/O (O, W, the report's I).
static const uint8_t kProtocolVersion = 5;

static const uint8_t kMaxLineLength = 64;

// Arguments a Command holds by default: one number per joint for `M` on a 12-joint host
// robot. The firmware uses BasicCommand<its joint count> (3 on the MK2: 14 bytes, not 50).
static const uint8_t kMaxArgs = 12;

enum CommandType : uint8_t {
  kCmdNone = 0,      // a comment-only line: nothing to do, replied `ok`
  kCmdRotate,        // L <joint> <degrees>: turn one actuator by a relative angle
  kCmdGripper,       // S <1|0>: close (1) or open (0) the gripper
  kCmdMoveAbsolute,  // M <a0> ... <aN-1>: every actuator to an absolute angle, degrees
  kCmdMoveTool,      // P <x> <y> <z>: the tool to a point, millimetres
  kCmdAperture,      // G <percent>: gripper aperture, 0 closed .. 100 fully open
  kCmdHome,          // H: home (seek endstops where fitted, else go to the home pose)
  kCmdSetZero,       // Z: declare the current position to be the home pose
  kCmdInfo,          // I: report firmware and protocol version, joints, robot name
  kCmdListSettings,  // $: report every setting
  kCmdSetSetting,    // $<n>=<value>: set setting n (the firmware validates n and value)
  kCmdDwell,         // D <seconds>: wait, in the queue, before the next queued command
  kCmdName,          // N <text>: the robot's name, staged in the configuration (config.h)
  kCmdLine,          // T <x> <y> <z> <mm/s>: the tool along a straight line to a point (line.h)
  kCmdOutput,        // O <pin> <0|1>: set an output pin, in the queue (after the moves before it)
  kCmdWaitInput,     // W <pin> <0|1> <seconds>: wait, in the queue, until an input reads a level
};

// The header's digital pins, by index: D0..D13 are 0..13, A0..A5 are 14..19 (board.h's table).
// O and W name them so; a pin the arm's drive uses is refused with kPinUnavailable.
static const uint8_t kIoPins = 20;

// The longest wait `D` takes, in milliseconds (thousandths of its seconds).
static const int32_t kMaxDwellMs = 600000L;

// The fastest tool speed `T` takes, in thousandths of a mm/s (1,000 mm/s).
static const int32_t kMaxLineSpeed = 1000000L;

// Argument kinds in a pattern, and what a bad one gives:
//   'j' joint index, below num_joints                       kBadJoint
//   'k' header pin index, below kIoPins                      kPinUnavailable
//   'n' number, in thousandths                              kBadNumber
//   'b' bit, 0 or 1                                         kBadNumber, kValueOutOfRange
//   'p' percent: a number from 0 to 100, in thousandths     kBadNumber, kValueOutOfRange
//   'w' wait: seconds from 0 to kMaxDwellMs / 1000, in thousandths (milliseconds)
//                                                           kBadNumber, kValueOutOfRange
//   'v' speed: above 0, at most kMaxLineSpeed, in thousandths kBadNumber, kValueOutOfRange
//   't' text: the rest of the line, blanks around it dropped (arg: its offset in the line
//       and its length; valid while the line is)            kMissingArgument
//   's' setting `<n>=<value>` (one word, two arguments: n of 1 to 3 digits, then the value
//       in thousandths)                                     kSettingUnknown, kMissingArgument,
//                                                           kBadNumber
// A '*' after a kind repeats it num_joints times: "n*" is one number per joint.
// Words are one character. A word may have two rows, one without arguments and one with;
// the line picks the row by whether it has any argument (`$` lists, `$1=5` sets).
struct CommandSpec {
  char word;
  CommandType type;
  char args[5];
};

static const CommandSpec kCommandTable[] ARTICULA_IN_FLASH = {
    {'L', kCmdRotate, "jn"},        // joint, degrees
    {'S', kCmdGripper, "b"},        // 1 close, 0 open
    {'M', kCmdMoveAbsolute, "n*"},  // degrees, one per joint
    {'P', kCmdMoveTool, "nnn"},     // x, y, z in mm
    {'G', kCmdAperture, "p"},       // percent open
    {'H', kCmdHome, ""},
    {'Z', kCmdSetZero, ""},
    {'I', kCmdInfo, ""},
    {'$', kCmdListSettings, ""},    // `$` alone
    {'$', kCmdSetSetting, "s"},     // `$<n>=<value>`
    {'D', kCmdDwell, "w"},          // seconds
    {'N', kCmdName, "t"},           // the robot's name
    {'T', kCmdLine, "nnnv"},        // x, y, z in mm, the tool's speed in mm/s
    {'O', kCmdOutput, "kb"},        // pin, level
    {'W', kCmdWaitInput, "kbw"},    // pin, level, seconds at most
};
static const uint8_t kCommandCount = sizeof(kCommandTable) / sizeof(kCommandTable[0]);

// Whether an argument of this kind is a number held in thousandths (the others are whole:
// joint indices, bits, setting numbers).
inline bool in_thousandths(char kind) { return kind == 'n' || kind == 'p' || kind == 'w' || kind == 'v'; }

// A parsed line. arg[] holds, in pattern order: joint indices, numbers in thousandths
// (millidegrees, micrometres, thousandths of a percent), bits, setting numbers.
template <uint8_t MaxArgs>
struct BasicCommand {
  static_assert(MaxArgs >= 4, "T takes four numbers");
  CommandType type;
  uint8_t argc;
  int32_t arg[MaxArgs];
};
typedef BasicCommand<kMaxArgs> Command;

// The aperture a gripper line asks for, in thousandths of a percent: G's number; S 1 closed (0),
// S 0 open (100,000). The firmware queues it, and the host's kinematic model keeps it, by this.
template <uint8_t MaxArgs>
inline int32_t command_aperture(const BasicCommand<MaxArgs>& c) {
  return c.type == kCmdAperture ? c.arg[0] : (c.arg[0] ? 0 : 100000L);
}
// An aperture in whole percent, as a status report's G gives it (rounded half up).
inline uint8_t aperture_percent(int32_t aperture) { return uint8_t((aperture + 500) / 1000); }

// Bytes that act at once, even in the middle of a line, and are never queued.
enum RealtimeCommand : uint8_t {
  kRealtimeNone = 0,  // an ordinary byte: feed it to the LineAssembler
  kRealtimeStatus,    // '?': send a status report (write_status) now
  kRealtimeStop,      // '!': decelerate to rest and empty the motion queue
};

inline RealtimeCommand realtime_command(char c) {
  return c == '?' ? kRealtimeStatus : c == '!' ? kRealtimeStop : kRealtimeNone;
}

namespace detail {
inline bool is_space(char c) { return c == ' ' || c == '\t'; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline char to_upper(char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; }

// Skips blanks from `at` to the next word in s[0, end); returns its length (0: no word).
inline uint8_t next_word(const char* s, uint8_t& at, uint8_t end) {
  while (at < end && is_space(s[at])) ++at;
  uint8_t e = at;
  while (e < end && !is_space(s[e])) ++e;
  return uint8_t(e - at);
}

// One to three digits (a joint index or a setting number).
inline bool parse_index(int32_t& out, const char* s, uint8_t len) {
  if (len == 0 || len > 3) return false;
  uint16_t v = 0;
  for (uint8_t k = 0; k < len; ++k) {
    if (!is_digit(s[k])) return false;
    v = uint16_t(v * 10 + (s[k] - '0'));
  }
  out = v;
  return true;
}
}  // namespace detail

// Parses a decimal number into thousandths. Accepts [+-]digits[.digits] and [+-].digits;
// rejects NaN, inf, exponents, empty strings and magnitudes above 1,000,000.
inline Status parse_thousandths(int32_t& out, const char* s, uint8_t len) {
  uint8_t i = 0;
  bool negative = false;
  if (i < len && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  int32_t whole = 0;  // thousandths
  uint8_t digits = 0, decimals = 0;
  bool round_up = false;
  for (; i < len && detail::is_digit(s[i]); ++i, ++digits) {
    if (whole > 100000000L) return kBadNumber;  // beyond 1,000,000 once scaled
    whole = whole * 10 + (s[i] - '0');
  }
  if (whole > 1000000L) return kBadNumber;
  whole *= 1000;
  if (i < len && s[i] == '.') {
    ++i;
    int32_t scale = 100;
    for (; i < len && detail::is_digit(s[i]); ++i, ++digits) {
      if (decimals < 3) {
        whole += (s[i] - '0') * scale;
        scale /= 10;
      } else if (decimals == 3) {
        round_up = s[i] >= '5';  // later digits only add: half away from zero
      }
      ++decimals;
    }
  }
  if (i != len || digits == 0) return kBadNumber;
  if (round_up) ++whole;
  if (whole > 1000000000L) return kBadNumber;
  out = negative ? -whole : whole;
  return kOk;
}

// Where a line's comment starts: its first '#' (a comment runs to the line's end), or `len`.
// The arm acts on what comes before it; every tool that reads a protocol line strips comments
// by this (the host's line_command, and through it Python's and the page's).
// (Counted in the length's own type: the firmware's lines are under 256 bytes.)
inline bool starts_comment(char c) { return c == '#'; }
template <typename Size>
inline Size comment_start(const char* text, Size len) {
  Size i = 0;
  while (i < len && !starts_comment(text[i])) ++i;
  return i;
}

namespace detail {
// parse_line on a line without realtime bytes, for any size of command.
inline Status parse_words(CommandType& type, uint8_t& argc, int32_t* arg, uint8_t max_args, const char* text,
                          uint8_t len, uint8_t num_joints) {
  uint8_t end = len;
  if (end > 0 && text[end - 1] == '\r') --end;
  if (end > kMaxLineLength) return kLineTooLong;
  bool comment = false;
  for (uint8_t i = 0; i < end; ++i) {  // (comment_start's walk, with the characters checked on the way)
    const uint8_t c = uint8_t(text[i]);
    if (starts_comment(char(c))) {
      comment = true;
      end = i;
      break;
    }
    if ((c < 0x20 && c != '\t') || c >= 0x7f) return kBadCharacter;
  }
  argc = 0;
  uint8_t at = 0;
  uint8_t size = detail::next_word(text, at, end);
  if (size == 0) {
    type = kCmdNone;
    return comment ? kOk : kEmptyLine;
  }
  if (text[at] == '$') size = 1;
  const char word = size == 1 ? detail::to_upper(text[at]) : '\0';
  at = uint8_t(at + size);
  uint8_t peek = at;
  const bool has_args = detail::next_word(text, peek, end) > 0;
  CommandSpec spec;
  bool found = false;
  for (uint8_t c = 0; c < kCommandCount; ++c) {
    const CommandSpec row = from_flash(kCommandTable[c]);
    if (row.word != word) continue;
    if (!found) spec = row;  // the only row, or the one to blame for a wrong argument count
    found = true;
    if ((row.args[0] != '\0') == has_args) {
      spec = row;
      break;
    }
  }
  if (!found) return kUnknownCommand;
  for (const char* kind = spec.args; *kind; ++kind) {
    const bool per_joint = kind[1] == '*';
    for (uint8_t r = per_joint ? num_joints : 1; r > 0; --r) {
      uint8_t n = detail::next_word(text, at, end);
      if (n == 0) return kMissingArgument;
      const char* s = text + at;
      at = uint8_t(at + n);
      int32_t v = 0;
      if (*kind == 't') {  // the rest of the line
        uint8_t e = end;
        while (e > at && detail::is_space(text[e - 1])) --e;
        if (argc + 2 > max_args) return kExtraArgument;
        arg[argc++] = int32_t(s - text);
        arg[argc++] = int32_t(e - (s - text));
        at = end;
        continue;
      }
      if (*kind == 's') {  // <n>=<value>: the setting number, then the value as a number
        uint8_t eq = 0;
        while (eq < n && s[eq] != '=') ++eq;
        if (!detail::parse_index(v, s, eq)) return kSettingUnknown;
        if (argc >= max_args) return kExtraArgument;
        arg[argc++] = v;
        if (eq + 1 >= n) return kMissingArgument;
        s += eq + 1;
        n = uint8_t(n - eq - 1);
      }
      if (*kind == 'j') {
        if (!detail::parse_index(v, s, n) || v >= num_joints) return kBadJoint;
      } else if (*kind == 'k') {
        if (!detail::parse_index(v, s, n) || v >= kIoPins) return kPinUnavailable;
      } else if (*kind == 'b') {
        if (n != 1 || !detail::is_digit(s[0])) return kBadNumber;
        v = s[0] - '0';
        if (v > 1) return kValueOutOfRange;
      } else {  // 'n', 'p', the value of 's'
        const Status st = parse_thousandths(v, s, n);
        if (st != kOk) return st;
        if (*kind == 'p' && (v < 0 || v > 100000L)) return kValueOutOfRange;
        if (*kind == 'w' && (v < 0 || v > kMaxDwellMs)) return kValueOutOfRange;
        if (*kind == 'v' && (v <= 0 || v > kMaxLineSpeed)) return kValueOutOfRange;
      }
      if (argc >= max_args) return kExtraArgument;
      arg[argc++] = v;
    }
    if (per_joint) ++kind;
  }
  if (detail::next_word(text, at, end) > 0) return kExtraArgument;
  type = spec.type;
  return kOk;
}

// A line that still holds realtime bytes: parsed as LineAssembler would have handed it out.
inline Status parse_without_realtime(CommandType& type, uint8_t& argc, int32_t* arg, uint8_t max_args,
                                     const char* line, uint8_t len, uint8_t num_joints) {
  char text[kMaxLineLength + 1];
  uint8_t n = 0;
  for (uint8_t i = 0; i < len; ++i) {
    if (realtime_command(line[i]) != kRealtimeNone) continue;
    if (n == kMaxLineLength + 1) return kLineTooLong;
    text[n++] = line[i];
  }
  return parse_words(type, argc, arg, max_args, text, n, num_joints);
}
}  // namespace detail

// Parses one line (without its LF; a CR before it is ignored; realtime bytes anywhere are
// dropped first, as LineAssembler drops them) into a command. num_joints bounds joint
// indices and is the count of numbers `M` takes; it must not exceed MaxArgs (an `M` line
// would give kExtraArgument). On an error `out` is unspecified and nothing else changes:
// the caller acts on kOk only. The firmware parses what LineAssembler hands out with the
// overload below, which skips the search for realtime bytes.
template <uint8_t MaxArgs>
inline Status parse_line(BasicCommand<MaxArgs>& out, const char* line, uint8_t len, uint8_t num_joints) {
  for (uint8_t i = 0; i < len; ++i)
    if (realtime_command(line[i]) != kRealtimeNone)
      return detail::parse_without_realtime(out.type, out.argc, out.arg, MaxArgs, line, len, num_joints);
  return detail::parse_words(out.type, out.argc, out.arg, MaxArgs, line, len, num_joints);
}

// Reads a reply line (`ok`, `error:N`, with or without CR/LF). False for anything else,
// such as a status report or noise.
inline bool parse_reply(uint8_t& code, const char* line, uint8_t len) {
  while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) --len;
  if (len == 2 && line[0] == 'o' && line[1] == 'k') {
    code = kOk;
    return true;
  }
  const char* e = "error:";
  uint8_t i = 0;
  for (; i < 6; ++i)
    if (i >= len || line[i] != e[i]) return false;
  if (i == len || len - i > 3) return false;
  int v = 0;
  for (; i < len; ++i) {
    if (!detail::is_digit(line[i])) return false;
    v = v * 10 + (line[i] - '0');
  }
  if (v > 255) return false;
  code = uint8_t(v);
  return true;
}

// ---- Reports: lines the controller sends besides `ok` / `error:N` ----
//
//   status   <Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>      on '?', at any time
//   info     [Articula|V:0.1.0|P:4|J:3|R:MK2 Plus|K:40233]              on I, before its ok
//   setting  $3=200.000                                                 on $, before its ok
// A report that has something to say once (settings reset to defaults) ends in |W:<code>.
// Integers and fixed-point thousandths are written by hand (no printf on AVR).
//
// Each report has two forms: write_*(sink, ...) sends it byte by byte to anything with a
// put(char) (the firmware's serial transmit buffer: no line buffer needed), and format_*
// writes it into a char buffer, returning its length with the LF, or 0 when the buffer is
// too small (a NUL follows the LF when there is room).

// What the controller is doing, the first word of a status report.
enum MachineState : uint8_t {
  kStateIdle = 0,  // at rest, the queue empty
  kStateRun,       // moving through the queue
  kStateStop,      // decelerating after '!'
  kStateHome,      // homing (H)
  kStateAlarm,     // position unknown (endstops fitted, not homed yet): moves give kNotHomed
};
static const uint8_t kStateCount = 5;
static const char* const kStateWords[kStateCount] = {"Idle", "Run", "Stop", "Home", "Alarm"};
// At rest: nothing runs, and nothing will until another line comes (Idle; Alarm after a failed
// homing, or unhomed at power-up). A sender that waits for a line's end waits for this: the
// harness, the studio and the Python link read it from the core (host/lib/protocol_view.cpp).
constexpr bool state_at_rest(MachineState s) { return s == kStateIdle || s == kStateAlarm; }

template <uint8_t MaxJoints>
struct StatusReport {
  MachineState state;
  uint8_t num_joints;           // entries used in steps[] and millideg[]
  int32_t steps[MaxJoints];     // S: motor positions in steps from step 0
  int32_t millideg[MaxJoints];  // A: the actuator angles those steps give, thousandths
  uint8_t gripper;              // G: aperture in percent, 0 closed .. 100 open
  uint8_t free_slots;           // Q: free places in the motion queue
  bool coils;                   // C: motor drivers energised
  int32_t io;                   // I: the levels of the pins the drive leaves free, bit n for
                                //    header pin n (kIoPins), 1 high; -1: not reported
  uint8_t warning;              // W: a status code said once (kSettingsReset); 0: none
};

// Bytes a buffer needs for any status report of `joints` joints, its LF and a NUL
// (a step count takes at most 11 characters, an angle 12, and a comma each).
// I's mask takes 7 more (up to 1,048,575, and its |I:).
constexpr uint16_t status_report_size(uint8_t joints) { return uint16_t(45 + 25 * joints); }

static const uint8_t kMaxRobotName = 24;

struct InfoReport {
  uint8_t version[3];            // V: firmware version, major.minor.patch
  uint8_t protocol;              // P: the protocol version the firmware speaks
  uint8_t num_joints;            // J: actuators, the count of numbers M takes
  char name[kMaxRobotName + 1];  // R: robot name, NUL-terminated; printable, no '|' or ']'
  int32_t checksum;              // K: the robot configuration's checksum, 0 to 65535
                                 //    (config.h); -1: none (a firmware before protocol 4)
  uint8_t warning;               // W: as in StatusReport
};

// Bytes a buffer needs for any info line, its LF and a NUL.
static const uint8_t kInfoReportSize = 79;
// Bytes a buffer needs for any setting line ($999=-2147483.648), its LF and a NUL.
static const uint8_t kSettingLineSize = 19;
// Bytes a buffer needs for any reply (error:255), its LF and a NUL.
static const uint8_t kReplySize = 11;

namespace detail {
template <typename Sink>
inline void write_text(Sink& out, const char* s) {
  while (*s) out.put(*s++);
}

// m / 10, its remainder in r, for every uint32, without a division (the AVR has no divide
// instruction: its 32-bit division routine takes ~40 us, and the Nano builds a status report,
// some 25 digits, in an interrupt). Below 2^16, x * 52429 / 2^19 (0.1 + 4e-7). Above, m * 0.8
// / 8 with the series 0.8 = 0.11001100.. in binary, truncated: m / 10 or one less, so one
// correction. Both checked for every uint32 once, and by the tests for a sample.
inline uint32_t divmod10(uint32_t m, uint8_t& r) {
  if (m < 0x10000UL) {  // most numbers of a report: one multiply (exact for every 16-bit m)
    const uint16_t x = uint16_t(m);
    // 16 x 16 -> 32 bits, and the shift as 16 + 3 (the AVR shifts bit by bit).
    const uint16_t q16 = uint16_t(uint16_t((uint32_t(x) * uint16_t(52429)) >> 16) >> 3);
    r = uint8_t(x - uint16_t(q16 * 10));
    return q16;
  }
  uint32_t q = (m >> 1) + (m >> 2);
  q += q >> 4;
  q += q >> 8;
  q += q >> 16;
  q >>= 3;
  uint8_t rest = uint8_t(m - ((q << 3) + (q << 1)));  // m - 10 q: 0 to 15
  if (rest > 9) {
    ++q;
    rest = uint8_t(rest - 10);
  }
  r = rest;
  return q;
}

// v / 10^decimals with exactly `decimals` (at most 9) decimals: (-5, 3) is "-0.005", (7, 0)
// is "7".
template <typename Sink>
inline void write_fixed(Sink& out, int32_t v, uint8_t decimals) {
  uint32_t m = v < 0 ? 0u - uint32_t(v) : uint32_t(v);  // INT32_MIN too
  if (v < 0) out.put('-');
  char d[10];
  uint8_t k = 0;
  do {
    uint8_t r;
    m = divmod10(m, r);
    d[k++] = char('0' + r);
  } while (m != 0 || k <= decimals);
  while (k > 0) {
    if (k == decimals) out.put('.');
    out.put(d[--k]);
  }
}

// "|K:" and the values, comma-separated.
template <typename Sink>
inline void write_field(Sink& out, char key, const int32_t* v, uint8_t count, uint8_t decimals) {
  out.put('|');
  out.put(key);
  out.put(':');
  for (uint8_t i = 0; i < count; ++i) {
    if (i > 0) out.put(',');
    write_fixed(out, v[i], decimals);
  }
}

template <typename Sink>
inline void write_field(Sink& out, char key, int32_t v) {
  write_field(out, key, &v, 1, 0);
}

// A sink into a fixed buffer that counts what does not fit.
class BufferSink {
 public:
  BufferSink(char* buf, uint16_t cap) : buf_(buf), cap_(cap), n_(0) {}
  void put(char c) {
    if (n_ < cap_) buf_[n_] = c;
    ++n_;
  }
  // The length written (the LF included), or 0 when it did not fit. NUL after it if room.
  uint16_t finish() {
    if (n_ > cap_) return 0;
    if (n_ < cap_) buf_[n_] = '\0';
    return n_;
  }

 private:
  char* buf_;
  uint16_t cap_;
  uint16_t n_;
};
}  // namespace detail

// False (nothing written) for a state or joint count the report cannot hold.
template <typename Sink, uint8_t MaxJoints>
inline bool write_status(Sink& out, const StatusReport<MaxJoints>& r) {
  if (r.state >= kStateCount || r.num_joints > MaxJoints) return false;
  out.put('<');
  detail::write_text(out, kStateWords[r.state]);
  detail::write_field(out, 'S', r.steps, r.num_joints, 0);
  detail::write_field(out, 'A', r.millideg, r.num_joints, 3);
  detail::write_field(out, 'G', r.gripper);
  detail::write_field(out, 'Q', r.free_slots);
  detail::write_field(out, 'C', r.coils);
  if (r.io >= 0) detail::write_field(out, 'I', r.io);
  if (r.warning != 0) detail::write_field(out, 'W', r.warning);
  out.put('>');
  out.put('\n');
  return true;
}

// False (nothing written) for a name that is too long or holds a byte the line cannot
// carry.
template <typename Sink>
inline bool write_info(Sink& out, const InfoReport& r) {
  uint8_t n = 0;
  for (; r.name[n] != '\0'; ++n) {
    const char c = r.name[n];
    if (n == kMaxRobotName || c < 0x20 || c > 0x7e || c == '|' || c == ']') return false;
  }
  detail::write_text(out, "[Articula|V:");
  for (uint8_t i = 0; i < 3; ++i) {
    if (i > 0) out.put('.');
    detail::write_fixed(out, r.version[i], 0);
  }
  detail::write_field(out, 'P', r.protocol);
  detail::write_field(out, 'J', r.num_joints);
  detail::write_text(out, "|R:");
  detail::write_text(out, r.name);
  if (r.checksum >= 0) detail::write_field(out, 'K', r.checksum);
  if (r.warning != 0) detail::write_field(out, 'W', r.warning);
  out.put(']');
  out.put('\n');
  return true;
}

// `ok` or `error:<code>` with its LF: the reply that ends every line (the firmware writes it
// with the number writer of every other report).
template <typename Sink>
inline void write_reply(Sink& out, Status status) {
  if (status == kOk) {
    out.put('o');
    out.put('k');
  } else {
    detail::write_text(out, "error:");
    detail::write_fixed(out, uint8_t(status), 0);
  }
  out.put('\n');
}

// The same into a buffer; returns the length written (without a NUL when the buffer is
// exactly full; cut short when it is too small). cap >= 10 always suffices.
inline uint8_t format_reply(char* buf, uint8_t cap, Status status) {
  struct Sink {
    char* buf;
    uint8_t cap, n;
    void put(char c) {
      if (n < cap) buf[n++] = c;
    }
  } out = {buf, cap, 0};
  write_reply(out, status);
  if (out.n < cap) buf[out.n] = '\0';
  return out.n;
}

// `$<n>=<value>` with three decimals: the same text as the command that sets it, so a
// listing sent back restores the settings (parse_line reads it as kCmdSetSetting). False
// (nothing written) for n above 999.
template <typename Sink>
inline bool write_setting(Sink& out, uint16_t number, int32_t value) {
  if (number > 999) return false;
  out.put('$');
  detail::write_fixed(out, number, 0);
  out.put('=');
  detail::write_fixed(out, value, 3);
  out.put('\n');
  return true;
}

template <uint8_t MaxJoints>
inline uint16_t format_status(char* buf, uint16_t cap, const StatusReport<MaxJoints>& r) {
  detail::BufferSink b(buf, cap);
  return write_status(b, r) ? b.finish() : 0;
}

inline uint16_t format_info(char* buf, uint16_t cap, const InfoReport& r) {
  detail::BufferSink b(buf, cap);
  return write_info(b, r) ? b.finish() : 0;
}

inline uint16_t format_setting(char* buf, uint16_t cap, uint16_t number, int32_t value) {
  detail::BufferSink b(buf, cap);
  return write_setting(b, number, value) ? b.finish() : 0;
}

// ---- Reading reports (host side; plain C++, so it compiles for AVR too) ----

namespace detail {
// [-]digits (at most 10) within [lo, hi].
inline bool parse_int(int32_t& out, const char* s, uint16_t len, int32_t lo, int32_t hi) {
  const uint16_t i = (len > 0 && s[0] == '-') ? 1 : 0;
  if (i == len || len - i > 10) return false;
  int64_t v = 0;
  for (uint16_t k = i; k < len; ++k) {
    if (!is_digit(s[k])) return false;
    v = v * 10 + (s[k] - '0');
  }
  if (i == 1) v = -v;
  if (v < lo || v > hi) return false;
  out = int32_t(v);
  return true;
}

// Integers (decimals 0, each within [lo, hi]) or thousandths (decimals 3) separated by
// `sep`, at most `max` of them; an empty text is an empty list.
inline bool parse_list(int32_t* out, uint8_t& count, const char* s, uint16_t len, uint8_t max, uint8_t decimals,
                       char sep, int32_t lo, int32_t hi) {
  count = 0;
  if (len == 0) return true;
  for (uint16_t i = 0;;) {
    uint16_t e = i;
    while (e < len && s[e] != sep) ++e;
    if (count == max || e - i > 20) return false;
    int32_t v = 0;
    const bool ok = decimals == 0 ? parse_int(v, s + i, uint16_t(e - i), lo, hi)
                                  : parse_thousandths(v, s + i, uint8_t(e - i)) == kOk;
    if (!ok) return false;
    out[count++] = v;
    if (e == len) return true;
    i = uint16_t(e + 1);  // past the separator; an empty item after it fails above
  }
}

// True when s[0, n) is the NUL-terminated `word`.
inline bool equals(const char* s, uint16_t n, const char* word) {
  uint16_t k = 0;
  while (k < n && word[k] != '\0' && s[k] == word[k]) ++k;
  return k == n && word[k] == '\0';
}

// The `|`-separated pieces of a report between its brackets (CR/LF after it ignored).
class ReportPieces {
 public:
  // False when the line is not `open` ... `close`.
  bool begin(const char* line, uint16_t len, char open, char close) {
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) --len;
    s_ = line;
    at_ = 1;
    end_ = uint16_t(len - 1);
    done_ = false;
    return len >= 2 && line[0] == open && line[len - 1] == close;
  }
  // The next piece (possibly empty); false after the last.
  bool next(const char*& piece, uint16_t& n) {
    if (done_) return false;
    uint16_t e = at_;
    while (e < end_ && s_[e] != '|') ++e;
    piece = s_ + at_;
    n = uint16_t(e - at_);
    done_ = e == end_;
    at_ = uint16_t(e + 1);
    return true;
  }

 private:
  const char* s_;
  uint16_t at_, end_;
  bool done_;
};
}  // namespace detail

// Reads a status report (with or without CR/LF). Fields may come in any order; unknown
// ones are skipped (a newer firmware may add some); S, A, G, Q, C are required, once each,
// with as many angles as steps. False (out untouched) for anything else.
template <uint8_t MaxJoints>
inline bool parse_status(StatusReport<MaxJoints>& out, const char* line, uint16_t len) {
  detail::ReportPieces pieces;
  const char* p = 0;
  uint16_t n = 0;
  if (!pieces.begin(line, len, '<', '>') || !pieces.next(p, n)) return false;
  uint8_t s = 0;
  while (s < kStateCount && !detail::equals(p, n, kStateWords[s])) ++s;
  if (s == kStateCount) return false;
  StatusReport<MaxJoints> r;
  r.state = MachineState(s);
  r.warning = 0;
  r.io = -1;
  uint8_t seen = 0, steps = 0, angles = 0;
  const int32_t lo = -2147483647L - 1, hi = 2147483647L;
  while (pieces.next(p, n)) {
    if (n < 2 || p[1] != ':') return false;
    const char* v = p + 2;
    const uint16_t vn = uint16_t(n - 2);
    int32_t x = 0;
    uint8_t bit = 0;
    bool ok = true;
    switch (p[0]) {
      case 'S':
        bit = 1;
        ok = detail::parse_list(r.steps, steps, v, vn, MaxJoints, 0, ',', lo, hi);
        break;
      case 'A':
        bit = 2;
        ok = detail::parse_list(r.millideg, angles, v, vn, MaxJoints, 3, ',', lo, hi);
        break;
      case 'G':
        bit = 4;
        ok = detail::parse_int(x, v, vn, 0, 100);
        r.gripper = uint8_t(x);
        break;
      case 'Q':
        bit = 8;
        ok = detail::parse_int(x, v, vn, 0, 255);
        r.free_slots = uint8_t(x);
        break;
      case 'C':
        bit = 16;
        ok = detail::parse_int(x, v, vn, 0, 1);
        r.coils = x != 0;
        break;
      case 'W':
        bit = 32;
        ok = detail::parse_int(x, v, vn, 1, 255);
        r.warning = uint8_t(x);
        break;
      case 'I':
        bit = 64;
        ok = detail::parse_int(x, v, vn, 0, (1L << kIoPins) - 1);
        r.io = x;
        break;
      default:  // a field this host does not know
        break;
    }
    if (!ok || (seen & bit) != 0) return false;
    seen = uint8_t(seen | bit);
  }
  if ((seen & 31) != 31 || steps != angles) return false;
  r.num_joints = steps;
  out = r;
  return true;
}

// Reads an info line (with or without CR/LF) by the same rules; V, P, J, R are required.
inline bool parse_info(InfoReport& out, const char* line, uint16_t len) {
  detail::ReportPieces pieces;
  const char* p = 0;
  uint16_t n = 0;
  if (!pieces.begin(line, len, '[', ']') || !pieces.next(p, n) || !detail::equals(p, n, "Articula")) return false;
  InfoReport r;
  r.warning = 0;
  r.checksum = -1;
  uint8_t seen = 0;
  while (pieces.next(p, n)) {
    if (n < 2 || p[1] != ':') return false;
    const char* v = p + 2;
    const uint16_t vn = uint16_t(n - 2);
    int32_t x[3] = {0, 0, 0};
    uint8_t bit = 0, count = 0;
    bool ok = true;
    switch (p[0]) {
      case 'V':
        bit = 1;
        ok = detail::parse_list(x, count, v, vn, 3, 0, '.', 0, 255) && count == 3;
        for (uint8_t k = 0; k < 3; ++k) r.version[k] = uint8_t(x[k]);
        break;
      case 'P':
        bit = 2;
        ok = detail::parse_int(x[0], v, vn, 0, 255);
        r.protocol = uint8_t(x[0]);
        break;
      case 'J':
        bit = 4;
        ok = detail::parse_int(x[0], v, vn, 0, 255);
        r.num_joints = uint8_t(x[0]);
        break;
      case 'R':
        bit = 8;
        ok = vn <= kMaxRobotName;
        for (uint16_t k = 0; ok && k < vn; ++k) r.name[k] = v[k];
        if (ok) r.name[vn] = '\0';
        break;
      case 'W':
        bit = 16;
        ok = detail::parse_int(x[0], v, vn, 1, 255);
        r.warning = uint8_t(x[0]);
        break;
      case 'K':
        bit = 32;
        ok = detail::parse_int(x[0], v, vn, 0, 65535);
        r.checksum = x[0];
        break;
      default:
        break;
    }
    if (!ok || (seen & bit) != 0) return false;
    seen = uint8_t(seen | bit);
  }
  if ((seen & 15) != 15) return false;
  out = r;
  return true;
}

// Assembles bytes into lines. A line longer than kMaxLineLength (not counting one CR before
// its LF) is drained to its LF and then reported once as too long; its bytes are never
// handed out. Realtime bytes ('?', '!') are dropped wherever they come: the caller acts on
// them (realtime_command) and they never count towards a line.
enum LineEvent : uint8_t { kLineNone = 0, kLineReady, kLineTooLongEnded };

class LineAssembler {
 public:
  // (constexpr: a static one is all zero in .bss, with no constructor run at start-up)
  constexpr LineAssembler() : buf_(), len_(0), ready_len_(0), overflow_(false) {}

  LineEvent feed(char c) {
    if (realtime_command(c) != kRealtimeNone) return kLineNone;
    if (c == '\n') {
      // kMaxLineLength + 1 bytes fit only when the last is the CR of a CRLF.
      const bool too_long = overflow_ || (len_ == kMaxLineLength + 1 && buf_[kMaxLineLength] != '\r');
      overflow_ = false;
      ready_len_ = too_long ? 0 : len_;
      len_ = 0;
      return too_long ? kLineTooLongEnded : kLineReady;
    }
    if (overflow_) return kLineNone;
    if (len_ == kMaxLineLength + 1) {  // room for one CR before the LF
      overflow_ = true;
      return kLineNone;
    }
    buf_[len_++] = c;
    return kLineNone;
  }

  // The line just completed by kLineReady (valid until the next feed).
  const char* line() const { return buf_; }
  uint8_t length() const { return ready_len_; }

  // The current partial line, for a reset.
  void clear() {
    len_ = 0;
    overflow_ = false;
  }

 private:
  char buf_[kMaxLineLength + 1];
  uint8_t len_;
  uint8_t ready_len_;
  bool overflow_;
};

// The line LineAssembler just completed (kLineReady), parsed: parse_line on its bytes,
// without looking for realtime bytes, which it never holds. The firmware's path.
template <uint8_t MaxArgs>
inline Status parse_line(BasicCommand<MaxArgs>& out, const LineAssembler& in, uint8_t num_joints) {
  return detail::parse_words(out.type, out.argc, out.arg, MaxArgs, in.line(), in.length(), num_joints);
}

}  // namespace articula

#endif  // ARTICULA_PROTOCOL_H
