// Tests shared/articula/protocol.h: number parsing into thousandths, the line grammar and its
// error codes (every command of the table), realtime bytes, the byte-to-line assembler (CRLF,
// overlong lines, realtime bytes, random noise), the `ok` / `error:<code>` replies and the
// status, info and setting reports (exact texts, round trips).
#include <articula/protocol.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace articula;

namespace articula {
// Readable failure messages (uint8_t enums would print as characters).
void PrintTo(Status s, std::ostream* os) { *os << int(s) << " (" << status_name(s) << ")"; }
void PrintTo(LineEvent e, std::ostream* os) { *os << int(e); }
void PrintTo(CommandType t, std::ostream* os) { *os << int(t); }
void PrintTo(RealtimeCommand r, std::ostream* os) { *os << int(r); }
void PrintTo(MachineState s, std::ostream* os) { *os << int(s); }
}  // namespace articula

namespace {

Status num(int32_t& out, const std::string& s) { return parse_thousandths(out, s.data(), uint8_t(s.size())); }

Status parse(Command& c, const std::string& s, uint8_t joints = 3) {
  return parse_line(c, s.data(), uint8_t(s.size()), joints);
}

Status parse(const std::string& s, uint8_t joints = 3) {
  Command c;
  return parse(c, s, joints);
}

// An independent reference for numbers: the exact decimal value, rounded to thousandths
// half away from zero by looking at the digits as text. Returns false when out of range.
bool reference_thousandths(const std::string& digits_int, const std::string& digits_frac, bool negative,
                           int64_t& out) {
  // Value * 10000 as an exact integer from the first 4 decimals, plus "any later nonzero".
  __int128 v = 0;
  for (char c : digits_int) v = v * 10 + (c - '0');
  std::string f = digits_frac;
  while (f.size() < 4) f += '0';
  for (int k = 0; k < 3; ++k) v = v * 10 + (f[k] - '0');
  // Half away from zero: the 4th decimal >= 5 rounds the magnitude up (later digits can
  // only make it larger, never push it below the half).
  if (f[3] >= '5') v += 1;
  if (v > 1000000000) return false;
  out = negative ? -int64_t(v) : int64_t(v);
  return true;
}

}  // namespace

TEST(ParseThousandths, Valid) {
  int32_t v = 0;
  EXPECT_EQ(num(v, "12"), kOk);
  EXPECT_EQ(v, 12000);
  EXPECT_EQ(num(v, "-12.5"), kOk);
  EXPECT_EQ(v, -12500);
  EXPECT_EQ(num(v, "+0.001"), kOk);
  EXPECT_EQ(v, 1);
  EXPECT_EQ(num(v, ".5"), kOk);
  EXPECT_EQ(v, 500);
  EXPECT_EQ(num(v, "-.5"), kOk);
  EXPECT_EQ(v, -500);
  EXPECT_EQ(num(v, "12.3456"), kOk);
  EXPECT_EQ(v, 12346);
  EXPECT_EQ(num(v, "12.3454"), kOk);
  EXPECT_EQ(v, 12345);
  EXPECT_EQ(num(v, "12.3455"), kOk);
  EXPECT_EQ(v, 12346);
  EXPECT_EQ(num(v, "-12.3455"), kOk);
  EXPECT_EQ(v, -12346);
  EXPECT_EQ(num(v, "12.34549999"), kOk);  // below the half, however many 9s
  EXPECT_EQ(v, 12345);
  EXPECT_EQ(num(v, "-0.0005"), kOk);  // half away from zero
  EXPECT_EQ(v, -1);
  EXPECT_EQ(num(v, "0.0005"), kOk);
  EXPECT_EQ(v, 1);
  EXPECT_EQ(num(v, "-0.0004"), kOk);
  EXPECT_EQ(v, 0);
  EXPECT_EQ(num(v, "0"), kOk);
  EXPECT_EQ(v, 0);
  EXPECT_EQ(num(v, "-0"), kOk);
  EXPECT_EQ(v, 0);
  EXPECT_EQ(num(v, "12."), kOk);  // digits then a bare point
  EXPECT_EQ(v, 12000);
  EXPECT_EQ(num(v, "007.250"), kOk);
  EXPECT_EQ(v, 7250);
  EXPECT_EQ(num(v, "1000000"), kOk);
  EXPECT_EQ(v, 1000000000);
  EXPECT_EQ(num(v, "-1000000"), kOk);
  EXPECT_EQ(v, -1000000000);
  EXPECT_EQ(num(v, "1000000.0004"), kOk);  // rounds down to the maximum
  EXPECT_EQ(v, 1000000000);
  EXPECT_EQ(num(v, "999999.9995"), kOk);  // rounds up to the maximum
  EXPECT_EQ(v, 1000000000);
  EXPECT_EQ(num(v, "0000000000000000000000000000001"), kOk);  // leading zeros are harmless
  EXPECT_EQ(v, 1000);
}

TEST(ParseThousandths, Invalid) {
  const char* bad[] = {"1000000.001", "1000000.0005", "-1000000.001", "1000001", "99999999999", "1e3", "1E3",
                       "nan",         "NaN",          "inf",          "-inf",    "-",           "+",   ".",
                       "-.",          "+.",           "",             "1.2.3",   "12a",         "a12", "--1",
                       "+-1",         " 1",           "1 ",           "0x10",    "1,5"};
  for (const char* s : bad) {
    int32_t v = 4242;
    EXPECT_EQ(num(v, s), kBadNumber) << '"' << s << '"';
    EXPECT_EQ(v, 4242) << s;  // untouched on error
  }
}

TEST(ParseThousandths, RandomAgainstReference) {
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> ndig(0, 8), nfrac(0, 7), digit(0, 9), coin(0, 3);
  int ok = 0, rejected = 0;
  for (int t = 0; t < 200000; ++t) {
    std::string i, f;
    const int ni = ndig(rng), nf = nfrac(rng);
    for (int k = 0; k < ni; ++k) i += char('0' + digit(rng));
    for (int k = 0; k < nf; ++k) f += char('0' + digit(rng));
    const int sign = coin(rng);  // 0: none, 1: '-', 2: '+', 3: none
    const bool point = nf > 0 || coin(rng) == 0;
    std::string s = (sign == 1 ? "-" : sign == 2 ? "+" : "") + i + (point ? "." : "") + f;
    int32_t v = 0;
    const Status st = num(v, s);
    int64_t expected = 0;
    if (i.empty() && f.empty()) {
      ASSERT_EQ(st, kBadNumber) << s;
    } else if (!reference_thousandths(i, f, sign == 1, expected)) {
      ASSERT_EQ(st, kBadNumber) << s;
      ++rejected;
    } else {
      ASSERT_EQ(st, kOk) << s;
      ASSERT_EQ(v, expected) << s;
      ++ok;
    }
  }
  EXPECT_GT(ok, 50000);
  EXPECT_GT(rejected, 10000);
}

TEST(ParseLine, ValidRotate) {
  struct Case {
    const char* line;
    int32_t joint, millideg;
  };
  const Case cases[] = {
      {"L 0 10", 0, 10000},
      {"l 2 -5.5", 2, -5500},
      {"L\t1\t+.25", 1, 250},
      {"   L   0     10   ", 0, 10000},
      {"\tL \t 1 \t 0.001\t", 1, 1},
      {"L 0 10 # hi", 0, 10000},
      {"L 0 10# hi", 0, 10000},
      {"L 0 10#", 0, 10000},
      {"L 0 10\r", 0, 10000},
      {"L 0 10 # comment\r", 0, 10000},
      {"L 00 1", 0, 1000},
      {"L 002 1", 2, 1000},
      {"L 1 1000000", 1, 1000000000},
      {"L 1 -1000000", 1, -1000000000},
      {"L 2 12.3456", 2, 12346},
      {"L 0 -0.0005", 0, -1},
  };
  for (const Case& c : cases) {
    Command cmd;
    cmd.type = kCmdGripper;
    ASSERT_EQ(parse(cmd, c.line), kOk) << '"' << c.line << '"';
    EXPECT_EQ(cmd.type, kCmdRotate) << c.line;
    EXPECT_EQ(cmd.argc, 2) << c.line;
    EXPECT_EQ(cmd.arg[0], c.joint) << c.line;
    EXPECT_EQ(cmd.arg[1], c.millideg) << c.line;
  }
}

TEST(ParseLine, ValidGripper) {
  const std::pair<const char*, int> cases[] = {{"S 1", 1}, {"s 0", 0}, {"S\t1\r", 1}, {"  s  1  # close", 1},
                                               {"S 0#", 0}};
  for (const auto& c : cases) {
    Command cmd;
    ASSERT_EQ(parse(cmd, c.first), kOk) << '"' << c.first << '"';
    EXPECT_EQ(cmd.type, kCmdGripper);
    EXPECT_EQ(cmd.argc, 1);
    EXPECT_EQ(cmd.arg[0], c.second);
  }
}

TEST(ParseLine, CommentsAndEmptyLines) {
  for (const char* s : {"# just a comment", "#", "   # indented", "\t#", "#\r", "# L 0 10", "## ##"}) {
    Command cmd;
    cmd.type = kCmdRotate;
    cmd.argc = 5;
    ASSERT_EQ(parse(cmd, s), kOk) << '"' << s << '"';
    EXPECT_EQ(cmd.type, kCmdNone) << s;
    EXPECT_EQ(cmd.argc, 0) << s;
  }
  for (const char* s : {"", " ", "\t", "  \t  ", "\r", " \r"}) EXPECT_EQ(parse(s), kEmptyLine) << '"' << s << '"';
  // Nothing after '#' is looked at, not even its bytes.
  EXPECT_EQ(parse(std::string("L 0 1 # \x01\xff")), kOk);
}

TEST(ParseLine, Malformed) {
  const std::pair<const char*, Status> cases[] = {
      {"xyz", kUnknownCommand},
      {"LL 0 1", kUnknownCommand},
      {"G1 X10", kUnknownCommand},
      {"0 10", kUnknownCommand},
      {"L", kMissingArgument},
      {"L # 0 10", kMissingArgument},
      {"L 0", kMissingArgument},
      {"L 0 # 10", kMissingArgument},
      {"L 0 1 2", kExtraArgument},
      {"L 0 1 x", kExtraArgument},
      {"L 0 1 2 3 4 5 6 7 8 9 10", kExtraArgument},
      {"L 3 10", kBadJoint},
      {"L -1 10", kBadJoint},
      {"L +0 10", kBadJoint},
      {"L a 10", kBadJoint},
      {"L 0.0 10", kBadJoint},
      {"L 999 10", kBadJoint},
      {"L 1000 10", kBadJoint},
      {"L 4294967296 10", kBadJoint},
      {"L 9 nan", kBadJoint},  // arguments are checked in order
      {"L 0 nan", kBadNumber},
      {"L 0 inf", kBadNumber},
      {"L 0 1e5", kBadNumber},
      {"L 0 1000000.001", kBadNumber},
      {"L 0 --1", kBadNumber},
      {"S 2", kValueOutOfRange},
      {"S 9", kValueOutOfRange},
      {"S", kMissingArgument},
      {"S 1 1", kExtraArgument},
      {"S x", kBadNumber},
      {"S 01", kBadNumber},
      {"S -1", kBadNumber},
      {"S 1.0", kBadNumber},
      // An unknown word is reported as such however many words follow it.
      {"xyz 1 2 3 4 5 6 7 8 9 10", kUnknownCommand},
  };
  for (const auto& c : cases) EXPECT_EQ(parse(c.first), c.second) << '"' << c.first << '"';
}

TEST(ParseLine, BadCharacters) {
  const std::string bad[] = {std::string("L 0 1\x01"), std::string("L 0 \xff"), std::string("\x7f"),
                             std::string("L 0\0 1", 7),  std::string("L 0\r 1"),   std::string("L\x0b" "0 1"),
                             std::string("S 1\x1b[A"),  std::string("\xc3\xa9"),  std::string("L 0 1\r\r")};
  for (const std::string& s : bad) EXPECT_EQ(parse(s), kBadCharacter) << s.size();
  // Every byte: printable ASCII, space and tab are allowed, nothing else.
  for (int b = 0; b < 256; ++b) {
    const std::string s = std::string("L 0 1 ") + char(b);
    const Status st = parse(s);
    if (b == '\t' || b == ' ' || b == '#' || b == '\r' || b == '?' || b == '!')
      EXPECT_EQ(st, kOk) << b;  // separator, comment, the CR before the LF, or a realtime byte
    else if (b < 0x20 || b >= 0x7f)
      EXPECT_EQ(st, kBadCharacter) << b;
    else
      EXPECT_EQ(st, kExtraArgument) << b;
  }
}

TEST(ParseLine, LineLength) {
  ASSERT_EQ(kMaxLineLength, 64);
  std::string s = "L 0 1";
  s.resize(64, ' ');
  EXPECT_EQ(parse(s), kOk);
  EXPECT_EQ(parse(s + "\r"), kOk);  // the CR does not count
  EXPECT_EQ(parse(s + " "), kLineTooLong);
  EXPECT_EQ(parse(s + " \r"), kLineTooLong);
  std::string c = "# ";
  c.resize(65, 'x');
  EXPECT_EQ(parse(c), kLineTooLong);  // comments count too
  c.resize(64);
  EXPECT_EQ(parse(c), kOk);
  EXPECT_EQ(parse(std::string(200, 'x')), kLineTooLong);
  // A number padded to the full length.
  std::string n = "L 2 -0.";
  n.resize(64, '0');
  Command cmd;
  ASSERT_EQ(parse(cmd, n), kOk);
  EXPECT_EQ(cmd.arg[1], 0);
  n[63] = '9';  // ...0009 at the 57th decimal: below half a thousandth
  ASSERT_EQ(parse(cmd, n), kOk);
  EXPECT_EQ(cmd.arg[1], 0);
}

TEST(ParseLine, JointCountBoundsIndex) {
  EXPECT_EQ(parse(std::string("L 5 1")), kBadJoint);
  Command cmd;
  EXPECT_EQ(parse(cmd, "L 5 1", 6), kOk);
  EXPECT_EQ(cmd.arg[0], 5);
  EXPECT_EQ(parse(cmd, "L 6 1", 6), kBadJoint);
  EXPECT_EQ(parse(cmd, "L 0 1", 0), kBadJoint);
  EXPECT_EQ(parse(cmd, "L 254 1", 255), kOk);
  EXPECT_EQ(parse(cmd, "L 255 1", 255), kBadJoint);
}

namespace {

struct Event {
  LineEvent kind;
  std::string line;
};

// Feeds bytes; returns the events (kLineNone is never recorded but checked: only LF ends).
std::vector<Event> feed_all(LineAssembler& a, const std::string& bytes) {
  std::vector<Event> out;
  for (char c : bytes) {
    const LineEvent e = a.feed(c);
    if (c != '\n') {
      EXPECT_EQ(e, kLineNone);
      continue;
    }
    EXPECT_NE(e, kLineNone);
    out.push_back(Event{e, e == kLineReady ? std::string(a.line(), a.length()) : std::string()});
  }
  return out;
}

}  // namespace

TEST(LineAssembler, LfCompletesALine) {
  LineAssembler a;
  const std::vector<Event> ev = feed_all(a, "L 0 10\nS 1\n\n");
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[0].kind, kLineReady);
  EXPECT_EQ(ev[0].line, "L 0 10");
  EXPECT_EQ(ev[1].line, "S 1");
  EXPECT_EQ(ev[2].kind, kLineReady);
  EXPECT_EQ(ev[2].line, "");
}

TEST(LineAssembler, CrLf) {
  LineAssembler a;
  const std::vector<Event> ev = feed_all(a, "L 1 -5\r\nS 0\r\n\r\n");
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[0].line, "L 1 -5\r");
  Command cmd;
  ASSERT_EQ(parse(cmd, ev[0].line), kOk);
  EXPECT_EQ(cmd.arg[1], -5000);
  EXPECT_EQ(parse(ev[1].line), kOk);
  EXPECT_EQ(parse(ev[2].line), kEmptyLine);
}

TEST(LineAssembler, OverlongLineDrainedAndReportedOnce) {
  LineAssembler a;
  const std::string longline(300, 'x');
  std::vector<Event> ev = feed_all(a, longline + "\nS 1\n");
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, kLineTooLongEnded);
  EXPECT_EQ(ev[1].kind, kLineReady);
  EXPECT_EQ(ev[1].line, "S 1");
  // Exactly at the limit: accepted, with or without CR.
  std::string s64 = "L 0 1";
  s64.resize(64, ' ');
  ev = feed_all(a, s64 + "\n" + s64 + "\r\n");
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, kLineReady);
  EXPECT_EQ(ev[0].line, s64);
  EXPECT_EQ(ev[1].kind, kLineReady);
  EXPECT_EQ(ev[1].line, s64 + "\r");
  EXPECT_EQ(parse(ev[1].line), kOk);
  // One byte over, with or without CR: too long, its bytes never handed out.
  ev = feed_all(a, s64 + "y\n" + s64 + "y\r\n" + s64 + "\r\r\nS 0\n");
  ASSERT_EQ(ev.size(), 4u);
  EXPECT_EQ(ev[0].kind, kLineTooLongEnded);
  EXPECT_EQ(ev[1].kind, kLineTooLongEnded);
  EXPECT_EQ(ev[2].kind, kLineTooLongEnded);
  EXPECT_EQ(ev[3].kind, kLineReady);
  EXPECT_EQ(ev[3].line, "S 0");
}

TEST(LineAssembler, Clear) {
  LineAssembler a;
  feed_all(a, "L 0 garbage");
  a.clear();
  std::vector<Event> ev = feed_all(a, "S 1\n");
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].line, "S 1");
  feed_all(a, std::string(100, 'z'));  // into overflow
  a.clear();
  ev = feed_all(a, "S 0\n");
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].kind, kLineReady);
  EXPECT_EQ(ev[0].line, "S 0");
}

TEST(LineAssembler, RandomByteSoup) {
  // 100,000 random bytes against a reference: a line (its bytes up to LF, one CR before the
  // LF not counted) of at most 64 bytes is handed out whole, a longer one reported once.
  // Realtime bytes ('?', '!') are dropped wherever they come and do not count.
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> byte(0, 255), pick(0, 99);
  std::string soup;
  for (int i = 0; i < 100000; ++i) {
    const int p = pick(rng);
    soup += p < 2 ? '\n' : p < 4 ? '\r' : p < 6 ? "?!"[p - 4] : p < 50 ? char(byte(rng)) : char(' ' + pick(rng) % 95);
  }
  LineAssembler a;
  std::string current;
  std::string raw;  // the bytes since the last LF, realtime ones included
  int lfs = 0, ready = 0, too_long = 0, parsed_ok = 0, compared = 0;
  for (char c : soup) {
    const LineEvent e = a.feed(c);
    if (c != '\n') {
      ASSERT_EQ(e, kLineNone);
      if (realtime_command(c) == kRealtimeNone) current += c;
      raw += c;
      continue;
    }
    ++lfs;
    std::string content = current;
    if (!content.empty() && content.back() == '\r') content.pop_back();
    if (content.size() > kMaxLineLength) {
      ASSERT_EQ(e, kLineTooLongEnded) << current.size();
      ++too_long;
    } else {
      ASSERT_EQ(e, kLineReady) << current.size();
      ASSERT_LE(a.length(), kMaxLineLength + 1);
      ASSERT_EQ(std::string(a.line(), a.length()), current);
      Command cmd, direct;
      const Status st = parse_line(cmd, a.line(), a.length(), 3);
      ASSERT_NE(st, kLineTooLong);
      ASSERT_EQ(parse_line(direct, a, 3), st);  // the firmware's overload
      if (st == kOk) {
        ASSERT_EQ(direct.type, cmd.type);
      }
      parsed_ok += st == kOk;
      ++ready;
    }
    // parse_line on the raw bytes drops the realtime bytes as the assembler did.
    if (raw.size() <= 255) {
      Command from_raw, from_line;
      const Status st_raw = parse_line(from_raw, raw.data(), uint8_t(raw.size()), 3);
      const Status st_line = e == kLineReady ? parse_line(from_line, a.line(), a.length(), 3) : kLineTooLong;
      ASSERT_EQ(st_raw, st_line) << raw.size();
      if (st_raw == kOk) {
        ASSERT_EQ(from_raw.type, from_line.type);
        ASSERT_EQ(from_raw.argc, from_line.argc);
        for (int k = 0; k < from_raw.argc; ++k) ASSERT_EQ(from_raw.arg[k], from_line.arg[k]);
      }
      ++compared;
    }
    raw.clear();
    current.clear();
  }
  EXPECT_EQ(ready + too_long, lfs);
  EXPECT_GT(compared, 1000);
  EXPECT_GT(ready, 500);
  EXPECT_GT(too_long, 300);
  EXPECT_GT(lfs, 1500);
}

TEST(Replies, FormatAndParseEveryStatus) {
  for (uint8_t code = 0; code < kStatusCount; ++code) {
    char buf[16];
    std::memset(buf, '#', sizeof buf);
    const uint8_t n = format_reply(buf, sizeof buf, Status(code));
    const std::string expected = code == 0 ? "ok\n" : "error:" + std::to_string(code) + "\n";
    ASSERT_EQ(std::string(buf, n), expected);
    EXPECT_EQ(buf[n], '\0');
    uint8_t back = 255;
    ASSERT_TRUE(parse_reply(back, buf, n)) << expected;
    EXPECT_EQ(back, code);
    const std::string crlf = expected.substr(0, expected.size() - 1) + "\r\n";
    back = 255;
    ASSERT_TRUE(parse_reply(back, crlf.data(), uint8_t(crlf.size())));
    EXPECT_EQ(back, code);
    const std::string bare = expected.substr(0, expected.size() - 1);
    back = 255;
    ASSERT_TRUE(parse_reply(back, bare.data(), uint8_t(bare.size())));
    EXPECT_EQ(back, code);
  }
  char buf[16];
  EXPECT_EQ(std::string(buf, format_reply(buf, sizeof buf, kOk)), "ok\n");
  EXPECT_EQ(std::string(buf, format_reply(buf, sizeof buf, kLineTooLong)), "error:7\n");
  EXPECT_EQ(std::string(buf, format_reply(buf, sizeof buf, kBadCharacter)), "error:11\n");
  EXPECT_EQ(std::string(buf, format_reply(buf, sizeof buf, Status(200))), "error:200\n");
  // Ten bytes always suffice; a smaller buffer is filled without overrun.
  std::memset(buf, '#', sizeof buf);
  EXPECT_EQ(format_reply(buf, 10, Status(255)), 10);
  EXPECT_EQ(std::string(buf, 10), "error:255\n");
  EXPECT_EQ(buf[10], '#');
  std::memset(buf, '#', sizeof buf);
  EXPECT_EQ(format_reply(buf, 5, kLineTooLong), 5);
  EXPECT_EQ(std::string(buf, 5), "error");
  EXPECT_EQ(buf[5], '#');
  uint8_t code = 0;
  ASSERT_TRUE(parse_reply(code, "error:7\n", 8));
  EXPECT_EQ(code, 7);
  ASSERT_TRUE(parse_reply(code, "ok\n", 3));
  EXPECT_EQ(code, 0);
  ASSERT_TRUE(parse_reply(code, "error:255", 9));
  EXPECT_EQ(code, 255);
}

TEST(Replies, ParseRejects) {
  const char* bad[] = {"oK",        "OK",       "Ok\n",      "okk",      " ok",     "ok ",      "error:",
                       "error:\n",  "error:x",  "error:1234", "error:256", "error:-1", "error: 7", "Error:7",
                       "error7",    "<status>", "",          "\n",       "error:7x", "err"};
  for (const char* s : bad) {
    uint8_t code = 99;
    EXPECT_FALSE(parse_reply(code, s, uint8_t(std::strlen(s)))) << '"' << s << '"';
    EXPECT_EQ(code, 99) << s;
  }
}

// ---- The commands added in protocol version 2 ----

namespace {

// Parses and checks the type and arguments in one go.
::testing::AssertionResult parses_to(const std::string& line, CommandType type, const std::vector<int32_t>& args,
                                     uint8_t joints = 3) {
  Command cmd;
  cmd.type = kCmdNone;
  const Status st = parse(cmd, line, joints);
  if (st != kOk) return ::testing::AssertionFailure() << '"' << line << "\" gives " << int(st);
  if (cmd.type != type) return ::testing::AssertionFailure() << '"' << line << "\" is type " << int(cmd.type);
  if (std::vector<int32_t>(cmd.arg, cmd.arg + cmd.argc) != args)
    return ::testing::AssertionFailure() << '"' << line << "\" has " << int(cmd.argc) << " other arguments";
  return ::testing::AssertionSuccess();
}

}  // namespace

TEST(ParseLine, MoveAbsolute) {
  EXPECT_TRUE(parses_to("M 10 -20.5 +.25", kCmdMoveAbsolute, {10000, -20500, 250}));
  EXPECT_TRUE(parses_to("m 0 0 0", kCmdMoveAbsolute, {0, 0, 0}));
  EXPECT_TRUE(parses_to("  M\t1  2 \t 3  # to the start\r", kCmdMoveAbsolute, {1000, 2000, 3000}));
  EXPECT_TRUE(parses_to("M 1 2 3#", kCmdMoveAbsolute, {1000, 2000, 3000}));
  EXPECT_TRUE(parses_to("M 12.3456 -0.0005 1000000", kCmdMoveAbsolute, {12346, -1, 1000000000}));
  // One number per joint, however many joints.
  EXPECT_TRUE(parses_to("M 7", kCmdMoveAbsolute, {7000}, 1));
  EXPECT_TRUE(parses_to("M 1 2 3 4 5 6 7 8 9 10 11 12", kCmdMoveAbsolute,
                        {1000, 2000, 3000, 4000, 5000, 6000, 7000, 8000, 9000, 10000, 11000, 12000}, 12));
  EXPECT_EQ(parse(std::string("M 1 2 3"), 12), kMissingArgument);
  EXPECT_EQ(parse(std::string("M 1 2 3 4 5 6 7 8 9 10 11 12"), 3), kExtraArgument);
  const std::pair<const char*, Status> bad[] = {
      {"M", kMissingArgument},      {"M 1", kMissingArgument},     {"M 1 2", kMissingArgument},
      {"M 1 2 # 3", kMissingArgument}, {"M 1 2 3 4", kExtraArgument}, {"M 1 2 3 x", kExtraArgument},
      {"M 1 x 3", kBadNumber},      {"M 1 2 nan", kBadNumber},     {"M inf 2 3", kBadNumber},
      {"M 1 2 1e3", kBadNumber},    {"M 1 2 1000000.001", kBadNumber}, {"M x", kBadNumber},
      {"M1 2 3", kUnknownCommand},  {"MM 1 2 3", kUnknownCommand},
  };
  for (const auto& c : bad) EXPECT_EQ(parse(c.first), c.second) << '"' << c.first << '"';
}

TEST(ParseLine, MoveAbsoluteNeedsRoomForEveryJoint) {
  // A command sized for fewer joints than the arm has cannot hold an M line.
  BasicCommand<4> small;  // the Nano's: T's four numbers
  EXPECT_EQ(parse_line(small, "M 1 2 3 4", 9, 4), kOk);
  EXPECT_EQ(small.argc, 4);
  EXPECT_EQ(parse_line(small, "M 1 2 3 4 5", 11, 5), kExtraArgument);
  EXPECT_EQ(parse_line(small, "M 1 2 3", 7, 5), kMissingArgument);  // the line's own fault comes first
  EXPECT_EQ(parse_line(small, "L 3 1", 5, 5), kOk);
  EXPECT_LE(sizeof(BasicCommand<4>), 4 + 4 * sizeof(int32_t));  // 18 bytes on AVR (no padding there)
  EXPECT_EQ(sizeof(Command::arg) / sizeof(int32_t), 12u);        // M on a 12-joint host robot
}

TEST(ParseLine, MoveTool) {
  EXPECT_TRUE(parses_to("P 100 -20.5 30", kCmdMoveTool, {100000, -20500, 30000}));
  EXPECT_TRUE(parses_to("p\t.5\t-.5\t0\r", kCmdMoveTool, {500, -500, 0}));
  EXPECT_TRUE(parses_to(" P 1 2 3 # mm", kCmdMoveTool, {1000, 2000, 3000}));
  EXPECT_TRUE(parses_to("P 1 2 3", kCmdMoveTool, {1000, 2000, 3000}, 12));  // not per joint
  const std::pair<const char*, Status> bad[] = {
      {"P", kMissingArgument},   {"P 1 2", kMissingArgument}, {"P 1 2 3 4", kExtraArgument},
      {"P nan 0 0", kBadNumber}, {"P 0 NaN 0", kBadNumber},   {"P 0 0 -inf", kBadNumber},
      {"P 1 2 3.4.5", kBadNumber}, {"P 1 2 1000001", kBadNumber},
  };
  for (const auto& c : bad) EXPECT_EQ(parse(c.first), c.second) << '"' << c.first << '"';
}

TEST(ParseLine, Dwell) {
  EXPECT_TRUE(parses_to("D 0", kCmdDwell, {0}));
  EXPECT_TRUE(parses_to("d 1.5 # a breath", kCmdDwell, {1500}));
  EXPECT_TRUE(parses_to("D 600", kCmdDwell, {600000}));
  const std::pair<const char*, Status> bad[] = {{"D 600.001", kValueOutOfRange}, {"D -0.001", kValueOutOfRange},
                                                {"D x", kBadNumber},            {"D", kMissingArgument},
                                                {"D 1 2", kExtraArgument}};
  for (const auto& b : bad) EXPECT_EQ(parse(b.first), b.second) << b.first;
}

TEST(ParseLine, Aperture) {
  EXPECT_TRUE(parses_to("G 0", kCmdAperture, {0}));
  EXPECT_TRUE(parses_to("g 100", kCmdAperture, {100000}));
  EXPECT_TRUE(parses_to("G 50.5 # half open\r", kCmdAperture, {50500}));
  EXPECT_TRUE(parses_to("G -0", kCmdAperture, {0}));
  EXPECT_TRUE(parses_to("G -0.0004", kCmdAperture, {0}));        // rounds to 0
  EXPECT_TRUE(parses_to("G 100.0004", kCmdAperture, {100000}));  // rounds to 100
  const std::pair<const char*, Status> bad[] = {
      {"G 101", kValueOutOfRange},     {"G -1", kValueOutOfRange},  {"G 100.001", kValueOutOfRange},
      {"G 100.0005", kValueOutOfRange}, {"G -0.001", kValueOutOfRange}, {"G -0.0005", kValueOutOfRange},
      {"G 1000000", kValueOutOfRange}, {"G x", kBadNumber},         {"G nan", kBadNumber},
      {"G 2000000", kBadNumber},       {"G", kMissingArgument},     {"G 1 2", kExtraArgument},
      {"G1", kUnknownCommand},         {"G1 X10", kUnknownCommand},
  };
  for (const auto& c : bad) EXPECT_EQ(parse(c.first), c.second) << '"' << c.first << '"';
}

TEST(ParseLine, CommandsWithoutArguments) {
  const std::pair<const char*, CommandType> good[] = {
      {"H", kCmdHome},   {"h", kCmdHome},       {" H # home\r", kCmdHome}, {"Z", kCmdSetZero},
      {"z\r", kCmdSetZero}, {"\tZ\t", kCmdSetZero}, {"I", kCmdInfo},        {"i # who?", kCmdInfo},
  };
  for (const auto& c : good) EXPECT_TRUE(parses_to(c.first, c.second, {}));
  const std::pair<const char*, Status> bad[] = {
      {"H 1", kExtraArgument},   {"Z 0", kExtraArgument}, {"I x", kExtraArgument},
      {"HZ", kUnknownCommand},   {"Home", kUnknownCommand}, {"I2", kUnknownCommand},
  };
  for (const auto& c : bad) EXPECT_EQ(parse(c.first), c.second) << '"' << c.first << '"';
}

TEST(ParseLine, Settings) {
  EXPECT_TRUE(parses_to("$", kCmdListSettings, {}));
  EXPECT_TRUE(parses_to("  $  # list\r", kCmdListSettings, {}));
  EXPECT_TRUE(parses_to("$#", kCmdListSettings, {}));
  EXPECT_TRUE(parses_to("$1=5", kCmdSetSetting, {1, 5000}));
  EXPECT_TRUE(parses_to("$12=-0.5\r", kCmdSetSetting, {12, -500}));
  EXPECT_TRUE(parses_to("$ 3=200 # steps", kCmdSetSetting, {3, 200000}));  // "$" is a word by itself
  EXPECT_TRUE(parses_to("\t$007=+.25", kCmdSetSetting, {7, 250}));
  EXPECT_TRUE(parses_to("$999=1000000", kCmdSetSetting, {999, 1000000000}));
  EXPECT_TRUE(parses_to("$0=0", kCmdSetSetting, {0, 0}));
  const std::pair<const char*, Status> bad[] = {
      {"$x=1", kSettingUnknown},   {"$=5", kSettingUnknown},     {"$-1=1", kSettingUnknown},
      {"$1000=1", kSettingUnknown}, {"$1.5=1", kSettingUnknown},  {"$$", kSettingUnknown},
      {"$x", kSettingUnknown},     {"$1=", kMissingArgument},    {"$1", kMissingArgument},
      {"$1 =5", kMissingArgument}, {"$1= 5", kMissingArgument},  {"$1=abc", kBadNumber},
      {"$1=nan", kBadNumber},      {"$1=1e3", kBadNumber},       {"$1=5=6", kBadNumber},
      {"$1=-", kBadNumber},        {"$1=5 6", kExtraArgument},   {"$1=5 $2=6", kExtraArgument},
  };
  for (const auto& c : bad) EXPECT_EQ(parse(c.first), c.second) << '"' << c.first << '"';
}

TEST(ParseLine, DigitalIo) {
  // A header pin by index (D0..D13, A0..A5: 0..19), a level, W's seconds as D's.
  EXPECT_TRUE(parses_to("O 19 1", kCmdOutput, {19, 1}));
  EXPECT_TRUE(parses_to("o 0 0 # D0", kCmdOutput, {0, 0}));
  EXPECT_TRUE(parses_to("W 18 0 2.5", kCmdWaitInput, {18, 0, 2500}));
  EXPECT_TRUE(parses_to("W 12 1 0", kCmdWaitInput, {12, 1, 0}));
  EXPECT_EQ(parse("O 20 1"), kPinUnavailable);
  EXPECT_EQ(parse("O 1234 1"), kPinUnavailable);
  EXPECT_EQ(parse("O -1 1"), kPinUnavailable);
  EXPECT_EQ(parse("O A5 1"), kPinUnavailable);
  EXPECT_EQ(parse("O 19 2"), kValueOutOfRange);
  EXPECT_EQ(parse("O 19"), kMissingArgument);
  EXPECT_EQ(parse("W 19 1"), kMissingArgument);
  EXPECT_EQ(parse("W 19 1 601"), kValueOutOfRange);
  EXPECT_EQ(parse("W 19 1 -1"), kValueOutOfRange);
  EXPECT_EQ(parse("W 19 1 nan"), kBadNumber);
  EXPECT_EQ(parse("W 19 1 5 5"), kExtraArgument);
}

TEST(ParseLine, EveryTableRowIsReachable) {
  // A valid line built from each row's pattern parses to that row's type: no row is shadowed
  // by another with the same word.
  std::set<int> types;
  for (uint8_t r = 0; r < kCommandCount; ++r) {
    const CommandSpec& row = kCommandTable[r];
    std::string line(1, row.word);
    std::vector<int32_t> args;
    for (const char* k = row.args; *k; ++k) {
      const int repeat = k[1] == '*' ? 3 : 1;
      for (int i = 0; i < repeat; ++i) {
        switch (*k) {
          case 'j': line += " 2", args.push_back(2); break;
          case 'k': line += " 19", args.push_back(19); break;
          case 'b': line += " 1", args.push_back(1); break;
          case 's': line += " 4=7", args.push_back(4), args.push_back(7000); break;
          case 't': line += " My arm ", args.push_back(2), args.push_back(6); break;  // offset, length
          default: line += " 7", args.push_back(7000);
        }
      }
      if (k[1] == '*') ++k;
    }
    EXPECT_TRUE(parses_to(line, row.type, args)) << line;
    types.insert(row.type);
  }
  EXPECT_EQ(types.size(), size_t(kCommandCount));
  EXPECT_EQ(kCommandCount, 15);
}

// ---- Realtime bytes ----

TEST(Realtime, ClassifiesEveryByte) {
  for (int b = 0; b < 256; ++b) {
    const RealtimeCommand r = realtime_command(char(b));
    if (b == '?')
      EXPECT_EQ(r, kRealtimeStatus);
    else if (b == '!')
      EXPECT_EQ(r, kRealtimeStop);
    else
      EXPECT_EQ(r, kRealtimeNone) << b;
  }
}

TEST(Realtime, ParseLineDropsThem) {
  EXPECT_TRUE(parses_to("L 0 1?0", kCmdRotate, {0, 10000}));
  EXPECT_TRUE(parses_to("?L 0 10!", kCmdRotate, {0, 10000}));
  EXPECT_TRUE(parses_to("L !0 1?0\r?", kCmdRotate, {0, 10000}));  // after the CR too
  EXPECT_TRUE(parses_to("S 1 # done?", kCmdGripper, {1}));
  EXPECT_TRUE(parses_to("$?1=5", kCmdSetSetting, {1, 5000}));
  EXPECT_TRUE(parses_to("?!# comment", kCmdNone, {}));
  EXPECT_EQ(parse(std::string("?")), kEmptyLine);  // the LF after a lone '?' ends an empty line
  EXPECT_EQ(parse(std::string("!\r")), kEmptyLine);
  EXPECT_EQ(parse(std::string("L 0 ?")), kMissingArgument);
  // They do not count towards the 64 bytes.
  std::string s = "L 0 1";
  s.resize(64, ' ');
  EXPECT_EQ(parse(s + std::string(100, '?')), kOk);
  EXPECT_EQ(parse(std::string(100, '!') + s + "\r"), kOk);
  EXPECT_EQ(parse(s + "?x"), kLineTooLong);
  EXPECT_EQ(parse(s + "?x\r"), kLineTooLong);
  EXPECT_EQ(parse(std::string(250, 'x') + "?"), kLineTooLong);  // stops copying at the limit
  EXPECT_EQ(parse("?" + std::string(254, '\r')), kLineTooLong);
  // Still a bad character where one is.
  EXPECT_EQ(parse(std::string("L 0 ?\x01") + "1"), kBadCharacter);
}

TEST(Realtime, LineAssemblerDropsThem) {
  LineAssembler a;
  std::vector<Event> ev = feed_all(a, "L 0 1?0\n?!S 1!\n# why?\n");
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[0].line, "L 0 10");
  EXPECT_EQ(ev[1].line, "S 1");
  EXPECT_EQ(ev[2].line, "# why");
  Command cmd;
  ASSERT_EQ(parse(cmd, ev[0].line), kOk);
  EXPECT_EQ(cmd.arg[1], 10000);
  // The firmware's path: parse what the assembler holds.
  BasicCommand<4> fw;
  for (char c : std::string("M 1?0 2! 3\n")) a.feed(c);
  ASSERT_EQ(parse_line(fw, a, 3), kOk);
  EXPECT_EQ(fw.type, kCmdMoveAbsolute);
  EXPECT_EQ(fw.arg[0], 10000);
  EXPECT_EQ(fw.arg[2], 3000);
  // A lone '?' and its LF: the LF ends an empty line.
  ev = feed_all(a, "?\n");
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].kind, kLineReady);
  EXPECT_EQ(ev[0].line, "");
  // Not counted towards the length: 64 bytes with 200 realtime bytes among them still fit.
  std::string s64 = "L 0 1";
  s64.resize(64, ' ');
  std::string mixed;
  for (size_t i = 0; i < s64.size(); ++i) mixed += s64[i] + std::string(i % 2 ? "???" : "!!!!");
  ev = feed_all(a, mixed + "\r\n" + mixed + "y\n");
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, kLineReady);
  EXPECT_EQ(ev[0].line, s64 + "\r");
  EXPECT_EQ(ev[1].kind, kLineTooLongEnded);
}

// ---- Reports ----

namespace {

template <uint8_t J>
std::string status_text_of(const StatusReport<J>& r) {
  char buf[status_report_size(J)];
  const uint16_t n = format_status(buf, sizeof buf, r);
  return std::string(buf, n);
}

std::string setting_text(uint16_t number, int32_t value) {
  char buf[kSettingLineSize];
  return std::string(buf, format_setting(buf, sizeof buf, number, value));
}

StatusReport<3> example_status() {
  StatusReport<3> r;
  r.state = kStateIdle;
  r.num_joints = 3;
  const int32_t steps[] = {0, 32, -5}, mdeg[] = {0, 10133, -3639};
  for (int i = 0; i < 3; ++i) r.steps[i] = steps[i], r.millideg[i] = mdeg[i];
  r.gripper = 100;
  r.free_slots = 15;
  r.coils = true;
  r.io = -1;  // (a firmware without I/O: no I field)
  r.warning = 0;
  return r;
}

}  // namespace

TEST(Reports, FixedPointIsExact) {
  // Thousandths written by hand, through the setting line (the same writer as every report).
  const std::pair<int32_t, const char*> cases[] = {
      {-5, "-0.005"},       {-12000, "-12.000"},   {0, "0.000"},          {5, "0.005"},
      {-1, "-0.001"},       {999, "0.999"},        {-999, "-0.999"},      {1000, "1.000"},
      {-1001, "-1.001"},    {10133, "10.133"},     {-3639, "-3.639"},     {120, "0.120"},
      {1000000000, "1000000.000"}, {-1000000000, "-1000000.000"},
      {2147483647, "2147483.647"}, {-2147483647 - 1, "-2147483.648"},
  };
  for (const auto& c : cases) EXPECT_EQ(setting_text(3, c.first), std::string("$3=") + c.second + "\n") << c.first;
  // Against the host's printf for many values.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int32_t> any(-2147483647 - 1, 2147483647), small(-20000, 20000);
  for (int t = 0; t < 20000; ++t) {
    const int32_t v = t % 2 ? any(rng) : small(rng);
    const int64_t m = v < 0 ? -int64_t(v) : v;
    char expected[32];
    std::snprintf(expected, sizeof expected, "$999=%s%lld.%03lld\n", v < 0 ? "-" : "", (long long)(m / 1000),
                  (long long)(m % 1000));
    ASSERT_EQ(setting_text(999, v), expected);
  }
}

// The writer's division by 10 without a divide: around every power of two and of ten, and
// a random sample (every uint32 was checked once, offline: 9 s).
TEST(Reports, DivMod10IsExact) {
  std::vector<uint32_t> v;
  for (uint32_t b = 0; b < 32; ++b)
    for (int64_t d = -12; d <= 12; ++d) v.push_back(uint32_t((int64_t(1) << b) + d));
  for (uint64_t p = 1; p <= 4000000000ULL; p *= 10)
    for (int64_t d = -12; d <= 12; ++d) v.push_back(uint32_t(int64_t(p) + d));
  std::mt19937 rng(5);
  for (int t = 0; t < 2000000; ++t) v.push_back(rng());
  for (uint32_t m = 0; m < 200000; ++m) v.push_back(m);
  v.push_back(0xFFFFFFFFu);
  for (uint32_t m : v) {
    uint8_t r = 0;
    const uint32_t q = detail::divmod10(m, r);
    ASSERT_EQ(q, m / 10) << m;
    ASSERT_EQ(r, m % 10) << m;
  }
}

TEST(Reports, StatusExactText) {
  StatusReport<3> r = example_status();
  EXPECT_EQ(status_text_of(r), "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>\n");
  r.state = kStateAlarm;
  r.coils = false;
  r.gripper = 0;
  r.free_slots = 0;
  r.warning = kSettingsReset;
  r.millideg[0] = -5;
  r.millideg[2] = -12000;
  EXPECT_EQ(status_text_of(r), "<Alarm|S:0,32,-5|A:-0.005,10.133,-12.000|G:0|Q:0|C:0|W:14>\n");
  const char* words[] = {"Idle", "Run", "Stop", "Home", "Alarm"};
  ASSERT_EQ(kStateCount, 5);
  for (uint8_t s = 0; s < kStateCount; ++s) {
    r.state = MachineState(s);
    EXPECT_EQ(status_text_of(r).substr(0, 1 + std::strlen(words[s]) + 1), std::string("<") + words[s] + "|");
  }
  r.num_joints = 0;
  r.state = kStateRun;
  r.warning = 0;
  EXPECT_EQ(status_text_of(r), "<Run|S:|A:|G:0|Q:0|C:0>\n");
}

TEST(Reports, StatusBufferSizeIsTightAndSafe) {
  // The longest report of 3 and of 12 joints fills status_report_size() exactly (with NUL).
  for (uint8_t joints : {uint8_t(3), uint8_t(12)}) {
    StatusReport<12> r;
    r.state = kStateAlarm;
    r.num_joints = joints;
    for (int i = 0; i < 12; ++i) r.steps[i] = -2147483647 - 1, r.millideg[i] = -2147483647 - 1;
    r.gripper = 100;
    r.free_slots = 255;
    r.coils = true;
    r.io = (1L << kIoPins) - 1;
    r.warning = 255;
    std::vector<char> buf(status_report_size(joints) + 8, '#');
    const uint16_t n = format_status(buf.data(), status_report_size(joints), r);
    ASSERT_EQ(n, status_report_size(joints) - 1u) << int(joints);
    EXPECT_EQ(buf[n - 1], '\n');
    EXPECT_EQ(buf[n], '\0');
    EXPECT_EQ(buf[n + 1], '#');
    // One byte less: no room for the NUL, still complete. Two less: refused, no overrun.
    std::fill(buf.begin(), buf.end(), '#');
    EXPECT_EQ(format_status(buf.data(), uint16_t(n), r), n);
    EXPECT_EQ(buf[n], '#');
    std::fill(buf.begin(), buf.end(), '#');
    EXPECT_EQ(format_status(buf.data(), uint16_t(n - 1), r), 0);
    EXPECT_EQ(buf[n - 1], '#');
  }
  // What a report cannot hold.
  StatusReport<3> r = example_status();
  char buf[status_report_size(3)];
  r.state = MachineState(kStateCount);
  EXPECT_EQ(format_status(buf, sizeof buf, r), 0);
  r = example_status();
  r.num_joints = 4;
  EXPECT_EQ(format_status(buf, sizeof buf, r), 0);
}

TEST(Reports, StatusRoundTripRandom) {
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int32_t> steps(-2147483647 - 1, 2147483647), mdeg(-1000000000, 1000000000),
      near(-40000, 40000);
  std::uniform_int_distribution<int> joints(0, 12), state(0, kStateCount - 1), pct(0, 100), byte(0, 255), coin(0, 3);
  for (int t = 0; t < 20000; ++t) {
    StatusReport<12> r;
    r.state = MachineState(state(rng));
    r.num_joints = uint8_t(joints(rng));
    for (int i = 0; i < r.num_joints; ++i) {
      r.steps[i] = coin(rng) ? near(rng) : steps(rng);
      r.millideg[i] = coin(rng) ? near(rng) : mdeg(rng);
    }
    r.gripper = uint8_t(pct(rng));
    r.free_slots = uint8_t(byte(rng));
    r.coils = coin(rng) & 1;
    r.io = coin(rng) == 0 ? -1 : int32_t(rng() % (1UL << kIoPins));
    r.warning = coin(rng) == 0 ? uint8_t(1 + byte(rng) % 255) : 0;
    char buf[status_report_size(12)];
    const uint16_t n = format_status(buf, sizeof buf, r);
    ASSERT_GT(n, 0);
    StatusReport<12> back;
    std::memset(&back, 0x5a, sizeof back);
    ASSERT_TRUE(parse_status(back, buf, n)) << std::string(buf, n);
    ASSERT_EQ(back.state, r.state);
    ASSERT_EQ(back.num_joints, r.num_joints);
    for (int i = 0; i < r.num_joints; ++i) {
      ASSERT_EQ(back.steps[i], r.steps[i]);
      ASSERT_EQ(back.millideg[i], r.millideg[i]);
    }
    ASSERT_EQ(back.gripper, r.gripper);
    ASSERT_EQ(back.free_slots, r.free_slots);
    ASSERT_EQ(back.coils, r.coils);
    ASSERT_EQ(back.io, r.io);
    ASSERT_EQ(back.warning, r.warning);
    // The controller's line as the host reads it: without LF, or with CRLF.
    ASSERT_TRUE(parse_status(back, buf, uint16_t(n - 1)));
    const std::string crlf = std::string(buf, n - 1) + "\r\n";
    ASSERT_TRUE(parse_status(back, crlf.data(), uint16_t(crlf.size())));
    // Never mistaken for an ok / error reply.
    uint8_t code = 0;
    ASSERT_FALSE(parse_reply(code, buf, uint8_t(std::min<uint16_t>(n, 255))));
  }
}

TEST(Reports, StatusParseTolerantAndStrict) {
  StatusReport<3> r;
  // Field order is free and unknown fields are skipped.
  const std::string shuffled = "<Run|C:0|Q:3|X:whatever|A:1.5,2,-3|G:7|S:1,2,3|F:1,2>";
  ASSERT_TRUE(parse_status(r, shuffled.data(), uint16_t(shuffled.size())));
  EXPECT_EQ(r.state, kStateRun);
  EXPECT_EQ(r.num_joints, 3);
  EXPECT_EQ(r.millideg[0], 1500);
  EXPECT_EQ(r.millideg[1], 2000);
  EXPECT_EQ(r.steps[2], 3);
  EXPECT_EQ(r.gripper, 7);
  EXPECT_EQ(r.free_slots, 3);
  EXPECT_FALSE(r.coils);
  EXPECT_EQ(r.warning, 0);
  const std::string good = "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>";
  const std::string bad[] = {
      "",
      "<>",
      "<Idle>",                                                    // no fields
      "Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>",      // no '<'
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1",      // no '>'
      "<idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>",     // state words are exact
      "<Hold|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>",     // no such state
      "<Idle|S:0,32,-5|A:0.000,10.133|G:100|Q:15|C:1>",            // fewer angles than steps
      "<Idle|S:0,32,-5,1|A:0.000,10.133,-3.639,1|G:100|Q:15|C:1>", // more joints than 3
      "<Idle|S:0,32,-5|G:100|Q:15|C:1>",                           // no angles
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|Q:15|C:1>",           // no gripper
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|C:1>",          // no queue
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15>",         // no coils
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:101|Q:15|C:1>",
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:256|C:1>",
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:2>",
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1|W:0>",
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1|W:256>",
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1|C:1>", // twice
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1|>",    // empty field
      "<Idle|S:0,32,,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>",
      "<Idle|S:0,32,-5,|A:0.000,10.133,-3.639,|G:100|Q:15|C:1>",
      "<Idle|S:0,32,2147483648|A:0.000,10.133,-3.639|G:100|Q:15|C:1>",
      "<Idle|S:0,32,-5|A:0.000,10.133,nan|G:100|Q:15|C:1>",
      "<Idle|S:0,32,-5|A:0.000,10.133,-3.639|G:+1|Q:15|C:1>",
      "<Idle|S 0,32,-5|A:0.000,10.133,-3.639|G:100|Q:15|C:1>",
  };
  for (const std::string& s : bad) {
    StatusReport<3> out = example_status();
    out.gripper = 42;
    EXPECT_FALSE(parse_status(out, s.data(), uint16_t(s.size()))) << s;
    EXPECT_EQ(out.gripper, 42) << s;  // untouched
  }
  EXPECT_TRUE(parse_status(r, good.data(), uint16_t(good.size())));
}

TEST(Reports, Info) {
  InfoReport info = {{0, 1, 0}, kProtocolVersion, 3, "MK2 Plus", 40233, 0};
  char buf[kInfoReportSize];
  uint16_t n = format_info(buf, sizeof buf, info);
  EXPECT_EQ(std::string(buf, n), "[Articula|V:0.1.0|P:5|J:3|R:MK2 Plus|K:40233]\n");
  InfoReport back;
  ASSERT_TRUE(parse_info(back, buf, n));
  EXPECT_EQ(back.version[0], 0);
  EXPECT_EQ(back.version[1], 1);
  EXPECT_EQ(back.version[2], 0);
  EXPECT_EQ(back.protocol, 5);
  EXPECT_EQ(back.checksum, 40233);
  EXPECT_EQ(back.num_joints, 3);
  EXPECT_STREQ(back.name, "MK2 Plus");
  EXPECT_EQ(back.warning, 0);
  // The longest info line fills kInfoReportSize exactly.
  InfoReport big = {{255, 255, 255}, 255, 255, "", 65535, kSettingsReset};
  std::memset(big.name, '[', kMaxRobotName);
  big.name[kMaxRobotName] = '\0';
  big.warning = 255;
  n = format_info(buf, sizeof buf, big);
  ASSERT_EQ(n, kInfoReportSize - 1);
  EXPECT_EQ(buf[n], '\0');
  EXPECT_EQ(format_info(buf, uint16_t(kInfoReportSize - 2), big), 0);
  ASSERT_TRUE(parse_info(back, buf, n));
  EXPECT_EQ(std::string(back.name), std::string(kMaxRobotName, '['));
  EXPECT_EQ(back.warning, 255);
  // Names the line cannot carry.
  for (const char* name : {"a|b", "a]b", "tab\there", "\x7f"}) {
    InfoReport bad = info;
    std::strcpy(bad.name, name);
    EXPECT_EQ(format_info(buf, sizeof buf, bad), 0) << name;
  }
  InfoReport unterminated = info;
  std::memset(unterminated.name, 'x', sizeof unterminated.name);  // no NUL within the array
  EXPECT_EQ(format_info(buf, sizeof buf, unterminated), 0);
  // Reading: fields in any order, unknown ones skipped; V, P, J, R required.
  const std::string odd = "[Articula|R:arm 2|Z:9|J:6|P:3|W:14|V:1.22.333]";
  EXPECT_FALSE(parse_info(back, odd.data(), uint16_t(odd.size())));  // 333 is not a byte
  const std::string ok = "[Articula|R:arm 2|Z:9|J:6|P:3|W:14|V:1.22.33]\r\n";
  ASSERT_TRUE(parse_info(back, ok.data(), uint16_t(ok.size())));
  EXPECT_STREQ(back.name, "arm 2");
  EXPECT_EQ(back.num_joints, 6);
  EXPECT_EQ(back.protocol, 3);
  EXPECT_EQ(back.warning, kSettingsReset);
  EXPECT_EQ(back.version[2], 33);
  EXPECT_EQ(back.checksum, -1);  // a firmware before protocol 4 has no K
  const char* bad[] = {"[Articula|V:0.1.0|P:2|J:3]",          // no name
                       "[Articula|V:0.1|P:2|J:3|R:x]",        // two version parts
                       "[Articula|V:0.1.0.0|P:2|J:3|R:x]",    // four
                       "[Articula|V:0.-1.0|P:2|J:3|R:x]",     // a negative part
                       "[articula|V:0.1.0|P:2|J:3|R:x]",      // the tag is exact
                       "[Articula|V:0.1.0|P:2|J:3|R:x",       // no ']'
                       "<Articula|V:0.1.0|P:2|J:3|R:x>",      // a status bracket
                       "[Articula|V:0.1.0|P:2|P:2|J:3|R:x]",  // twice
                       "[Articula|V:0.1.0|P:2|J:3|R:x|K:65536]",              // not 16 bits
                       "[Articula|V:0.1.0|P:2|J:3|R:0123456789012345678901234]"};  // 25 characters
  for (const char* s : bad) {
    InfoReport out = info;
    EXPECT_FALSE(parse_info(out, s, uint16_t(std::strlen(s)))) << s;
    EXPECT_STREQ(out.name, "MK2 Plus") << s;
  }
  uint8_t code = 0;
  EXPECT_FALSE(parse_reply(code, buf, uint8_t(n)));
}

TEST(Reports, SettingLineIsTheCommandThatSetsIt) {
  EXPECT_EQ(setting_text(3, 200000), "$3=200.000\n");
  EXPECT_EQ(setting_text(12, -5), "$12=-0.005\n");
  EXPECT_EQ(setting_text(0, 0), "$0=0.000\n");
  char buf[kSettingLineSize + 4];
  std::memset(buf, '#', sizeof buf);
  const uint16_t n = format_setting(buf, kSettingLineSize, 999, -2147483647 - 1);  // the longest
  EXPECT_EQ(std::string(buf, n), "$999=-2147483.648\n");
  EXPECT_EQ(n, kSettingLineSize - 1);
  EXPECT_EQ(buf[n], '\0');
  EXPECT_EQ(format_setting(buf, 5, 999, 1), 0);
  EXPECT_EQ(format_setting(buf, sizeof buf, 1000, 1), 0);  // setting numbers have 3 digits
  // A listing sent back sets the same values.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> value(-1000000000, 1000000000);
  std::uniform_int_distribution<int> number(0, 999);
  for (int t = 0; t < 10000; ++t) {
    const int num = number(rng);
    const int32_t v = value(rng);
    const std::string line = setting_text(uint16_t(num), v);
    Command cmd;
    ASSERT_EQ(parse(cmd, line.substr(0, line.size() - 1)), kOk) << line;
    ASSERT_EQ(cmd.type, kCmdSetSetting);
    ASSERT_EQ(cmd.argc, 2);
    ASSERT_EQ(cmd.arg[0], num);
    ASSERT_EQ(cmd.arg[1], v);
  }
}

TEST(Reports, SinkFormIsTheBufferForm) {
  // What the firmware streams to its serial port is what format_* puts in a buffer.
  struct StringSink {
    std::string s;
    void put(char c) { s += c; }
  } sink;
  const StatusReport<3> r = example_status();
  ASSERT_TRUE(write_status(sink, r));
  EXPECT_EQ(sink.s, status_text_of(r));
  sink.s.clear();
  const InfoReport info = {{1, 2, 3}, kProtocolVersion, 3, "x", -1, 0};
  ASSERT_TRUE(write_info(sink, info));
  EXPECT_EQ(sink.s, "[Articula|V:1.2.3|P:5|J:3|R:x]\n");
  sink.s.clear();
  ASSERT_TRUE(write_setting(sink, 5, -1500));
  EXPECT_EQ(sink.s, "$5=-1.500\n");
  sink.s.clear();
  EXPECT_FALSE(write_setting(sink, 1000, 0));
  EXPECT_EQ(sink.s, "");
}

TEST(Reports, StatusIoField) {
  // I: the free pins' levels, a mask; absent (-1) from a firmware without I/O.
  StatusReport<3> r = example_status();
  r.io = 1L << 19;
  const std::string text = status_text_of(r);
  EXPECT_NE(text.find("|C:1|I:524288>"), std::string::npos) << text;
  StatusReport<3> back;
  ASSERT_TRUE(parse_status(back, text.data(), uint16_t(text.size())));
  EXPECT_EQ(back.io, 1L << 19);
  const std::string old = "<Idle|S:0,0,0|A:0,0,0|G:0|Q:15|C:0>";
  ASSERT_TRUE(parse_status(back, old.data(), uint16_t(old.size())));
  EXPECT_EQ(back.io, -1);
  for (const char* bad : {"<Idle|S:0|A:0|G:0|Q:15|C:0|I:1048576>", "<Idle|S:0|A:0|G:0|Q:15|C:0|I:-1>",
                          "<Idle|S:0|A:0|G:0|Q:15|C:0|I:1|I:1>"})
    EXPECT_FALSE(parse_status(back, bad, uint16_t(std::strlen(bad)))) << bad;
}
