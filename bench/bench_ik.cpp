// bench/bench_ik.cpp - inverse kinematics figures (bench/README.md).
//
//   Panda, full pose: 1,000 random poses within the joint limits (fixed seed), each solved
//   from the same start (the "ready" home pose) with the default solver and options.
//   Success: position error < 1 mm, orientation error < 1e-3 rad, within the limits.
//   Reported: success rate, median and 95th percentile of the time per solve.
//   MK2 Plus, position only: 1,000 random reachable points (uniform motor angles within the
//   motor limits), default solver (the closed form): success rate and time per solve.
//
// The per-solve times come from steady_clock around each call; the BM_*Each benchmarks
// measure the same calls in Google Benchmark's loop as a cross-check.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench_common.h"
#include "ik.h"

using namespace articula;
using namespace articula::host;
using articula::bench::load;
using articula::bench::percentile_sorted;

namespace {

struct Case {
  std::string name;
  Robot robot;
  std::vector<IkTarget> targets;
  std::vector<double> start;
  IkOptions options;
};

std::vector<std::string> g_summary;

Case panda_case(IkMethod method) {
  Case c{"panda full pose, " + std::string(ik_method_name(method)), load("panda"), {}, {}, {}};
  c.start = c.robot.home;
  c.options.method = method;
  for (const auto& q : bench::random_poses(c.robot.model, 1000, 20261121)) {
    HostFrames f;
    forward_kinematics(f, c.robot.model, q.data());
    c.targets.push_back(IkTarget::pose(f.T_base_tool));
  }
  return c;
}

Case mk2_case(IkMethod method) {
  Case c{"mk2plus position, " + std::string(ik_method_name(method)), load("mk2plus"), {}, {}, {}};
  c.start = c.robot.home;
  c.options.method = method;
  std::mt19937_64 rng(20261121);
  const HostActuation& a = c.robot.actuation;
  for (int i = 0; i < 1000; ++i) {
    double u[kMaxJoints], q[kMaxJoints];
    for (int k = 0; k < a.num_motors; ++k)
      u[k] = deg_to_rad(
          std::uniform_real_distribution<double>(a.motors[k].min / 1000.0, a.motors[k].max / 1000.0)(rng));
    joints_from_actuators(q, a, u);
    c.targets.push_back(IkTarget::at(tool_position(c.robot.model, q)));
  }
  return c;
}

// Solves every target once, timing each call.
void run_case(benchmark::State& state, const Case& c) {
  const InverseKinematics ik(c.robot);
  std::vector<double> us;
  int ok = 0, false_reached = 0;
  long iterations = 0, attempts = 0;
  std::map<std::string, int> statuses;
  for (auto _ : state) {
    us.clear();
    ok = false_reached = 0;
    iterations = attempts = 0;
    statuses.clear();
    for (const IkTarget& t : c.targets) {
      const auto t0 = std::chrono::steady_clock::now();
      const IkResult r = ik.solve(t, c.start, c.options);
      const auto t1 = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(r.q.data());
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
      const bool success = r.position_error_mm < 1.0 && (!t.has_rotation || r.orientation_error_rad < 1e-3) &&
                           ik.within_all_limits(r.q);
      ok += success;
      if (r.reached() && (r.position_error_mm > c.options.position_tolerance_mm ||
                          r.orientation_error_rad > c.options.orientation_tolerance_rad))
        ++false_reached;
      iterations += r.iterations;
      attempts += r.attempts;
      ++statuses[ik_status_name(r.status)];
    }
  }
  const double n = double(c.targets.size());
  double sum = 0;
  for (double v : us) sum += v;
  std::sort(us.begin(), us.end());
  const double median = percentile_sorted(us, 0.5), p95 = percentile_sorted(us, 0.95), mean = sum / n;
  const double worst = us.empty() ? 0 : us.back();
  state.counters["success_pct"] = 100.0 * ok / n;
  state.counters["median_us"] = median;
  state.counters["p95_us"] = p95;
  state.counters["mean_us"] = mean;
  state.counters["max_us"] = worst;
  state.counters["iters_mean"] = double(iterations) / n;
  state.counters["attempts_mean"] = double(attempts) / n;
  char line[512];
  std::string st;
  for (const auto& [k, v] : statuses) st += " " + k + "=" + std::to_string(v);
  std::snprintf(line, sizeof line,
                "%-28s %4d targets: success %.1f %% (%d), median %.2f us, p95 %.2f us, mean %.2f us, max %.1f us, "
                "mean iterations %.1f, mean attempts %.2f, statuses:%s, reached above tolerance: %d",
                c.name.c_str(), int(n), 100.0 * ok / n, ok, median, p95, mean, worst,
                double(iterations) / n, double(attempts) / n, st.c_str(), false_reached);
  g_summary.push_back(line);
}

void BM_PandaFullPose1000(benchmark::State& state) {
  static const Case c = panda_case(IkMethod::kAuto);
  run_case(state, c);
}
BENCHMARK(BM_PandaFullPose1000)->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_Mk2Position1000(benchmark::State& state) {
  static const Case c = mk2_case(IkMethod::kAuto);
  run_case(state, c);
}
BENCHMARK(BM_Mk2Position1000)->Iterations(1)->Unit(benchmark::kMillisecond);

// The numeric solver on the MK2, for comparison with its closed form.
void BM_Mk2Position1000Lm(benchmark::State& state) {
  static const Case c = mk2_case(IkMethod::kLevenbergMarquardt);
  run_case(state, c);
}
BENCHMARK(BM_Mk2Position1000Lm)->Iterations(1)->Unit(benchmark::kMillisecond);

// The same calls in Google Benchmark's loop: mean time per solve.
// The case's targets one after the other in Google Benchmark's loop.
void solve_each(benchmark::State& state, const Case& c) {
  const InverseKinematics ik(c.robot);
  size_t i = 0;
  for (auto _ : state) {
    IkResult r = ik.solve(c.targets[i], c.start, c.options);
    benchmark::DoNotOptimize(r.q.data());
    i = (i + 1) % c.targets.size();
  }
}

void BM_PandaFullPoseEach(benchmark::State& state) {
  static const Case c = panda_case(IkMethod::kAuto);
  solve_each(state, c);
}
BENCHMARK(BM_PandaFullPoseEach)->Unit(benchmark::kMicrosecond);

void BM_Mk2PositionEach(benchmark::State& state) {
  static const Case c = mk2_case(IkMethod::kAuto);
  solve_each(state, c);
}
BENCHMARK(BM_Mk2PositionEach)->Unit(benchmark::kNanosecond);

}  // namespace

// ARTICULA_BENCH_DUMP=dir writes the Panda's poses, start and targets there (CSV, rad and
// mm), and the MK2's points (mk2_targets.csv, x y z mm), for bench/compare_rtb.py and
// bench/bench_python.py to solve the very same problems.
void dump(const std::string& dir) {
  const Case c = panda_case(IkMethod::kAuto);
  std::FILE* f = std::fopen((dir + "/panda_targets.csv").c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s/panda_targets.csv\n", dir.c_str());
    std::exit(2);
  }
  std::fprintf(f, "# start (rad): ");
  for (double v : c.start) std::fprintf(f, "%.17g ", v);
  std::fprintf(f, "\n# one target a line: q1..q7 (rad) it was made from, then R (row-major) and p (mm) "
                  "of the flange\n");
  const auto qs = bench::random_poses(c.robot.model, 1000, 20261121);
  for (size_t i = 0; i < qs.size(); ++i) {
    for (double v : qs[i]) std::fprintf(f, "%.17g,", v);
    const IkTarget& t = c.targets[i];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) std::fprintf(f, "%.17g,", t.rotation.m[r][k]);
    std::fprintf(f, "%.17g,%.17g,%.17g\n", t.position.x, t.position.y, t.position.z);
  }
  std::fclose(f);
  const Case mk2 = mk2_case(IkMethod::kAuto);
  f = std::fopen((dir + "/mk2_targets.csv").c_str(), "w");
  if (!f) std::exit(2);
  for (const IkTarget& t : mk2.targets) std::fprintf(f, "%.17g,%.17g,%.17g\n", t.position.x, t.position.y, t.position.z);
  std::fclose(f);
}

int main(int argc, char** argv) {
  if (const char* dir = std::getenv("ARTICULA_BENCH_DUMP")) dump(dir);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (!g_summary.empty()) std::printf("\nSummary (per-call steady_clock times):\n");
  for (const auto& s : g_summary) std::printf("  %s\n", s.c_str());
  return 0;
}
