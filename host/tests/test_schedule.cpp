// Tests the prediction's times (host/lib/predict_run.cpp: the firmware's) and articula/planner.h
// on the host: a streamed program's moves blend as the firmware's planner blends them; the rest
// sender and $6=0 give motion.h's rest-to-rest timing; a corner passes at its junction level; the queue's depth
// limits the look-ahead.
#include <gtest/gtest.h>

#include <articula/motion.h>
#include <articula/planner.h>

#include <string>

#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "test_robots.h"

using namespace articula;
using namespace articula::host;

namespace {

Prediction run(const std::string& text, SenderModel::Kind kind, const std::string& settings = "") {
  ControllerSettings s;
  if (!settings.empty()) apply_settings_text(s, settings, 3);
  SenderModel sender;
  sender.kind = kind;
  return predict_program(mk2(), parse_program(text, "t.arm", mk2()), s, sender);
}

std::string base_turn(double total, int parts) {
  std::string text;
  for (int k = 1; k <= parts; ++k) text += "M " + std::to_string(total * k / parts) + " 90 0\n";
  return text;
}

}  // namespace

TEST(Schedule, CollinearStreamTakesAsLongAsOneMove) {
  const Prediction one = run(base_turn(60, 1), SenderModel::kStream);
  const Prediction split = run(base_turn(60, 20), SenderModel::kStream);
  const Prediction rest = run(base_turn(60, 20), SenderModel::kRest);
  ASSERT_EQ(split.rejected, 0);
  EXPECT_EQ(split.records.back().steps, one.records.back().steps);
  const double ratio = double(split.total_ticks) / double(one.total_ticks);
  std::printf("60 deg base turn, stream: one move %.1f ms, 20 moves %.1f ms (%.4fx); rest to rest %.1f ms (%.2fx)\n",
              one.total_s() * 1e3, split.total_s() * 1e3, ratio, rest.total_s() * 1e3,
              double(rest.total_ticks) / double(one.total_ticks));
  EXPECT_LE(ratio, 1.03);
  EXPECT_GT(double(rest.total_ticks) / double(one.total_ticks), 3.0);
  // Back to back, in order.
  for (size_t k = 1; k < split.records.size(); ++k)
    EXPECT_EQ(split.records[k].start_tick, split.records[k - 1].end_tick) << k;
}

TEST(Schedule, JunctionZeroAndTheRestSenderAreRestToRest) {
  const std::string text = base_turn(30, 5) + "G 50\nM 10 80 -10\nD 0.25\nM 0 90 0\n";
  const Prediction rest = run(text, SenderModel::kRest);
  const Prediction zero = run(text, SenderModel::kStream, "6=0");
  ASSERT_EQ(rest.records.size(), zero.records.size());
  for (size_t k = 0; k < rest.records.size(); ++k) {
    EXPECT_EQ(zero.records[k].ticks, rest.records[k].ticks) << k;
    if (rest.records[k].action == PredictRecord::Action::kMove) {
      EXPECT_EQ(rest.records[k].ticks, profile_duration_ticks(rest.records[k].dominant_steps, rest.settings.motion()));
    }
  }
  EXPECT_EQ(zero.total_ticks - zero.records.front().start_tick, rest.total_ticks);
}

TEST(Schedule, APauseOrTheGripperEndsAStream) {
  // The move before a D ends at rest: its duration is its rest-to-rest profile's, less what
  // it gained entering at speed.
  const Prediction p = run(base_turn(30, 5) + "D 0.1\n" + "M 40 90 0\n", SenderModel::kStream);
  ASSERT_EQ(p.rejected, 0);
  const PredictRecord& d = p.records[5];
  EXPECT_EQ(d.action, PredictRecord::Action::kPause);
  EXPECT_EQ(d.ticks, 200000u);
  const PredictRecord& after = p.records[6];
  EXPECT_EQ(after.ticks, profile_duration_ticks(after.dominant_steps, p.settings.motion()));
}

TEST(JunctionLevel, FollowsTheRule) {
  const int32_t x[3] = {10, 0, 0}, x2[3] = {20, 0, 0}, y[3] = {0, 10, 0}, back[3] = {-10, 0, 0},
                diag[3] = {10, 10, 0};
  EXPECT_EQ(junction_level<3>(x, 10, x2, 20, 3, 50), kMaxJunctionLevel);  // the same direction
  EXPECT_EQ(junction_level<3>(x, 10, x2, 20, 3, 0), 0);                   // $6=0: at rest
  // A right angle in steps: m = 1, level 4 d = 2 at d = 0.5 step; a reversal: m = 2, level d.
  EXPECT_EQ(junction_level<3>(x, 10, y, 10, 3, 50), 2);
  EXPECT_EQ(junction_level<3>(x, 10, back, 10, 3, 400), 4);
  // 45 degrees in steps: the base's share stays 1, the shoulder's rises from 0 to 1: m = 1.
  EXPECT_EQ(junction_level<3>(x, 10, diag, 10, 3, 100), 4);
  // Long moves are scaled to at most 1023 dominant steps and give the same level.
  const int32_t lx[3] = {100000, 0, 0}, ly[3] = {0, 100000, 0};
  EXPECT_EQ(junction_level<3>(lx, 100000, ly, 100000, 3, 50), 2);
}

TEST(JunctionLevel, APlanEndsAtRestAndNeverEntersFasterThanItCanStop) {
  PlanBlock b[4] = {{10, 0, 0, 0}, {10, 65535, 0, 0}, {3, 8, 0, 0}, {10, 65535, 0, 0}};
  const uint16_t first = plan_entries([&](uint8_t k) -> const PlanBlock& { return b[k]; },
                                      [&](uint8_t k, uint16_t e) { b[k].entry = e; }, 4);
  EXPECT_EQ(first, 0);       // after rest
  EXPECT_EQ(b[3].entry, 10);  // the newest stops in its 10 steps
  EXPECT_EQ(b[2].entry, 8);   // its junction
  EXPECT_EQ(b[1].entry, 18);  // its exit (8) and its 10 steps
}
