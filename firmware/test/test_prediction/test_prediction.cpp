// The firmware on its virtual clock (firmware/sitl/) against the host's prediction
// (host/lib/predict.h, `articula predict`): every shipped protocol program, plan and stream,
// sent as `--sender rest` and `--sender stream` send them, gets the predicted reply on every
// line, makes the predicted steps, ends every move on the predicted tick exactly (the SITL
// machine's main loop takes no time, as the prediction assumes), and comes to rest on the
// predicted steps. The figures are printed. This is the oracle for the prediction to become
// the firmware itself (issue 39): it runs in milliseconds, where the emulated Nanos take
// seconds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"

using namespace articula;

namespace {

const host::Robot& robot_file() {
  static const host::Robot r = host::load_robot_file(ARTICULA_ROBOT_FILE);
  return r;
}

struct Case {
  const char* file;
  host::SenderModel::Kind sender;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.file << " --sender " << host::sender_name(c.sender);
}

std::string name_of(const ::testing::TestParamInfo<Case>& info) {
  std::string n = info.param.file;  // "hil/plans/x.arm": hil_plans_x
  n = n.substr(0, n.rfind('.'));
  for (char& c : n)
    if (!isalnum(static_cast<unsigned char>(c))) c = '_';
  return n + (info.param.sender == host::SenderModel::kRest ? "_rest" : "_stream");
}

class FirmwareMatchesThePrediction : public ::testing::TestWithParam<Case> {};

TEST_P(FirmwareMatchesThePrediction, RepliesStepsAndMoveEnds) {
  const Case c = GetParam();
  const host::Robot& robot = robot_file();
  const std::string path = std::string(ARTICULA_SOURCE_DIR) + "/" + c.file;
  const host::Program program = host::load_program(path, robot);
  host::SenderModel sender;
  sender.kind = c.sender;
  const host::Prediction p = host::predict_program(robot, program, {}, sender);

  std::vector<std::string> lines;
  for (const host::PredictRecord& r : p.records) lines.push_back(r.stop ? "!" : r.protocol.empty() ? r.text : r.protocol);

  sim::boot();
  sim::status();  // the W:14 of a blank EEPROM, taken
  sim::take_lines();
  const uint64_t t0 = sitl::hw.now;
  const size_t coil_writes0 = sitl::hw.coil_log.size();
  const std::vector<sitl::Exchange> got =
      sitl::run_lines(lines, c.sender == host::SenderModel::kRest ? sitl::kAtRest : sitl::kStreamed);
  ASSERT_EQ(got.size(), p.records.size());

  // Every deadline at which a motor stepped, from the coil writes (decoded by the SITL HAL).
  std::vector<uint64_t> steps;
  for (size_t i = coil_writes0; i < sitl::hw.coil_log.size(); ++i) {
    const sitl::CoilWrite& w = sitl::hw.coil_log[i];
    if (w.step != 0 && (steps.empty() || steps.back() != w.tick - t0)) steps.push_back(w.tick - t0);
  }

  uint64_t predicted_steps = 0, worst = 0;
  size_t k = 0, moves = 0;
  for (size_t i = 0; i < p.records.size(); ++i) {
    const host::PredictRecord& r = p.records[i];
    const std::string want = r.stop ? "" : r.reply == kOk ? "ok" : "error:" + std::to_string(int(r.reply));
    EXPECT_EQ(got[i].reply, want) << c.file << " line " << r.line << ": " << lines[i];
    if (r.dominant_steps == 0) continue;
    ++moves;
    predicted_steps += r.dominant_steps;
    k += r.dominant_steps;
    if (k > steps.size()) break;
    const uint64_t end = steps[k - 1];
    worst = std::max<uint64_t>(worst, end > r.end_tick ? end - r.end_tick : r.end_tick - end);
    EXPECT_EQ(end, r.end_tick) << c.file << " line " << r.line << " (" << lines[i] << "): its last step";
  }
  EXPECT_EQ(steps.size(), predicted_steps) << c.file << ": the firmware made other steps than predicted";
  const host::PredictRecord& last = p.records.back();
  for (size_t m = 0; m < last.steps.size() && m < size_t(robot::kJoints); ++m)
    EXPECT_EQ(sitl::hw.position[m], last.steps[m]) << c.file << ": motor " << m << " at rest";
  EXPECT_EQ(sim::hal_errors(), "");
  std::printf("  %s, %s: %zu lines, %zu moves, %zu steps; last step at %.6f s (predicted %.6f s); worst move end %llu ticks\n",
              c.file, host::sender_name(c.sender), lines.size(), moves, steps.size(),
              steps.empty() ? 0.0 : double(steps.back()) / 2e6, double(p.total_ticks) / 2e6,
              static_cast<unsigned long long>(worst));
}

const char* const kFiles[] = {
    "programs/demo.arm",           "programs/grasp-and-lift.arm",    "programs/push.arm",
    "programs/thesis-repeatability.arm", "programs/too-fast.arm",  "hil/plans/straight-lines.arm",
    "hil/plans/thesis-repeatability.arm", "hil/plans/thesis-single-joint.arm", "hil/plans/tool-points.arm",
    "hil/streams/circle.arm",      "hil/streams/collinear-split.arm", "hil/streams/lines.arm",
    "hil/streams/square.arm",      "hil/streams/stream-mixed.arm",   "hil/streams/zigzag.arm",
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const char* f : kFiles)
    for (host::SenderModel::Kind k : {host::SenderModel::kRest, host::SenderModel::kStream}) out.push_back(Case{f, k});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Shipped, FirmwareMatchesThePrediction, ::testing::ValuesIn(cases()), name_of);

}  // namespace

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
