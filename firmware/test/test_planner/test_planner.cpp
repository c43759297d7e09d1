// Tests the look-ahead planner in the firmware (articula/planner.h run by controller.cpp and
// stepper.cpp), through the serial protocol and the pins: a stream of collinear moves runs
// without a stop and about as fast as the same turn in one move; a corner slows to its
// junction level and not to rest; $6=0 gives every move from rest to rest, tick for tick;
// a D sent while the queue is full waits for room and is answered ok; '!' at speed near
// the end of a short move goes on decelerating into the next one.
#include <articula/motion.h>
#include <articula/planner.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "queue.h"
#include "robot.h"

using namespace articula;

namespace {

const int kJ = robot::kJoints;

std::string m_line(double a0, double a1, double a2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "M %.3f %.3f %.3f", a0, a1, a2);
  return buf;
}

std::vector<uint64_t> ticks_of(int motor, uint64_t from_tick) {
  std::vector<uint64_t> out;
  for (const sim::Step& s : sim::steps_of(motor, from_tick)) out.push_back(s.tick);
  return out;
}

// Every line at once, as a file piped into the port: the firmware reads them as it takes
// them. Returns the replies in order.
std::vector<std::string> stream(const std::vector<std::string>& lines, uint64_t max_ticks = 120 * sim::kSecond) {
  std::string all;
  for (const std::string& l : lines) all += l + "\n";
  sim::take_lines();
  sim::send(all);
  std::vector<std::string> replies;
  sim::run_until(
      [&] {
        for (const std::string& l : sim::take_lines())
          if (l == "ok" || l.rfind("error:", 0) == 0) replies.push_back(l);
        return replies.size() == lines.size() && sim::at_rest();
      },
      max_ticks);
  return replies;
}

// The base (motor 0) turned by `total` degrees in `parts` equal M lines, from the home pose.
std::vector<std::string> base_turn(double total, int parts) {
  const double s = robot::config().home[1] / 1000.0, e = robot::config().home[2] / 1000.0;
  const double b0 = robot::config().home[0] / 1000.0;
  std::vector<std::string> lines;
  for (int k = 1; k <= parts; ++k) lines.push_back(m_line(b0 + total * k / parts, s, e));
  return lines;
}

}  // namespace

TEST(Planner, CollinearMovesRunAsOneWithoutAStop) {
  sim::boot();
  const uint64_t t_one = sitl::hw().now;
  ASSERT_EQ(sim::command(base_turn(60, 1)[0]), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const std::vector<uint64_t> one = ticks_of(0, t_one);
  ASSERT_GT(one.size(), 100u);

  sim::boot();
  const uint64_t t_split = sitl::hw().now;
  const std::vector<std::string> replies = stream(base_turn(60, 20));
  ASSERT_EQ(replies, std::vector<std::string>(20, "ok"));
  const std::vector<uint64_t> split = ticks_of(0, t_split);
  ASSERT_EQ(split.size(), one.size());
  // The same steps; the time from the first step to the last within 3 % of one move's.
  const double ratio = double(split.back() - split.front()) / double(one.back() - one.front());
  std::printf("60 deg base turn: one move %.1f ms, 20 moves %.1f ms, ratio %.4f\n",
              (one.back() - one.front()) / 2000.0, (split.back() - split.front()) / 2000.0, ratio);
  EXPECT_LE(ratio, 1.03);
  // No stop: after the climb no interval is longer than the one before it by more than the
  // profile's own step (a stop at a junction is the 31.6 ms first step from rest again).
  const uint64_t c0 = split[0] - t_split;
  for (size_t k = 2; k + 100 < split.size(); ++k) {  // the last 100: the final stop (90 steps)
    const uint64_t dt = split[k] - split[k - 1];
    EXPECT_LT(dt, c0 / 2) << "step " << k << " waited " << dt << " ticks";
    if (k + 10 < split.size() / 2) {
      EXPECT_LE(dt, split[k - 1] - split[k - 2]) << "step " << k << " slowed while climbing";
    }
  }
}

TEST(Planner, JunctionSettingZeroIsRestToRestTickForTick) {
  sim::boot();
  ASSERT_EQ(sim::command("$6=0"), "ok");
  const MotionSettings s = sim::motion_settings();
  const uint64_t t0 = sitl::hw().now;
  int32_t from = sim::status().steps[0];
  const std::vector<std::string> lines = base_turn(30, 5);
  ASSERT_EQ(stream(lines), std::vector<std::string>(5, "ok"));
  // Each move of the base its own rest-to-rest profile, back to back.
  std::vector<uint64_t> expected;
  uint64_t t = t0;
  for (const std::string& l : lines) {
    double b = 0;
    std::sscanf(l.c_str(), "M %lf", &b);
    const int32_t to = quantize_within_limits(robot::motor(0), Millideg(b * 1000 + (b < 0 ? -0.5 : 0.5)));
    StepProfile p;
    p.start(uint32_t(std::abs(to - from)), s);
    while (!p.done()) expected.push_back(t += p.next_interval());
    from = to;
  }
  // The first move starts a poll after the line arrived: compare the intervals.
  const std::vector<uint64_t> got = ticks_of(0, t0);
  ASSERT_EQ(got.size(), expected.size());
  for (size_t k = 1; k < got.size(); ++k)
    EXPECT_EQ(got[k] - got[k - 1], expected[k] - expected[k - 1]) << "step " << k;
}

TEST(Planner, ACornerSlowsToItsJunctionLevelNotToRest) {
  sim::boot();
  const double b0 = robot::config().home[0] / 1000.0, s0 = robot::config().home[1] / 1000.0,
               e0 = robot::config().home[2] / 1000.0;
  // 20 degrees of base, then the base and the shoulder together: a 45-degree turn in steps.
  const std::vector<std::string> lines = {m_line(b0 + 20, s0, e0), m_line(b0 + 40, s0 + 10, e0)};
  const uint64_t t0 = sitl::hw().now;
  ASSERT_EQ(stream(lines), std::vector<std::string>(2, "ok"));
  const std::vector<uint64_t> base = ticks_of(0, t0);
  ASSERT_GT(base.size(), 60u);
  // The base's longest interval after its first step: a stop would repeat the first.
  uint64_t longest = 0;
  for (size_t k = 1; k + 40 < base.size(); ++k) longest = std::max(longest, base[k] - base[k - 1]);
  EXPECT_LT(longest, (base[0] - t0) / 2);  // (the last 40 steps: the final stop)
}

TEST(Planner, ADwellSentWhileTheQueueIsFullWaitsForRoomAndIsAnsweredOk) {
  sim::boot();
  std::vector<std::string> lines = base_turn(34, queue::kSize + 3);
  lines.push_back("D 0.2");
  lines.push_back(m_line(0, robot::config().home[1] / 1000.0, robot::config().home[2] / 1000.0));
  const std::vector<std::string> replies = stream(lines);
  EXPECT_EQ(replies, std::vector<std::string>(lines.size(), "ok"));
  // The wait happened: the last move's first step comes at least 0.2 s after the one before.
  const std::vector<uint64_t> base = ticks_of(0, 0);
  uint64_t longest = 0;
  for (size_t k = 1; k < base.size(); ++k) longest = std::max(longest, base[k] - base[k - 1]);
  EXPECT_GE(longest, 2 * sim::kSecond / 10);
}

TEST(Planner, StopAtSpeedGoesOnAlongThePathIntoTheNextMove) {
  sim::boot();
  // As many lines as the firmware reads before it is at rest again: the one under way, 16
  // queued, one held unanswered and one read behind it (later ones would run after the stop).
  const std::vector<std::string> lines = base_turn(57, queue::kSize + 3);
  const size_t ticks_per_turn = size_t(quantize_within_limits(robot::motor(0), robot::config().home[0] + 57000) -
                                       sim::status().steps[0]);
  std::string all;
  for (const std::string& l : lines) all += l + "\n";
  const uint64_t t0 = sitl::hw().now;
  sim::send(all);
  ASSERT_TRUE(sim::run_until([&] { return ticks_of(0, t0).size() >= 60; }, 60 * sim::kSecond));
  sim::send("!");
  ASSERT_TRUE(sim::run_until_at_rest());
  const std::vector<uint64_t> base = ticks_of(0, t0);
  // It decelerated: the intervals after the stop grow, and none is a jump to rest (it takes
  // more steps than a move of 3 degrees has: the stop ran on into the queued moves).
  size_t k = 60;
  while (k + 1 < base.size() && base[k + 1] - base[k] <= base[k] - base[k - 1]) ++k;
  const size_t decel = base.size() - k;
  EXPECT_GT(decel, 12u) << "stopped within a few steps: not along the path";
  for (size_t j = k + 1; j < base.size(); ++j)
    EXPECT_GE(base[j] - base[j - 1], base[j - 1] - base[j - 2]) << "step " << j;
  EXPECT_LT(base.size(), ticks_per_turn);  // short of the whole turn
  EXPECT_EQ(sim::status().state, kStateIdle);
  EXPECT_EQ(sim::hal_errors(), "");
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
