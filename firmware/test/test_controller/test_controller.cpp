// Tests firmware/src/controller.cpp at the serial line: one reply per line, every error
// code the firmware can give (each rejected line leaving position, commanded angles and
// queue as they were), overlong lines, comments, the info line, and the realtime bytes:
// a status report mid-move (right steps, answered at once from the receive interrupt), in
// the middle of a command's work (before its reply, never inside a line, one report for a
// burst), during start-up, and a stop mid-move (queue emptied, the waiting line answered
// error:15, later moves fine).
#include <articula/actuation.h>
#include <articula/protocol.h>
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "queue.h"
#include "robot.h"

using namespace articula;

namespace {

const int kJ = robot::kJoints;

std::vector<int32_t> steps_of(const sim::Status& s) { return std::vector<int32_t>(s.steps, s.steps + kJ); }

// Positions the pins gave up to (and including) tick t.
std::vector<int64_t> pin_positions_at(uint64_t t) {
  std::vector<int64_t> p(kJ, 0);
  for (const sitl::CoilWrite& w : sitl::hw().coil_log)
    if (w.tick <= t && w.motor < kJ) p[w.motor] += w.step;
  return p;
}

// The angle of step 0 (where the arm is at power-up), millidegrees.
Millideg zero(int i) { return robot::motor(uint8_t(i)).zero; }

// The M line of the zero angles plus offsets, degrees.
std::string m_line(double d0, double d1, double d2) {
  const double d[3] = {d0, d1, d2};
  std::string s = "M";
  for (int i = 0; i < kJ; ++i) s += " " + std::to_string(zero(i) / 1000.0 + d[i]);
  return s;
}

}  // namespace

TEST(Controller, EveryLineOneReply) {
  sim::boot();
  EXPECT_EQ(sim::command("# only a comment"), "ok");
  EXPECT_EQ(sim::command("   "), "error:1");
  EXPECT_EQ(sim::command("I"), "ok");
  ASSERT_EQ(sim::reports().size(), 1u);
  InfoReport info;
  const std::string& l = sim::reports()[0];
  ASSERT_TRUE(parse_info(info, l.data(), uint16_t(l.size()))) << l;
  EXPECT_EQ(info.protocol, kProtocolVersion);
  EXPECT_EQ(info.num_joints, kJ);
  EXPECT_STREQ(info.name, robot::config().name);  // the robot file's (test_robot checks)
  EXPECT_EQ(info.checksum, robot::checksum());
  EXPECT_EQ(info.version[0], 0);
  EXPECT_EQ(info.version[1], 1);
  EXPECT_EQ(info.version[2], 0);
  EXPECT_EQ(info.warning, kSettingsReset);  // a blank EEPROM: said once
  EXPECT_EQ(sim::command("i"), "ok");
  ASSERT_TRUE(parse_info(info, sim::reports()[0].data(), uint16_t(sim::reports()[0].size())));
  EXPECT_EQ(info.warning, 0);
  EXPECT_EQ(sim::command("L 0 1\r"), "ok");  // CRLF
  EXPECT_EQ(sim::command("l 0 -1 # back"), "ok");
  sim::run_until_at_rest();
  EXPECT_TRUE(sim::take_lines().empty());  // nothing else was said
  EXPECT_EQ(sim::hal_errors(), "");
}

// Each error the firmware can answer with, and after each one the arm, its commanded
// angles and the queue are as they were: a long move is under way the whole time, so the
// queue holds moves, and the final relative move lands on the step the exact sum gives.
TEST(Controller, EveryErrorLeavesEverythingAsItWas) {
  sim::boot();
  ASSERT_EQ(sim::command("L 0 0.2"), "ok");  // commanded 0.2 deg: the test's witness
  ASSERT_TRUE(sim::run_until_at_rest());
  ASSERT_EQ(sim::command(m_line(40, 0, 0)), "ok");
  ASSERT_EQ(sim::command(m_line(-40, 0, 0)), "ok");
  ASSERT_EQ(sim::command(m_line(0.2, 0, 0)), "ok");  // back: base commanded 0.2 + zero
  const sim::Status before = sim::status();
  ASSERT_EQ(before.state, kStateRun);
  const std::string too_long(65, 'x');
  const struct {
    std::string line;
    std::string reply;
  } cases[] = {
      {"", "error:1"},
      {"X 1", "error:2"},
      {"G1", "error:2"},
      {"L 0 abc", "error:3"},
      {"L 0 1e3", "error:3"},
      {"$1=abc", "error:3"},
      {"L 0", "error:4"},
      {"M 0", "error:4"},
      {"$1=", "error:4"},
      {"L 0 1 2", "error:5"},
      {"H 1", "error:5"},
      {"L 9 1", "error:6"},
      {"L " + std::to_string(kJ) + " 1", "error:6"},
      {too_long, "error:7"},
      {"G 101", "error:8"},
      {"G -0.001", "error:8"},
      {"S 2", "error:8"},
      {"$0=0", "error:8"},
      {"$0=4001", "error:8"},
      {"$0=600.5", "error:8"},
      {"$2=-1", "error:8"},
      {"$3=" + std::to_string(1 << kJ), "error:8"},
      {"L 0 999999.9", "error:8"},  // the commanded angle would pass 1,000,000 degrees
      {"L 0 1000", "error:9"},
      {"L 0 -1000", "error:9"},
      {"M 1000 0 0", kJ == 3 ? "error:9" : "error:5"},
      {m_line(0, 0, 500), kJ == 3 ? "error:9" : "error:5"},
      {"P 1000 0 0", "error:10"},
      {"P 0 0 -500", "error:10"},
      {"L 0 1\x01", "error:11"},
      {"L 0 \xC3\xA9", "error:11"},
      {"$8=1", "error:13"},
      {"$99=1", "error:13"},
      {"$x=1", "error:13"},
  };
  for (const auto& c : cases) {
    EXPECT_EQ(sim::command(c.line), c.reply) << "line \"" << c.line << "\"";
    const sim::Status now = sim::status();
    EXPECT_EQ(now.free_slots, before.free_slots) << c.line;
  }
  ASSERT_TRUE(sim::run_until_at_rest());
  const sim::Status after = sim::status();
  // Zero + 0.2 deg is where the base was sent; the witness: 0.2 + 0.15 = 0.35 deg.
  ASSERT_EQ(sim::command("L 0 0.15"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const MotorSpec& base = robot::motor(0);
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(base, zero(0) + 350)) << "commanded angle changed";
  EXPECT_EQ(after.steps[0], quantize_within_limits(base, zero(0) + 200));
  for (int i = 1; i < kJ; ++i) EXPECT_EQ(after.steps[i], 0);
  EXPECT_EQ(sim::hal_errors(), "");
}

TEST(Controller, NotHomedWhileEndstopsAreFittedAndUnhomed) {
  sim::boot();
  ASSERT_EQ(sim::command("$3=1"), "ok");
  sim::boot(false);  // power-up with a switch fitted: position unknown
  EXPECT_EQ(sim::status().state, kStateAlarm);
  const sim::Status before = sim::status();
  for (const char* line : {"L 0 1", "M 0 90 0", "P 235 0 213"}) EXPECT_EQ(sim::command(line), "error:12") << line;
  EXPECT_EQ(sim::command("G 50"), "ok");  // the gripper knows where it is
  EXPECT_EQ(sim::command("I"), "ok");
  sim::run_until_at_rest();
  const sim::Status after = sim::status();
  EXPECT_EQ(steps_of(after), steps_of(before));
  EXPECT_EQ(after.state, kStateAlarm);
  EXPECT_EQ(sim::command("Z"), "ok");
  EXPECT_EQ(sim::status().state, kStateIdle);
  EXPECT_EQ(sim::command("L 0 1"), "ok");
}

// A line of 64 bytes is fine (with a CR too), 65 is too long; the realtime bytes do not
// count; the overlong line is read to its end, then answered once, and the next is fine.
TEST(Controller, OverlongLines) {
  sim::boot();
  std::string l64 = "L 0 1";
  l64 += std::string(64 - l64.size() - 1, ' ') + "#";
  ASSERT_EQ(l64.size(), 64u);
  EXPECT_EQ(sim::command(l64), "ok");
  EXPECT_EQ(sim::command(l64 + "\r"), "ok");
  EXPECT_EQ(sim::command(l64 + "x"), "error:7");
  EXPECT_EQ(sim::command(l64 + "?"), "ok");  // '?' is taken out: still 64 bytes
  EXPECT_EQ(sim::take_lines().size(), 0u);
  EXPECT_EQ(sim::reports().size(), 1u);  // the status report the '?' asked for
  EXPECT_EQ(sim::command(std::string(500, 'L')), "error:7");
  EXPECT_EQ(sim::command("L 0 -2"), "ok");  // three times +1 above, then -2
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(robot::motor(0), zero(0) + 1000));
}

// '?' in the middle of a move: answered at once (the receive interrupt builds the report),
// with the steps the pins had given by then and the state Run; a '?' in the middle of a line
// is taken out of it.
TEST(Controller, StatusMidMove) {
  sim::boot();
  ASSERT_EQ(sim::command(m_line(60, 0, 0)), "ok");
  ASSERT_TRUE(sim::run_until([] { return sitl::hw().position[0] != 0 && std::abs(sitl::hw().position[0]) > 40; },
                             10 * sim::kSecond));
  for (int k = 0; k < 5; ++k) {
    sim::take_lines();
    const uint64_t t = sitl::hw().now;
    sim::send("?");
    const std::vector<std::string> lines = sim::take_lines();  // before any main-loop pass
    ASSERT_EQ(lines.size(), 1u);
    sim::Status st;
    ASSERT_TRUE(parse_status(st, lines[0].data(), uint16_t(lines[0].size()))) << lines[0];
    EXPECT_EQ(st.state, kStateRun);
    EXPECT_TRUE(st.coils);
    EXPECT_EQ(st.free_slots, queue::kSize);
    const std::vector<int64_t> pins = pin_positions_at(t);
    for (int i = 0; i < kJ; ++i) {
      EXPECT_EQ(st.steps[i], pins[i]) << i;
      EXPECT_EQ(st.millideg[i], steps_to_millideg(robot::motor(uint8_t(i)), st.steps[i]));
    }
    sim::run_until([] { return false; }, 40 * sim::kPollTicks);
  }
  // Mid-line: the line still works.
  sim::send("L 0 1?");
  sim::tick();
  sim::send("0\n");
  ASSERT_TRUE(sim::run_until_at_rest());
  int reports = 0, oks = 0;
  for (const std::string& l : sim::take_lines()) {
    reports += l[0] == '<';
    oks += l == "ok";
  }
  EXPECT_EQ(reports, 1);
  EXPECT_EQ(oks, 1);
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(robot::motor(0), zero(0) + 70000));
}

namespace {

// Delivers `bytes` to the receive interrupt at the first HAL call the firmware makes with
// interrupts enabled once `when` holds (in the middle of its work on a line), once.
void deliver_when(const std::function<bool()>& when, const std::string& bytes) {
  auto done = std::make_shared<bool>(false);
  sitl::hw().interrupt_point = [when, bytes, done] {
    if (*done || !when()) return;
    *done = true;
    for (char c : bytes) sitl::receive(c);
  };
}

bool is_reply(const std::string& l) { return l == "ok" || l.rfind("error:", 0) == 0; }

}  // namespace

// A '?' that arrives while the main loop works on a line (P's inverse kinematics takes
// milliseconds on the Nano, M's set-up less) is answered at once, before that line's reply:
// the report shows the state before the line took effect (the move not queued yet).
TEST(Controller, StatusDuringACommandIsAnsweredBeforeItsReply) {
  sim::boot();
  sim::status();  // the W:14 of the blank EEPROM
  sim::take_lines();
  const std::vector<std::string> lines_sent = {"P 200 50 150", m_line(10, 5, -5), "P 235 0 213"};
  for (const std::string& l : lines_sent) {
    ASSERT_TRUE(sim::run_until_at_rest());
    sim::take_lines();
    const uint64_t built = sitl::hw().reports_built;
    // The '?' comes right after the line's LF has been read: the firmware is busy with it.
    deliver_when([] { return sitl::hw().last_read == '\n'; }, "?");
    sitl::hw().last_read = -1;
    sim::send(l + "\n");
    sim::tick();
    sitl::hw().interrupt_point = nullptr;
    const std::vector<std::string> lines = sim::take_lines();
    ASSERT_EQ(lines.size(), 2u) << l;
    EXPECT_EQ(sitl::hw().reports_built, built + 1);
    sim::Status st;
    ASSERT_TRUE(parse_status(st, lines[0].data(), uint16_t(lines[0].size()))) << lines[0];
    EXPECT_EQ(st.state, kStateIdle) << l;  // the move is not queued yet
    EXPECT_EQ(st.free_slots, queue::kSize) << l;
    EXPECT_EQ(lines[1], "ok") << l;
    // The next report shows the move.
    EXPECT_EQ(sim::status().state, kStateRun) << l;
  }
  EXPECT_EQ(sim::hal_errors(), "");
}

// A report never goes inside another line: a '?' that arrives while the firmware is writing
// a line (here after the first byte of a reply, of an info line, of a setting line) is sent
// right after that line's LF. Several '?' before it goes are answered by one report.
TEST(Controller, StatusNeverSplitsALineAndABurstIsAnsweredOnce) {
  sim::boot();
  sim::status();
  sim::take_lines();
  for (const char* line : {"L 0 1", "I", "$", "X"}) {
    const uint64_t w0 = sitl::hw().serial_writes;
    const uint64_t built = sitl::hw().reports_built;
    deliver_when([w0] { return sitl::hw().serial_writes == w0 + 1; }, "??");  // after the first byte
    const std::string reply = sim::command(line);
    sitl::hw().interrupt_point = nullptr;
    EXPECT_TRUE(is_reply(reply)) << line;
    EXPECT_EQ(sitl::hw().reports_built, built + 1) << line;  // one report for both
    // The output, line by line: the report whole, after the first line.
    std::vector<std::string> lines = sim::reports();
    lines.push_back(reply);
    for (const std::string& l : sim::take_lines()) lines.push_back(l);
    size_t at = lines.size();
    for (size_t i = 0; i < lines.size(); ++i)
      if (lines[i][0] == '<') at = i;
    ASSERT_EQ(at, 1u) << line << ": the report is not right after the line it waited for";
    sim::Status st;
    EXPECT_TRUE(parse_status(st, lines[at].data(), uint16_t(lines[at].size()))) << lines[at];
    for (size_t i = 0; i < lines.size(); ++i) {
      if (i == at) continue;
      EXPECT_EQ(lines[i].find_first_of("<>"), std::string::npos) << lines[i];
    }
    ASSERT_TRUE(sim::run_until_at_rest());
    sim::take_lines();
  }
  EXPECT_EQ(sim::hal_errors(), "");
}

// '?' and '!' that arrive while the firmware sets itself up (the receiver is on from
// hal::init()) are acted on once it is up: one report, and the stop (the arm is at rest, so
// it only makes the commanded angles those of the steps). A line that came meanwhile is read
// too.
TEST(Controller, RealtimeBytesDuringStartUpAreKept) {
  sim::boot(true, "?!I\n");
  std::vector<std::string> lines = sim::take_lines();
  ASSERT_EQ(lines.size(), 1u);  // the report, at once
  sim::Status st;
  ASSERT_TRUE(parse_status(st, lines[0].data(), uint16_t(lines[0].size()))) << lines[0];
  EXPECT_EQ(st.state, kStateStop);  // the '!' was taken too
  EXPECT_EQ(st.warning, kSettingsReset);
  ASSERT_TRUE(sim::run_until([] { return !sim::take_lines().empty(); }, sim::kSecond));  // then I
  EXPECT_EQ(sim::status().state, kStateIdle);
  EXPECT_EQ(sim::command("L 0 1"), "ok");
  EXPECT_EQ(sim::hal_errors(), "");
}

// '!' in the middle of a move with a full queue and a line waiting for room: the waiting
// line gets error:15, so does the complete line behind it, the queue is emptied, the arm
// decelerates (state Stop) to rest; the commanded angles become those of the steps reached;
// the next lines work from there.
TEST(Controller, StopMidMove) {
  sim::boot();
  std::string burst;
  for (int k = 0; k < int(queue::kSize) + 3; ++k) burst += k % 2 ? "L 0 -30\n" : "L 0 30\n";
  sim::send(burst);
  // The first move starts, eight more fill the queue, one waits, one more is read.
  ASSERT_TRUE(sim::run_until([] { return std::abs(sitl::hw().position[0]) > 30; }, 10 * sim::kSecond));
  std::vector<std::string> lines = sim::take_lines();
  EXPECT_EQ(lines.size(), queue::kSize + 1u);
  for (const std::string& l : lines) EXPECT_EQ(l, "ok");
  EXPECT_EQ(sim::status().free_slots, 0);
  sim::send("!");
  sim::tick();
  lines = sim::take_lines();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "error:15");
  EXPECT_EQ(lines[1], "error:15");
  sim::Status st = sim::status();
  EXPECT_EQ(st.state, kStateStop);
  EXPECT_EQ(st.free_slots, queue::kSize);
  // Lines sent now wait for rest.
  sim::send("I\n");
  sim::tick();
  EXPECT_TRUE(sim::take_lines().empty());
  ASSERT_TRUE(sim::run_until([] { return !sim::take_lines().empty(); }, 10 * sim::kSecond));
  st = sim::status();
  EXPECT_EQ(st.state, kStateIdle);
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(st.steps[i], sitl::hw().position[i]);
  EXPECT_NE(st.steps[0], 0);
  // The commanded angle is now the reached step's angle (the A field): 0.5 degrees off it
  // is the step this move goes to (not where the discarded moves would have left it).
  const MotorSpec& base = robot::motor(0);
  const Millideg a_field = st.millideg[0];
  EXPECT_EQ(a_field, steps_to_millideg(base, st.steps[0]));
  ASSERT_EQ(sim::command("L 0 -0.5"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  st = sim::status();
  EXPECT_EQ(st.steps[0], quantize_within_limits(base, a_field - 500)) << "the commanded angle was not re-derived";
  EXPECT_EQ(sim::command(m_line(0, 0, 0)), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  st = sim::status();
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(st.steps[i], 0);
  for (int i = 0; i < kJ; ++i) EXPECT_EQ(sitl::hw().position[i], st.steps[i]);
  EXPECT_EQ(sim::hal_errors(), "");
}

// '!' at rest: nothing moves, the next status says Idle, lines still work.
TEST(Controller, StopAtRest) {
  sim::boot();
  sim::send("!");
  sim::tick();
  EXPECT_TRUE(sim::take_lines().empty());
  EXPECT_EQ(sim::status().state, kStateIdle);
  EXPECT_EQ(sim::command("L 0 1"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(robot::motor(0), zero(0) + 1000));
}

namespace {

// The ticks between the last step of `L 0 10` and the first of `L 0 -10`, with `between`
// sent between them.
uint64_t gap_around(const std::string& between) {
  sim::boot();
  EXPECT_EQ(sim::command("L 0 10"), "ok");
  if (!between.empty()) {
    EXPECT_EQ(sim::command(between), "ok");
  }
  EXPECT_EQ(sim::command("L 0 -10"), "ok");
  EXPECT_TRUE(sim::run_until_at_rest());
  const std::vector<sim::Step> steps = sim::steps_of(0);
  size_t i = 0;
  while (i + 1 < steps.size() && steps[i + 1].dir == steps[0].dir) ++i;
  EXPECT_LT(i + 1, steps.size());
  return i + 1 < steps.size() ? steps[i + 1].tick - steps[i].tick : 0;
}

}  // namespace

// D waits in the queue: the next move starts exactly that long later, and the status says
// Run meanwhile; a wait out of range is refused and changes nothing.
TEST(Controller, DwellWaitsInTheQueue) {
  const uint64_t plain = gap_around("");
  EXPECT_EQ(gap_around("D 1.5"), plain + 3 * sim::kSecond / 2);
  EXPECT_EQ(gap_around("D 0"), plain);
  sim::boot();
  ASSERT_EQ(sim::command("D 2"), "ok");
  sim::run_until([] { return false; }, sim::kSecond);
  sim::take_lines();
  sim::send("?");
  const std::vector<std::string> lines = sim::take_lines();
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("<Run|", 0), 0u) << lines[0];
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::command("D 600.001"), "error:8");
  EXPECT_EQ(sim::command("D -1"), "error:8");
  EXPECT_EQ(sim::command("D"), "error:4");
  EXPECT_TRUE(sim::at_rest());
}

// O and W (protocol 5): an output set in queue order, after the move before it; a wait that
// ends within a millisecond of its input's change and holds the move behind it until then; one
// that runs out drops what follows and says W:21; pins the drive keeps refused.
TEST(Controller, DigitalIoInQueueOrder) {
  sim::boot();
  sim::status();  // (the blank EEPROM's W:14)
  const uint32_t kept = robot::kept_pins();
  int pin = -1;
  for (int p = 0; p < kIoPins && pin < 0; ++p)
    if (!(kept & (1UL << p))) pin = p;
  EXPECT_EQ(sim::command("O 1 1"), "error:20");  // D1: the serial line's TX
  EXPECT_EQ(sim::command("W 20 1 1"), "error:20");
  ASSERT_GE(pin, 0) << "every build leaves pins to O and W";
  if (robot::servos()) {  // a servo arm's: its joints' signal pins (its configuration's) and the gripper's D3
    const std::string servo = std::to_string(int(robot::config().servo_pin[0]));
    EXPECT_EQ(sim::command("O " + servo + " 1"), "error:20");
    EXPECT_EQ(sim::command("W " + servo + " 1 1"), "error:20");
    EXPECT_EQ(sim::command("O 3 1"), "error:20");
    EXPECT_TRUE(sim::at_rest());
  }
  const uint32_t bit = uint32_t(1) << pin;
  const std::string p = std::to_string(pin);
  sitl::Hardware& hw = sitl::hw();
  // At power-up a free pin is an input with its pull-up: I shows it high.
  EXPECT_EQ(uint32_t(sim::status().io), ~kept & ((1UL << kIoPins) - 1));

  // W holds the move behind it until the input reads 0: something outside pulls it low 1 s in.
  ASSERT_EQ(sim::command("W " + p + " 0 5"), "ok");
  ASSERT_EQ(sim::command("L 0 10"), "ok");
  sim::run_until([] { return false; }, sim::kSecond);  // (a second of the wait)
  EXPECT_EQ(sim::status().state, kStateRun);
  EXPECT_TRUE(sim::steps_of(0).empty());
  const uint64_t low_at = hw.now;
  hw.io_driven |= bit;
  hw.io_external &= ~bit;
  ASSERT_TRUE(sim::run_until_at_rest());
  const std::vector<sim::Step> moved = sim::steps_of(0);
  ASSERT_FALSE(moved.empty());
  uint64_t began = 0;
  for (const sitl::ActionEvent& e : hw.actions)
    if (e.kind == queue::kMove) began = e.tick;
  EXPECT_GE(began, low_at);
  EXPECT_LE(began, low_at + sim::kSecond / 1000 + sim::kPollTicks);  // a look a millisecond
  hw.io_driven &= ~bit;

  // O after a move: the pin changes when the move's last step is made, not before.
  ASSERT_EQ(sim::command("L 0 -10"), "ok");
  ASSERT_EQ(sim::command("O " + p + " 0"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  ASSERT_FALSE(hw.io_log.empty());
  EXPECT_EQ(hw.io_log.back().pin, pin);
  EXPECT_FALSE(hw.io_log.back().high);
  const uint64_t last_step = sim::steps_of(0).back().tick;
  EXPECT_GE(hw.io_log.back().tick, last_step);
  EXPECT_LE(hw.io_log.back().tick, last_step + sim::kSecond / 100);
  EXPECT_EQ(uint32_t(sim::status().io) & bit, 0u);

  // A wait that runs out: the move behind it is dropped, the next report says W:21, at rest.
  const int32_t before = hw.position[0];
  ASSERT_EQ(sim::command("W " + p + " 1 0.25"), "ok");  // (an output reads its own level: 0)
  ASSERT_EQ(sim::command("L 0 10"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const sim::Status s = sim::status();
  EXPECT_EQ(s.warning, kInputTimeout);
  EXPECT_EQ(s.state, kStateIdle);
  EXPECT_EQ(hw.position[0], before);
  EXPECT_EQ(sim::status().warning, 0);  // said once
  // and the plan goes on from where the arm stands
  ASSERT_EQ(sim::command("L 0 10"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_NE(hw.position[0], before);

  // '!' ends a wait at once.
  ASSERT_EQ(sim::command("W " + p + " 1 600"), "ok");
  sim::run_until([] { return false; }, sim::kSecond / 10);
  sim::send("!");
  ASSERT_TRUE(sim::run_until_at_rest(sim::kSecond / 10));
  EXPECT_EQ(sim::hal_errors(), "");
}

// The example session of docs/protocol.md, line by line, on the MK2 (each '?' after the
// moves before it have ended, as a person typing would see it).
TEST(Controller, ExampleSessionOfTheProtocolDocument) {
  sim::boot();
  if (std::string(robot::config().name) != "MK2 Plus") GTEST_SKIP() << "the example is the MK2's";
  std::ifstream doc(std::string(ARTICULA_SOURCE_DIR) + "/docs/protocol.md");
  ASSERT_TRUE(doc.good());
  std::string line;
  while (std::getline(doc, line) && line != "## Example session") {
  }
  std::vector<std::pair<std::string, std::vector<std::string>>> session;  // sent, expected
  while (std::getline(doc, line) && line.rfind("## ", 0) != 0) {
    if (line.rfind("    > ", 0) == 0) session.push_back({line.substr(6), {}});
    if (line.rfind("    < ", 0) == 0 && !session.empty()) session.back().second.push_back(line.substr(6));
  }
  ASSERT_GT(session.size(), 15u);
  sim::boot();
  sim::status();  // takes the W:14 of the blank EEPROM
  sim::take_lines();
  for (const auto& step : session) {
    std::vector<std::string> got;
    if (step.first == "?") {
      ASSERT_TRUE(sim::run_until_at_rest());
      sim::take_lines();
      sim::send("?");
      got = sim::take_lines();
    } else {
      got.push_back(sim::command(step.first));
      got.insert(got.begin(), sim::reports().begin(), sim::reports().end());
    }
    EXPECT_EQ(got, step.second) << "> " << step.first;
  }
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::hal_errors(), "");
}

// The serial line at the Nano's real rate (firmware/sitl/machine.h): one frame of 10 bits at
// 117,647 baud, 170 ticks, a byte; a line sent while another is on the wire follows it; the
// firmware sees a line, answers it and moves only once its LF is in.
TEST(SerialLine, ALineActsOnlyOnceItsLastFrameIsIn) {
  sim::boot();
  sim::status();  // takes the W:14 of the blank EEPROM
  sim::take_lines();
  const uint64_t t0 = sitl::hw().now + 100;
  const uint64_t lf = sim::send_at(t0, "L 0 10\n");
  EXPECT_EQ(lf, t0 + 7 * 170);
  const uint64_t lf2 = sim::send_at(t0, "L 0 -10\n");  // on the wire after the first line
  EXPECT_EQ(lf2, lf + 8 * 170);
  EXPECT_EQ(sim::on_the_line(), 15u);
  std::vector<std::string> seen;
  while (sitl::hw().now + sim::kPollTicks <= lf) {  // every pass before the LF is in
    sim::tick();
    for (const std::string& l : sim::take_lines()) seen.push_back(l + " @" + std::to_string(sitl::hw().now));
  }
  EXPECT_TRUE(seen.empty()) << seen[0];
  EXPECT_TRUE(sim::steps_of(0).empty());
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::take_lines(), (std::vector<std::string>{"ok", "ok"}));
  const std::vector<sim::Step> steps = sim::steps_of(0);
  ASSERT_FALSE(steps.empty());
  EXPECT_GT(steps.front().tick, lf);  // the first step after the LF arrived, not before
  int net = 0;
  for (const sim::Step& st : steps) net += st.dir;
  EXPECT_EQ(net, 0);  // there and back: the second line ran too
  EXPECT_EQ(sim::on_the_line(), 0u);
  EXPECT_EQ(sim::hal_errors(), "");
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
