// bench/bench_physics.cpp - the physics simulation (host/physics/sim.h): the MK2 arm and a
// 3 cm cube on the ground, 1 ms world steps, 10 s simulated per iteration; items/s = world
// steps per second (the target: 300,000 on one core). BM_SimMk2Cube runs a program
// of moves (the arm stepping as the firmware times it, the gripper opening and closing),
// BM_SimMk2CubeIdle holds still. bench/compare_mujoco.py runs both.
#include <benchmark/benchmark.h>

#include "bench_common.h"
#include "bench_scene.h"
#include "program.h"
#include "sim.h"

using namespace articula;
using namespace articula::host;
using articula::bench::cube_scene;
using articula::bench::kMoves;

namespace {

void run(benchmark::State& state, bool moves) {
  const Robot robot = bench::load("mk2plus");
  const Scene scene = cube_scene();
  const Program program = parse_protocol_program(moves ? kMoves : "", "bench.arm", robot);
  const int steps = 10000;  // 10 s of 1 ms steps
  double program_s = 0;
  for (auto _ : state) {
    state.PauseTiming();
    Simulation sim(robot, scene);
    sim.load_program(program);
    program_s = sim.program_end();
    state.ResumeTiming();
    for (int i = 0; i < steps; ++i) sim.step();
    benchmark::DoNotOptimize(sim.object_pose(0).p.z);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * steps);
  state.counters["program_s"] = program_s;
}

void BM_SimMk2Cube(benchmark::State& state) { run(state, true); }
void BM_SimMk2CubeIdle(benchmark::State& state) { run(state, false); }

}  // namespace

BENCHMARK(BM_SimMk2Cube)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimMk2CubeIdle)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
