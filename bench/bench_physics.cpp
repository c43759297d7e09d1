// bench/bench_physics.cpp - the physics simulation (host/physics/sim.h): the MK2 arm and a
// 3 cm cube on the ground, 1 ms world steps, 10 s simulated per iteration; items/s = world
// steps per second (the target: 300,000 on one core). BM_SimMk2Cube runs a program
// of moves (the arm stepping as the firmware times it, the gripper opening and closing),
// BM_SimMk2CubeIdle holds still. bench/compare_mujoco.py runs both. BM_AbuseEveryRobot runs the
// abuse test's world (host/physics/tests/abuse_scene.h: every shipped robot, 25 random commands
// through a busy scene) and gives, per robot and overall, simulated seconds per CPU second of the
// simulation's steps, the worst 1 s of simulated time included (the figure the abuse test once
// asserted, 50x: a speed is a benchmark's figure, not a unit test's). BM_CellOfMk2s/N puts N of
// BM_SimMk2Cube's arm, each with its cube and program and its own firmware, in one world
// (cell_sim.h): world steps/s for 1, 2 and 4 arms, and `per_arm_us`, a world step's time per
// arm (flat: the cost grows linearly with the arms). BM_BeltAndCubes/N: a running belt carrying N
// cubes beside the arm at rest, against the bare world (N = 0): issue 53's figure.
#include <benchmark/benchmark.h>

#include <ctime>

#include "bench_common.h"
#include "abuse_scene.h"
#include "bench_scene.h"
#include "cell_sim.h"
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

double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void BM_AbuseEveryRobot(benchmark::State& state) {
  std::vector<Robot> robots;
  for (const auto& f : abuse::shipped_robot_files(ARTICULA_SOURCE_DIR)) robots.push_back(load_robot_file(f));
  double simulated = 0, cpu = 0, worst = 1e300;
  for (auto _ : state) {
    std::mt19937 rng(abuse::kSeed);
    for (const Robot& r : robots) {
      state.PauseTiming();
      Simulation sim(r, abuse::busy_scene(abuse::reach_mm(r)), abuse::options());
      sim.load_program(abuse::random_commands(r, rng));
      state.ResumeTiming();
      while (!sim.done()) {
        const double t0 = sim.time(), c0 = thread_seconds();
        while (!sim.done() && sim.time() < t0 + 1 - 1e-9) sim.step();
        const double dc = thread_seconds() - c0;
        simulated += sim.time() - t0;
        cpu += dc;
        worst = std::min(worst, (sim.time() - t0) / std::max(dc, 1e-9));
      }
    }
  }
  state.counters["x_real_time"] = simulated / std::max(cpu, 1e-9);
  state.counters["worst_1s_x"] = worst;
  state.counters["simulated_s"] = simulated / double(state.iterations());
}

// N MK2s facing out from a circle 1.2 m across (their reaches never meet), each with the cube in
// front of it where bench_scene.h puts it, each running kMoves on its own firmware.
void BM_CellOfMk2s(benchmark::State& state) {
  const int n = int(state.range(0));
  const Robot robot = bench::load("mk2plus");
  Cell cell;
  cell.name = "bench";
  const SceneObject cube = cube_scene().objects[0];
  for (int i = 0; i < n; ++i) {
    CellArm a;
    a.name = "arm" + std::to_string(i);
    a.robot = robot;
    a.yaw_deg = 360.0 * i / n;
    const double yaw = a.yaw_deg * M_PI / 180;
    a.xyz = make_vec3(600 * std::cos(yaw), 600 * std::sin(yaw), 0.0);
    a.program = parse_protocol_program(kMoves, "bench.arm", robot);
    SceneObject c = cube;
    c.name = "cube" + std::to_string(i);
    c.xyz = a.T_world_base() * cube.xyz;
    cell.scene.objects.push_back(c);
    cell.arms.push_back(a);
  }
  const int steps = 10000;
  for (auto _ : state) {
    state.PauseTiming();
    CellSimulation sim(cell);
    state.ResumeTiming();
    for (int i = 0; i < steps; ++i) sim.step();
    benchmark::DoNotOptimize(sim.world().object_pose(0).p.z);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * steps);
  state.counters["arms"] = n;
  state.counters["per_arm_us"] =
      benchmark::Counter(double(steps) * n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Issue 53's figure: a running belt carrying N 25 mm cubes (in rows of five on a 2 m belt,
// 100 mm/s), the arm at rest, against the same world bare (N = 0: the ground and the arm only);
// world steps per second, 2 s simulated per iteration (the cubes stay on the belt).
void BM_BeltAndCubes(benchmark::State& state) {
  const int n = int(state.range(0));
  const Robot robot = bench::load("mk2plus");
  Scene scene;
  if (n > 0) {
    SceneObject belt;
    belt.name = "belt";
    belt.size = {2000, 240, 10};
    belt.xyz = make_vec3(600.0, 0.0, 5.0);
    belt.rpy_deg = make_vec3(0.0, 0.0, 90.0);
    belt.belt = 100;
    scene.objects.push_back(belt);
  }
  for (int i = 0; i < n; ++i) {
    SceneObject c;
    c.name = "cube" + std::to_string(i);
    c.size = {25, 25, 25};
    c.xyz = make_vec3(600.0 - 80 + 40 * (i % 5), -900.0 + 45 * (i / 5), 22.5);
    c.movable = true;
    c.mass = 0.016;
    scene.objects.push_back(c);
  }
  const int steps = 2000;
  for (auto _ : state) {
    state.PauseTiming();
    Simulation sim(robot, scene);
    state.ResumeTiming();
    for (int i = 0; i < steps; ++i) sim.step();
    benchmark::DoNotOptimize(sim.time());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * steps);
  state.counters["objects"] = n;
}

}  // namespace

BENCHMARK(BM_BeltAndCubes)->Arg(0)->Arg(10)->Arg(50)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CellOfMk2s)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AbuseEveryRobot)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_SimMk2Cube)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimMk2CubeIdle)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
