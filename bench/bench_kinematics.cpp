// bench/bench_kinematics.cpp - forward kinematics, Jacobian and the closed-form IK of the
// core (shared/articula), double, on the host (bench/README.md).
#include <benchmark/benchmark.h>

#include <articula/ik_ypp.h>

#include <cmath>
#include <random>

#include "bench_common.h"

using namespace articula;
using namespace articula::host;

namespace {

const std::vector<std::vector<double>>& poses(const HostModel& m) {
  static const std::vector<std::vector<double>> p = bench::random_poses(m, 1024, 7);
  return p;
}

void fk(benchmark::State& state, const HostModel& m) {
  const auto& q = poses(m);
  HostFrames f;
  size_t i = 0;
  for (auto _ : state) {
    forward_kinematics(f, m, q[i].data());
    benchmark::DoNotOptimize(f.T_base_tool.p.x);
    benchmark::ClobberMemory();
    i = (i + 1) & 1023;
  }
}

void jac(benchmark::State& state, const HostModel& m, bool with_fk) {
  const auto& q = poses(m);
  HostFrames f;
  forward_kinematics(f, m, q[0].data());
  double J[6][kMaxJoints];
  size_t i = 0;
  for (auto _ : state) {
    if (with_fk) forward_kinematics(f, m, q[i].data());
    jacobian(J, m, f);
    benchmark::DoNotOptimize(J[0][0]);
    benchmark::ClobberMemory();
    i = (i + 1) & 1023;
  }
}

void BM_PandaFk(benchmark::State& s) {
  static const HostModel m = bench::load("panda").model;
  fk(s, m);
}
void BM_PandaJacobian(benchmark::State& s) {
  static const HostModel m = bench::load("panda").model;
  jac(s, m, false);
}
void BM_PandaFkAndJacobian(benchmark::State& s) {
  static const HostModel m = bench::load("panda").model;
  jac(s, m, true);
}
BENCHMARK(BM_PandaFk);
BENCHMARK(BM_PandaJacobian);
BENCHMARK(BM_PandaFkAndJacobian);

// sin and cos of one angle: glibc's sincos, and Math<double>::sincos (the core's fast path,
// shared/articula/platform.h), one at a time and eight at a time (sincos_n, two per SIMD
// pair), for 1,024 angles uniform in [-pi, pi]. Times per angle.
const std::vector<double>& sincos_angles() {
  static const std::vector<double> x = [] {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-M_PI, M_PI);
    std::vector<double> v(1024);
    for (double& a : v) a = u(rng);
    return v;
  }();
  return x;
}
void BM_SinCosGlibc(benchmark::State& state) {
  const auto& x = sincos_angles();
  size_t i = 0;
  for (auto _ : state) {
    double s, c;
    ::sincos(x[i], &s, &c);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(c);
    i = (i + 1) & 1023;
  }
}
void BM_SinCosCore(benchmark::State& state) {
  const auto& x = sincos_angles();
  size_t i = 0;
  for (auto _ : state) {
    double s, c;
    Math<double>::sincos(x[i], s, c);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(c);
    i = (i + 1) & 1023;
  }
}
void BM_SinCosCoreEightAtOnce(benchmark::State& state) {
  const auto& x = sincos_angles();
  double s[8], c[8];
  size_t i = 0;
  for (auto _ : state) {
    Math<double>::sincos_n(&x[i], s, c, 8);
    benchmark::DoNotOptimize(s[7]);
    benchmark::ClobberMemory();
    i = (i + 8) & 1023;
  }
  state.SetItemsProcessed(state.iterations() * 8);
}
BENCHMARK(BM_SinCosGlibc);
BENCHMARK(BM_SinCosCore);
BENCHMARK(BM_SinCosCoreEightAtOnce);

// The core's closed form alone (ypp_solve), on the MK2 with its motor limits: points the
// arm reaches (uniform motor angles within their limits), and points it does not (poses
// within the looser joint box that break a motor limit), where ypp_solve searches for the
// nearest pose within the limits.
struct Mk2Points {
  YppArm<double> arm;
  std::vector<Vec3<double>> reachable, unreachable;
  Mk2Points() {
    const Robot r = bench::load("mk2plus");
    ypp_from_model(arm, r.model);
    ypp_limits_from_actuation(arm, r.actuation);
    std::mt19937_64 rng(3);
    while (reachable.size() < 1024) {
      double u[3], q[3];
      for (int k = 0; k < 3; ++k)
        u[k] = deg_to_rad(std::uniform_real_distribution<double>(r.actuation.motors[k].min / 1000.0,
                                                                 r.actuation.motors[k].max / 1000.0)(rng));
      joints_from_actuators(q, r.actuation, u);
      reachable.push_back(tool_position(r.model, q));
    }
    for (const auto& q : bench::random_poses(r.model, 100000, 4)) {
      if (unreachable.size() == 1024) break;
      YppResult<double> res;
      const Vec3<double> p = tool_position(r.model, q.data());
      ypp_solve(res, arm, p, false);
      if (res.status != kYppReached) unreachable.push_back(p);
    }
  }
};

void ypp(benchmark::State& state, bool reachable) {
  static const Mk2Points pts;
  const std::vector<Vec3<double>>& targets = reachable ? pts.reachable : pts.unreachable;
  YppResult<double> res;
  size_t i = 0;
  for (auto _ : state) {
    ypp_solve(res, pts.arm, targets[i], true);
    benchmark::DoNotOptimize(res.nearest.x);
    benchmark::ClobberMemory();
    i = (i + 1) % targets.size();
  }
}
void BM_Mk2YppSolveReachable(benchmark::State& s) { ypp(s, true); }
void BM_Mk2YppSolveNearestOfUnreachable(benchmark::State& s) { ypp(s, false); }
BENCHMARK(BM_Mk2YppSolveReachable);
BENCHMARK(BM_Mk2YppSolveNearestOfUnreachable);

}  // namespace

BENCHMARK_MAIN();
