// Tests shared/articula/protocol.h: number parsing into thousandths, the line grammar and its
// error codes, the byte-to-line assembler (CRLF, overlong lines, random noise) and the
// `ok` / `error:<code>` replies.
#include <articula/protocol.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace articula;

namespace articula {
// Readable failure messages (uint8_t enums would print as characters).
void PrintTo(Status s, std::ostream* os) { *os << int(s) << " (" << status_name(s) << ")"; }
void PrintTo(LineEvent e, std::ostream* os) { *os << int(e); }
void PrintTo(CommandType t, std::ostream* os) { *os << int(t); }
}  // namespace articula

namespace {

Status num(int32_t& out, const std::string& s) { return parse_thousandths(out, s.data(), uint8_t(s.size())); }

Status parse(Command& c, const std::string& s, uint8_t joints = 3) {
  return parse_line(c, s.data(), uint8_t(s.size()), joints);
}

Status parse(const std::string& s) {
  Command c;
  return parse(c, s);
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
    if (b == '\t' || b == ' ' || b == '#' || b == '\r')
      EXPECT_EQ(st, kOk) << b;  // separator, comment, or the CR before the LF
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
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> byte(0, 255), pick(0, 99);
  std::string soup;
  for (int i = 0; i < 100000; ++i) {
    const int p = pick(rng);
    soup += p < 2 ? '\n' : p < 4 ? '\r' : p < 50 ? char(byte(rng)) : char(' ' + pick(rng) % 95);
  }
  LineAssembler a;
  std::string current;
  int lfs = 0, ready = 0, too_long = 0, parsed_ok = 0;
  for (char c : soup) {
    const LineEvent e = a.feed(c);
    if (c != '\n') {
      ASSERT_EQ(e, kLineNone);
      current += c;
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
      Command cmd;
      const Status st = parse_line(cmd, a.line(), a.length(), 3);
      ASSERT_NE(st, kLineTooLong);
      parsed_ok += st == kOk;
      ++ready;
    }
    current.clear();
  }
  EXPECT_EQ(ready + too_long, lfs);
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
