// The prediction is the firmware (issue 39): this program links the host library with a
// firmware that differs from firmware/src in one line (host/tests/CMakeLists.txt: controller.cpp
// makes D's pause twice as long), and the prediction follows it. Nothing else changed: the
// host library, its model of the controller (which still says 0.5 s for D 0.5) and the CLI's
// code are the same as in every other test program.
#include <gtest/gtest.h>

#include <string>

#include "predict.h"
#include "program.h"
#include "robot_file.h"
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

}  // namespace
