// The abuse test: every shipped robot through random commands (seeded) that cross
// itself and the scene: no NaN, no body leaves the world, nothing falls through the ground.
// How fast it runs is bench_physics's BM_AbuseEveryRobot (bench/README.md), not a check here:
// a slow or busy machine is no fault of the physics.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "abuse_scene.h"

using namespace articula;
using namespace articula::host;

namespace {

TEST(Abuse, EveryRobotRandomCommands) {
  const std::vector<std::string> files = abuse::shipped_robot_files(ARTICULA_SOURCE_DIR);
  ASSERT_GE(files.size(), 5u);
  std::mt19937 rng(abuse::kSeed);
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    const Robot r = load_robot_file(f);
    const Scene scene = abuse::busy_scene(abuse::reach_mm(r));
    Simulation sim(r, scene, abuse::options());
    sim.load_program(abuse::random_commands(r, rng));
    ASSERT_GT(sim.end_time(), 3);
    const auto& lo = scene.world_min;
    const auto& hi = scene.world_max;
    while (!sim.done()) {
      sim.step();
      for (double q : sim.joints()) ASSERT_TRUE(std::isfinite(q)) << "t = " << sim.time();
      for (int i = 0; i < sim.num_objects(); ++i) {
        const Vec3<double> c = sim.object_pose(i).p;
        ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) << sim.object(i).name;
        ASSERT_TRUE(c.x >= lo.x && c.y >= lo.y && c.z >= lo.z && c.x <= hi.x && c.y <= hi.y && c.z <= hi.z)
            << sim.object(i).name << " at t = " << sim.time();
      }
    }
    int removed = 0;
    for (int i = 0; i < sim.num_objects(); ++i) {
      removed += sim.object_removed(i);
      EXPECT_GT(sim.object_pose(i).p.z, -50) << sim.object(i).name << " fell through the ground";
    }
    EXPECT_EQ(removed, 0) << "a body was taken out of the world";
    int blocks = 0;
    for (const auto& e : sim.events())
      blocks += e.kind == SimEvent::Kind::kCollision || e.kind == SimEvent::Kind::kSelfCollision ||
                e.kind == SimEvent::Kind::kSqueeze;
    std::printf("%-20s %6.1f s simulated, %4zu events, %3d collisions refused\n", r.name.c_str(), sim.time(),
                sim.events().size(), blocks);
  }
}

}  // namespace
