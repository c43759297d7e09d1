// bench/bench_predict.cpp - what the real arm will do with a program: the prediction as
// `articula predict` makes it (host::predict_program: the firmware on its virtual clock runs
// the lines, every record is read from what it did, the host adds the tools) against the
// firmware's run alone (firmware/sitl: sitl::run_lines, the same lines sent as the same sender
// sends them). Issue 39 holds the prediction to at most 1.5x the time it took before it ran the
// firmware (bench/README.md, "The prediction").
//
// Programs (MK2 Plus, the firmware's built-in arm):
//   streams10k  10,000 lines: hil/streams/*.arm and programs/*.arm one after the other, again
//               and again (P segments, T lines, M, L, S, G, D, settings);
//   draw_text   bench_draw.py's 60-character text, 120 mm wide, as `robot.draw` writes it.
// Each with --sender rest and --sender stream.
#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "draw.h"
#include "ik.h"
#include "machine.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"

using namespace articula;

namespace {

const host::Robot& mk2() {
  static const host::Robot r = host::load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  return r;
}

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The protocol lines of a program file, comments and blank lines left out (the core's rule:
// host::line_command).
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string l;
  while (std::getline(s, l)) {
    l = host::line_command(l);
    if (!l.empty()) out.push_back(l);
  }
  return out;
}

std::string streams10k() {
  static std::string text;
  if (!text.empty()) return text;
  const char* files[] = {"hil/streams/circle.arm", "hil/streams/collinear-split.arm", "hil/streams/lines.arm",
                         "hil/streams/square.arm", "hil/streams/stream-mixed.arm", "hil/streams/zigzag.arm",
                         "programs/demo.arm",      "programs/grasp-and-lift.arm",    "programs/push.arm"};
  std::vector<std::string> all;
  for (const char* f : files)
    for (const std::string& l : lines_of(read(std::string(ARTICULA_SOURCE_DIR) + "/" + f))) all.push_back(l);
  for (size_t n = 0; n < 10000; ++n) text += all[n % all.size()] + "\n";
  return text;
}

std::string draw_text() {
  static std::string text;
  if (!text.empty()) return text;
  host::DrawRequest req;
  req.text = "The quick brown fox jumps over the lazy dog: 0123456789, ok!";
  req.width_mm = 120;
  req.x = 255;
  req.y = 0;
  req.pen.paper_z = 0;
  req.pen.pen_mm = 120;
  const host::InverseKinematics ik(mk2());
  text = host::make_drawing(mk2(), ik, req).program;
  return text;
}

void predict(benchmark::State& state, std::string (*program)(), host::SenderModel::Kind kind) {
  const host::Program p = host::parse_protocol_program(program(), "bench", mk2());
  host::SenderModel sender;
  sender.kind = kind;
  uint64_t ticks = 0;
  for (auto _ : state) {
    const host::Prediction r = host::predict_program(mk2(), p, {}, sender);
    ticks = r.total_ticks;
    benchmark::DoNotOptimize(ticks);
  }
  state.counters["lines"] = double(p.statements.size());
  state.counters["arm_s"] = double(ticks) / kStepTickHz;
}

void firmware(benchmark::State& state, std::string (*program)(), host::SenderModel::Kind kind) {
  const std::vector<std::string> lines = lines_of(program());
  uint64_t ticks = 0;
  for (auto _ : state) {
    sitl::boot();
    const uint64_t t0 = sitl::hw().now;
    sitl::run_lines(lines, kind == host::SenderModel::kRest ? sitl::kAtRest : sitl::kStreamed);
    ticks = sitl::stopped_at() - t0;
    state.PauseTiming();  // the logs are the machine's memory, not its work: emptied between runs
    sitl::hw().coil_log.clear();
    sitl::hw().coil_log.shrink_to_fit();
    state.ResumeTiming();
  }
  state.counters["lines"] = double(lines.size());
  state.counters["arm_s"] = double(ticks) / kStepTickHz;
}

BENCHMARK_CAPTURE(predict, streams10k_rest, streams10k, host::SenderModel::kRest)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(firmware, streams10k_rest, streams10k, host::SenderModel::kRest)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(predict, streams10k_stream, streams10k, host::SenderModel::kStream)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(firmware, streams10k_stream, streams10k, host::SenderModel::kStream)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(predict, draw_text_rest, draw_text, host::SenderModel::kRest)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(firmware, draw_text_rest, draw_text, host::SenderModel::kRest)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(predict, draw_text_stream, draw_text, host::SenderModel::kStream)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(firmware, draw_text_stream, draw_text, host::SenderModel::kStream)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
