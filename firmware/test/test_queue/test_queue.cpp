// Tests firmware/src/queue.cpp and the flow control around it: moves are answered `ok`
// when queued, the status report counts the free places, a full queue delays the reply
// (never an error) while the firmware reads on to the end of one more line and no further,
// realtime bytes still work meanwhile, and Z and $n=v wait for the queue to empty.
#include <articula/actuation.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "queue.h"
#include "robot.h"

using namespace articula;

namespace {

const int kJ = robot::kJoints;

int count(const std::vector<std::string>& lines, const std::string& what) {
  int n = 0;
  for (const std::string& l : lines) n += l == what;
  return n;
}

}  // namespace

TEST(Queue, RingBasics) {
  sim::boot();
  EXPECT_TRUE(queue::empty());
  EXPECT_EQ(queue::free_slots(), queue::kSize);
  queue::Action a{};
  for (int k = 0; k < int(queue::kSize); ++k) {
    a.kind = queue::kMove;
    for (int i = 0; i < kJ; ++i) a.target[i] = k * 10 + i;
    queue::push(a);
    EXPECT_EQ(queue::count(), k + 1);
  }
  EXPECT_TRUE(queue::full());
  // Around the ring twice: first in, first out.
  for (int k = 0; k < 2 * int(queue::kSize); ++k) {
    EXPECT_EQ(queue::front().target[0], k * 10) << k;
    queue::pop();
    a.target[0] = (k + int(queue::kSize)) * 10;
    queue::push(a);
  }
  queue::clear();
  EXPECT_TRUE(queue::empty());
  EXPECT_EQ(sitl::hw().interrupts_off_depth, 0);
}

// Eleven moves sent at once: the first starts, eight fill the queue (each answered ok at
// once), the tenth waits unanswered, the eleventh is read to its end and no further byte is
// read; each time a move ends, one more reply comes.
TEST(Queue, FullQueueDelaysTheReply) {
  sim::boot();
  std::string burst;
  const int n = int(queue::kSize) + 3;
  for (int k = 0; k < n; ++k) burst += k % 2 ? "L 0 -20\n" : "L 0 20\n";
  burst += "I\n";  // behind them all
  sim::send(burst);
  ASSERT_TRUE(sim::run_until([] { return sitl::hw().position[0] != 0; }, 10 * sim::kSecond));
  sim::run_until([] { return false; }, 100 * sim::kPollTicks);
  std::vector<std::string> lines = sim::take_lines();
  EXPECT_EQ(count(lines, "ok"), int(queue::kSize) + 1);
  EXPECT_EQ(lines.size(), queue::kSize + 1u);
  // Read: the nine queued lines, the waiting one and the one behind it; the rest not.
  EXPECT_EQ(sitl::hw().rx.size(), std::string("I\n").size());
  // Realtime bytes still work: a status report at once, the queue full.
  const sim::Status st = sim::status();
  EXPECT_EQ(st.free_slots, 0);
  EXPECT_EQ(st.state, kStateRun);
  // The first move ends: the waiting line is queued and answered by the next pass, and
  // the held one becomes the waiting one.
  ASSERT_TRUE(sim::run_until([] { return !sim::take_lines().empty(); }, 20 * sim::kSecond));
  const uint64_t replied = sitl::hw().now;
  const std::vector<sim::Step> steps = sim::steps_of(0);
  size_t turn = 1;
  while (turn < steps.size() && steps[turn].dir == steps[0].dir) ++turn;
  const uint64_t first_end = steps[turn - 1].tick;  // the first move's last step
  EXPECT_GT(replied, first_end);
  EXPECT_LE(replied, first_end + 2 * sim::kPollTicks);
  EXPECT_EQ(turn, size_t(quantize_within_limits(robot::motor(0), robot::motor(0).zero + 20000)));
  EXPECT_EQ(sim::status().free_slots, 0);
  EXPECT_EQ(sitl::hw().rx.size(), 0u);  // the I line is read now, behind the waiting move
  // Everything runs to its end; every line is answered once, in order.
  ASSERT_TRUE(sim::run_until_at_rest());
  lines = sim::take_lines();
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "ok");
  EXPECT_EQ(lines[1].substr(0, 9), "[Articula");
  EXPECT_EQ(lines[2], "ok");
  // n moves of +-20: back where it began, every move made.
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(robot::motor(0), robot::motor(0).zero + 20000));
  EXPECT_EQ(sim::status().free_slots, queue::kSize);
}

// A bad line behind a full queue is answered at once, before the good one waiting.
TEST(Queue, BadLinesAreAnsweredAtOnceWithoutTouchingTheQueue) {
  sim::boot();
  for (int k = 0; k < int(queue::kSize) + 1; ++k) ASSERT_EQ(sim::command(k % 2 ? "L 0 -10" : "L 0 10"), "ok");
  EXPECT_EQ(sim::status().free_slots, 0);
  EXPECT_EQ(sim::command("L 0 1000"), "error:9");
  EXPECT_EQ(sim::command("X"), "error:2");
  EXPECT_EQ(sim::command("$0=0"), "error:8");
  EXPECT_EQ(sim::command("I"), "ok");  // reports need no room
  EXPECT_EQ(sim::command("$"), "ok");
  EXPECT_EQ(sim::status().free_slots, 0);
  // A good one waits for room.
  sim::send("G 10\n");
  sim::run_until([] { return false; }, 20 * sim::kPollTicks);
  EXPECT_TRUE(sim::take_lines().empty());
  ASSERT_TRUE(sim::run_until([] { return !sim::take_lines().empty(); }, 10 * sim::kSecond));
  ASSERT_TRUE(sim::run_until_at_rest());
  EXPECT_EQ(sim::status().gripper, 10);
  EXPECT_EQ(sim::status().steps[0], quantize_within_limits(robot::motor(0), robot::motor(0).zero + 10000));
}

// Z and $n=v wait until the queue is empty and the arm at rest, then act.
TEST(Queue, ZeroAndSettingsWaitForRest) {
  sim::boot();
  for (const char* wait : {"Z", "$5=100"}) {
    ASSERT_EQ(sim::command("L 0 30"), "ok");
    ASSERT_EQ(sim::command("L 0 -20"), "ok");
    sim::send(std::string(wait) + "\n");
    std::string reply;
    ASSERT_TRUE(sim::run_until(
        [&] {
          const std::vector<std::string> l = sim::take_lines();
          if (!l.empty()) reply = l[0];
          return !l.empty();
        },
        20 * sim::kSecond));
    EXPECT_EQ(reply, "ok");
    EXPECT_TRUE(sim::at_rest()) << wait;
    const uint64_t last = sim::steps_of(0).back().tick;
    EXPECT_LE(last, sitl::hw().now) << wait;
    if (wait[0] == 'Z') {  // the position is now the home pose
      const sim::Status st = sim::status();
      for (int i = 0; i < kJ; ++i) EXPECT_EQ(st.steps[i], robot::home_steps()[i]);
    }
  }
  EXPECT_EQ(sim::command("$"), "ok");
  bool found = false;
  for (const std::string& l : sim::reports()) found = found || l == "$5=100.000";
  EXPECT_TRUE(found);
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
