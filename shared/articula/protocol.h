// articula/protocol.h - the serial protocol codec: bytes to lines, lines to commands,
// statuses to replies. docs/protocol.md is the specification; this is its code, shared by
// the firmware (parsing) and the host (formatting commands, reading replies).
//
// Grammar of a line (case-insensitive; spaces and tabs separate words):
//   line     = [ word { sep arg } ] [ "#" comment ]     terminated by LF, CR before it ignored
//   arg      = joint | number | bit
//   joint    = digit { digit }                          0-based index, below the joint count
//   number   = [ "+" | "-" ] digits [ "." [ digits ] ] | [ "+" | "-" ] "." digits
//              parsed exactly into thousandths; more decimals round half away from zero
//   bit      = "0" | "1"
// A line holds at most kMaxLineLength bytes before its LF; a longer one is read to its end
// and rejected as a whole.
//
// Commands are rows of one table (kCommandTable): a word, a type, and a pattern of argument
// kinds. A new command is a new row (and a handler in the firmware).
#ifndef ARTICULA_PROTOCOL_H
#define ARTICULA_PROTOCOL_H

#include "status.h"

namespace articula {

static const uint8_t kMaxLineLength = 64;
static const uint8_t kMaxArgs = 6;

enum CommandType : uint8_t {
  kCmdNone = 0,  // a comment-only line: nothing to do, replied `ok`
  kCmdRotate,    // L <joint> <degrees>: turn one joint by a relative angle
  kCmdGripper,   // S <1|0>: close (1) or open (0) the gripper
};

// Argument kinds in a pattern: 'j' joint index, 'n' number (thousandths), 'b' bit.
struct CommandSpec {
  const char* word;
  CommandType type;
  const char* args;
};

static const CommandSpec kCommandTable[] = {
    {"L", kCmdRotate, "jn"},
    {"S", kCmdGripper, "b"},
};
static const uint8_t kCommandCount = sizeof(kCommandTable) / sizeof(kCommandTable[0]);

struct Command {
  CommandType type;
  uint8_t argc;
  int32_t arg[kMaxArgs];  // joint index, number in thousandths (millidegrees), or bit
};

namespace detail {
inline bool is_space(char c) { return c == ' ' || c == '\t'; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline char to_upper(char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; }
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

// Parses one line (without its LF; a CR before it is ignored) into a command.
// num_joints bounds joint indices. On an error `out` is unspecified and nothing else
// changes: the caller acts on kOk only.
inline Status parse_line(Command& out, const char* line, uint8_t len, uint8_t num_joints) {
  if (len > 0 && line[len - 1] == '\r') --len;
  if (len > kMaxLineLength) return kLineTooLong;
  bool comment = false;
  uint8_t end = 0;
  for (; end < len; ++end) {
    const uint8_t c = uint8_t(line[end]);
    if (c == '#') {
      comment = true;
      break;
    }
    if ((c < 0x20 && c != '\t') || c >= 0x7f) return kBadCharacter;
  }
  // Split into words: start offsets and lengths of the first 1 + kMaxArgs, a count of all
  // (so an unknown word is reported as such however many words follow it).
  uint8_t start[kMaxArgs + 1], size[kMaxArgs + 1], words = 0;
  for (uint8_t i = 0; i < end;) {
    while (i < end && detail::is_space(line[i])) ++i;
    if (i == end) break;
    const uint8_t first = i;
    while (i < end && !detail::is_space(line[i])) ++i;
    if (words < kMaxArgs + 1) {
      start[words] = first;
      size[words] = uint8_t(i - first);
    }
    ++words;  // at most kMaxLineLength / 2
  }
  out.argc = 0;
  if (words == 0) {
    out.type = kCmdNone;
    return comment ? kOk : kEmptyLine;
  }
  const CommandSpec* spec = 0;
  for (uint8_t c = 0; c < kCommandCount && !spec; ++c) {
    const char* w = kCommandTable[c].word;
    uint8_t k = 0;
    while (k < size[0] && w[k] != '\0' && detail::to_upper(line[start[0] + k]) == w[k]) ++k;
    if (k == size[0] && w[k] == '\0') spec = &kCommandTable[c];
  }
  if (!spec) return kUnknownCommand;
  uint8_t wanted = 0;
  while (spec->args[wanted] != '\0') ++wanted;
  for (uint8_t a = 0; a < wanted; ++a) {
    if (1 + a >= words) return kMissingArgument;
    const char* s = line + start[1 + a];
    const uint8_t n = size[1 + a];
    int32_t v = 0;
    switch (spec->args[a]) {
      case 'j': {
        if (n > 3) return kBadJoint;
        for (uint8_t k = 0; k < n; ++k) {
          if (!detail::is_digit(s[k])) return kBadJoint;
          v = v * 10 + (s[k] - '0');
        }
        if (v >= num_joints) return kBadJoint;
        break;
      }
      case 'b': {
        if (n != 1 || !detail::is_digit(s[0])) return kBadNumber;
        v = s[0] - '0';
        if (v > 1) return kValueOutOfRange;
        break;
      }
      default: {  // 'n'
        const Status st = parse_thousandths(v, s, n);
        if (st != kOk) return st;
      }
    }
    out.arg[a] = v;
  }
  if (words > 1 + wanted) return kExtraArgument;
  out.type = spec->type;
  out.argc = wanted;
  return kOk;
}

// `ok` or `error:<code>` with its LF; returns the length written (without a NUL when the
// buffer is exactly full). cap >= 10 always suffices.
inline uint8_t format_reply(char* buf, uint8_t cap, Status status) {
  char tmp[12];
  uint8_t n = 0;
  if (status == kOk) {
    tmp[n++] = 'o';
    tmp[n++] = 'k';
  } else {
    const char* e = "error:";
    while (*e) tmp[n++] = *e++;
    const uint8_t code = uint8_t(status);
    if (code >= 100) tmp[n++] = char('0' + code / 100);
    if (code >= 10) tmp[n++] = char('0' + (code / 10) % 10);
    tmp[n++] = char('0' + code % 10);
  }
  tmp[n++] = '\n';
  uint8_t k = 0;
  for (; k < n && k < cap; ++k) buf[k] = tmp[k];
  if (k < cap) buf[k] = '\0';
  return k;
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

// Assembles bytes into lines. A line longer than kMaxLineLength (not counting one CR before
// its LF) is drained to its LF and then reported once as too long; its bytes are never
// handed out.
enum LineEvent : uint8_t { kLineNone = 0, kLineReady, kLineTooLongEnded };

class LineAssembler {
 public:
  LineAssembler() : len_(0), ready_len_(0), overflow_(false) {}

  LineEvent feed(char c) {
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

  // The current partial line, for a reset (a realtime stop, say).
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

}  // namespace articula

#endif  // ARTICULA_PROTOCOL_H
