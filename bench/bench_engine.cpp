// bench/bench_engine.cpp - the same measurements compiled twice: natively (build/bench/
// bench_engine) and by emscripten into WebAssembly (build/wasm/bench/bench_engine.mjs, run by
// node), so that bench_wasm.py compares the web engine's code with the native code in the
// same run on the same machine (bench/README.md, "The web engine").
//
//   Panda FK         robots/panda.json, 1,000 poses within the limits, cycled: ns per call,
//                    the best of 15 batches of 100,000 calls
//   Panda IK         bench_ik's case: 1,000 random full poses, each from the ready pose,
//                    default solver: success, median and 95th percentile per solve (the
//                    second pass: the first warms the code, as a long studio session is warm)
//   MK2 IK           bench_ik's case: 1,000 reachable points, the closed form: median per
//                    solve, and the mean over the batch (the clock's granularity matters at 0.5 us)
//   physics          bench_physics's scene (the MK2 and a 3 cm cube, its 9 s of moves), 10 s
//                    of 1 ms steps: world steps per second, the best of 3
//
// Prints one JSON object. Plain C++ with no benchmark library, so that both builds are the same
// source with the same clock (steady_clock; in WebAssembly, performance.now()).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "bench_scene.h"
#include "ik.h"
#include "program.h"
#include "scene.h"
#include "sim.h"

using namespace articula;
using namespace articula::host;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

volatile double g_sink = 0;

double fk_ns() {
  const Robot panda = bench::load("panda");
  const auto poses = bench::random_poses(panda.model, 1000, 20261121);
  double best = 1e9;
  HostFrames f;
  for (int batch = 0; batch < 15; ++batch) {
    const auto t0 = Clock::now();
    double acc = 0;
    for (int i = 0; i < 100000; ++i) {
      forward_kinematics(f, panda.model, poses[size_t(i % 1000)].data());
      acc += f.T_base_tool.p.x;
    }
    best = std::min(best, seconds_since(t0) * 1e9 / 100000);
    g_sink = g_sink + acc;
  }
  return best;
}

struct IkFigures {
  double success = 0, median_us = 0, p95_us = 0, mean_us = 0;
};

IkFigures ik_run(const Robot& robot, const std::vector<IkTarget>& targets, const IkOptions& o) {
  const InverseKinematics ik(robot);
  std::vector<double> us;
  int ok = 0;
  const auto all = Clock::now();
  for (const IkTarget& t : targets) {
    const auto t0 = Clock::now();
    const IkResult r = ik.solve(t, robot.home, o);
    us.push_back(seconds_since(t0) * 1e6);
    ok += r.position_error_mm < 1.0 && (!t.has_rotation || r.orientation_error_rad < 1e-3) && ik.within_all_limits(r.q);
  }
  IkFigures out;
  out.mean_us = seconds_since(all) * 1e6 / double(targets.size());
  std::sort(us.begin(), us.end());
  out.success = double(ok) / double(targets.size());
  out.median_us = bench::percentile_sorted(us, 0.5);
  out.p95_us = bench::percentile_sorted(us, 0.95);
  return out;
}

IkFigures panda_ik() {
  const Robot panda = bench::load("panda");
  std::vector<IkTarget> targets;
  for (const auto& q : bench::random_poses(panda.model, 1000, 20261121)) {
    HostFrames f;
    forward_kinematics(f, panda.model, q.data());
    targets.push_back(IkTarget::pose(f.T_base_tool));
  }
  ik_run(panda, targets, IkOptions{});  // warm: a JIT compiles hot code again, optimised (V8's tiers)
  return ik_run(panda, targets, IkOptions{});
}

IkFigures mk2_ik() {
  const Robot mk2 = bench::load("mk2plus");
  std::mt19937_64 rng(20261121);
  const HostActuation& a = mk2.actuation;
  std::vector<IkTarget> targets;
  for (int i = 0; i < 1000; ++i) {
    double u[kMaxJoints], q[kMaxJoints];
    for (int k = 0; k < a.num_motors; ++k)
      u[k] = deg_to_rad(std::uniform_real_distribution<double>(a.motors[k].min / 1000.0, a.motors[k].max / 1000.0)(rng));
    joints_from_actuators(q, a, u);
    targets.push_back(IkTarget::at(tool_position(mk2.model, q)));
  }
  IkOptions o;
  o.method = IkMethod::kClosedForm;
  ik_run(mk2, targets, o);  // warm
  return ik_run(mk2, targets, o);
}

double physics_steps_per_s() {
  const Robot mk2 = bench::load("mk2plus");
  const Scene scene = bench::cube_scene();
  const Program program = parse_protocol_program(bench::kMoves, "bench.arm", mk2);
  double best = 0;
  for (int round = 0; round < 3; ++round) {
    Simulation sim(mk2, scene);
    sim.load_program(program);
    const auto t0 = Clock::now();
    for (int i = 0; i < 10000; ++i) sim.step();
    best = std::max(best, 10000 / seconds_since(t0));
    g_sink = g_sink + sim.object_pose(0).p.z;
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string only = argc > 1 ? argv[1] : "";
  std::string out = "{";
  auto field = [&](const char* k, double v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s\"%s\": %.6g", out.size() > 1 ? ", " : "", k, v);
    out += buf;
  };
  if (only.empty() || only == "fk") field("fk_ns", fk_ns());
  if (only.empty() || only == "ik") {
    const IkFigures p = panda_ik();
    field("panda_ik_success", p.success);
    field("panda_ik_median_us", p.median_us);
    field("panda_ik_p95_us", p.p95_us);
    const IkFigures m = mk2_ik();
    field("mk2_ik_success", m.success);
    field("mk2_ik_median_us", m.median_us);
    field("mk2_ik_mean_us", m.mean_us);
  }
  if (only.empty() || only == "physics") field("physics_steps_per_s", physics_steps_per_s());
  std::printf("%s}\n", out.c_str());
  return 0;
}
