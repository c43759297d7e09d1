// Live physics with a streamed program: each line sent to the simulation as soon as the one
// before is answered (Simulation::command, the firmware's own session), as GRBL's simple
// sender streams. The physics' step counts are the virtual Nano's at every world step: the
// firmware run here on its own (sitl::run_lines, the same lines streamed), its coils' steps
// read back by the SITL's decoder.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "nano_config.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "sim.h"

// The firmware on its virtual clock (the host's eight-motor build the library links).
#include "machine.h"

using namespace articula;
using namespace articula::host;

namespace {

const std::string kSrc = ARTICULA_SOURCE_DIR;
Robot load(const std::string& name) { return load_robot_file(kSrc + "/robots/" + name + ".json"); }

// Lines that blend when streamed (short moves the planner joins), a straight line's segments,
// a gripper pause and a refused line among them.
const char* const kProgram =
    "M 30 60 -20\nM 25 65 -15\nM 20 70 -10\nM 10 80 -5\nM 0 90 0\nP 250 -50 150\nT 250 50 150 40\n"
    "G 30\nL 0 10\nL 1 150\nL 0 -10\nM 0 90 0\n";

}  // namespace

TEST(Stream, LivePhysicsStepsAsTheVirtualNano) {
  const Robot r = load("mk2plus");
  const Program p = parse_protocol_program(kProgram, "stream.arm", r);
  std::vector<std::string> lines;
  for (const Statement& st : p.statements) lines.push_back(st.text);

  Simulation sim(r, Scene{});
  std::vector<Status> replies;
  for (const std::string& line : lines) replies.push_back(sim.command(line));

  // The virtual Nano alone, the same lines streamed (the thread's first machine: the
  // simulation's firmware is a machine of its own).
  const ConfiguredArm<kFirmwareMotors> arm = firmware_arm(r);
  sitl::boot(true, "", nullptr, &arm);
  sitl::take_lines();
  const uint64_t t0 = sitl::hw().now;
  const std::vector<sitl::Exchange> got = sitl::run_lines(lines, sitl::kStreamed);
  ASSERT_EQ(got.size(), lines.size());
  for (size_t i = 0; i < lines.size(); ++i)
    EXPECT_EQ(got[i].reply, replies[i] == kOk ? std::string("ok") : "error:" + std::to_string(int(replies[i])))
        << lines[i];
  EXPECT_EQ(replies[9], kJointLimit);  // L 1 150
  const int n = r.actuation.num_motors;
  std::vector<std::vector<sitl::Step>> steps;
  size_t total = 0;
  for (int m = 0; m < n; ++m) {
    steps.push_back(sitl::steps_of(m, t0));
    total += steps.back().size();
  }
  const uint64_t end = sitl::stopped_at() - t0;
  ASSERT_GT(total, 500u);

  // The streamed program blends: faster than each line from rest to rest.
  SenderModel rest;
  EXPECT_LT(double(end) / kStepTickHz, predict_program(r, p, {}, rest).total_s() - 0.05);

  // World step by world step (1 ms): the physics' counts are the Nano's.
  std::vector<size_t> next(size_t(n), 0);
  std::vector<int32_t> nano(size_t(n), 0);
  const uint64_t tick_per_step = uint64_t(sim.options().dt * kStepTickHz + 0.5);
  size_t compared = 0;
  for (uint64_t k = 1; (k - 1) * tick_per_step <= end + 2 * tick_per_step; ++k) {
    sim.step();
    for (int m = 0; m < n; ++m)
      for (size_t& i = next[size_t(m)]; i < steps[size_t(m)].size() && steps[size_t(m)][i].tick - t0 <= k * tick_per_step;
           ++i)
        nano[size_t(m)] += steps[size_t(m)][i].dir;
    ASSERT_EQ(sim.counted_steps(), nano) << "at " << double(k * tick_per_step) / kStepTickHz << " s";
    ++compared;
  }
  EXPECT_EQ(sim.lost_steps(), std::vector<int32_t>(size_t(n), 0));
  EXPECT_FALSE(sim.busy());
  std::printf("  %zu lines streamed, %zu steps, %zu world steps compared, the end at %.3f s\n", lines.size(), total,
              compared, double(end) / kStepTickHz);
}
