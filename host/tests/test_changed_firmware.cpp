// The prediction and the physics are the firmware (issue 39): this program links the host
// library and the physics with a firmware that differs from firmware/src in one line
// (host/tests/CMakeLists.txt: controller.cpp makes D's pause twice as long), and both follow
// it. Nothing else changed: the host library and the physics are the same as in every other
// test program.
#include <gtest/gtest.h>

#include <string>

#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "sim.h"
#include "test_robots.h"

using namespace articula;
using namespace articula::host;

namespace {

Prediction predict(const std::string& text, SenderModel::Kind kind) {
  SenderModel sender;
  sender.kind = kind;
  return predict_program(mk2(), parse_protocol_program(text, "test", mk2()), {}, sender);
}

TEST(ChangedFirmware, ThePredictionFollowsAFirmwareSource) {
  for (SenderModel::Kind kind : {SenderModel::kRest, SenderModel::kStream}) {
    const Prediction p = predict("D 0.5\nL 0 10\n", kind);
    ASSERT_EQ(p.records.size(), 2u);
    const PredictRecord& d = p.records[0];
    const PredictRecord& l = p.records[1];
    // The firmware as shipped pauses 0.5 s (1,000,000 ticks: host.Predict.ProgramDwellIsTheFirmwares);
    // this one pauses 1 s, and the move after it starts 1 s later.
    EXPECT_EQ(d.end_tick - d.start_tick, 2000000u) << sender_name(kind);
    EXPECT_EQ(l.start_tick, d.end_tick) << sender_name(kind);
    EXPECT_GT(l.end_tick, l.start_tick) << sender_name(kind);
    EXPECT_EQ(p.total_ticks, l.end_tick) << sender_name(kind);
  }
}

TEST(ChangedFirmware, ThePhysicsFollowsAFirmwareSource) {
  // A program: each line at rest; commands: streamed. The move after D 0.5 starts 1 s on.
  Simulation program(mk2(), Scene{}), plain(mk2(), Scene{});
  program.load_program(parse_protocol_program("D 0.5\nL 0 10\n", "test", mk2()));
  plain.load_program(parse_protocol_program("L 0 10\n", "test", mk2()));
  EXPECT_NEAR(program.program_end() - plain.program_end(), 1.0, 1e-6);
  program.run_until(0.99);
  EXPECT_EQ(program.counted_steps(), (std::vector<int32_t>{0, 0, 0}));  // (the shipped firmware: moving)
  while (!program.done()) program.step();
  EXPECT_EQ(program.counted_steps(), (std::vector<int32_t>{32, 0, 0}));

  Simulation live(mk2(), Scene{});
  ASSERT_EQ(live.command("D 0.5"), kOk);
  ASSERT_EQ(live.command("L 0 10"), kOk);
  live.run_until(0.99);
  EXPECT_EQ(live.counted_steps(), (std::vector<int32_t>{0, 0, 0}));
  live.run_until(1.2);
  EXPECT_GT(live.counted_steps()[0], 0);
}

}  // namespace
