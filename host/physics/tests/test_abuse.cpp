// The abuse test: every shipped robot through random commands (seeded) that cross
// itself and the scene: no NaN, no body leaves the world, and the simulation runs at least
// 50x faster than real time over every second of simulated time.
#include <gtest/gtest.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

#include "program.h"
#include "robot_file.h"
#include "sim.h"

using namespace articula;
using namespace articula::host;

namespace {

double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double reach_mm(const Robot& r) {
  double reach = std::fabs(r.model.T_last_tool.p.x) + std::fabs(r.model.T_last_tool.p.y) + std::fabs(r.model.T_last_tool.p.z);
  for (int i = 0; i < r.model.num_rows; ++i) reach += std::fabs(r.model.rows[i].a) + std::fabs(r.model.rows[i].d);
  return reach;
}

// Objects all round the arm within its reach: cubes, a ball, a can, a static pillar and table.
Scene busy_scene(double reach) {
  Scene s;
  const double r = 0.55 * reach, size = std::clamp(0.12 * reach, 20.0, 80.0);
  for (int k = 0; k < 6; ++k) {
    SceneObject o;
    o.name = "thing " + std::to_string(k);
    const double a = k * M_PI / 3;
    o.xyz = make_vec3(r * std::cos(a), r * std::sin(a), size / 2);
    o.movable = k < 4;
    o.mass = 0.05 + 0.05 * k;
    o.type = k == 1 ? SceneObject::Type::kSphere : k == 2 ? SceneObject::Type::kCylinder : SceneObject::Type::kBox;
    o.size = {size, size, size};
    if (k == 1) o.size = {size / 2, 0, 0};
    if (k == 2) o.size = {size / 2, size, 0};
    if (k == 4) o.size = {size, size, 3 * size}, o.xyz.z = 1.5 * size;  // a pillar
    if (k == 5) o.size = {2 * size, 2 * size, size};                   // a low table
    s.objects.push_back(o);
  }
  SceneObject stack = s.objects[0];  // a cube on another
  stack.name = "stacked";
  stack.xyz.z += stack.size[2];
  s.objects.push_back(stack);
  return s;
}

std::string random_program(const Robot& r, std::mt19937& rng, int commands) {
  std::ostringstream p;
  std::uniform_real_distribution<double> u(0, 1);
  if (r.has_motors) {
    for (int c = 0; c < commands; ++c) {
      if (u(rng) < 0.2) {
        p << "G " << int(u(rng) * 100) << "\n";
        continue;
      }
      p << "M";
      for (int m = 0; m < r.actuation.num_motors; ++m) {
        const MotorSpec& ms = r.actuation.motors[m];
        p << " " << (ms.min + u(rng) * (ms.max - ms.min)) / 1000.0;
      }
      p << "\n";
    }
  } else {
    for (int c = 0; c < commands; ++c) {
      if (r.gripper.present && u(rng) < 0.2) {
        p << "h\n" << 0.5 * u(rng) << "\n";
        continue;
      }
      p << "m\n";
      for (int j = 0; j < r.model.num_joints; ++j) {
        const JointSpec<double>& js = r.model.joints[j];
        const double v = js.lo + u(rng) * (js.hi - js.lo);
        p << (js.param == kParamD ? v : v * 180 / M_PI) << "\n";
      }
    }
  }
  return p.str();
}

TEST(Abuse, EveryRobotRandomCommands) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(ARTICULA_SOURCE_DIR) + "/robots"))
    if (e.path().extension() == ".json" && e.path().filename() != "robot.schema.json") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u);
  std::mt19937 rng(20240505);
  double worst_ratio = 1e300;
  std::string worst_where;
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    const Robot r = load_robot_file(f);
    const Scene scene = busy_scene(reach_mm(r));
    SimOptions o;
    o.joints.speed_deg = 180;
    o.joints.speed_mm = 300;
    o.settings.value[ControllerSettings::kMaxRate] = 900;  // faster than the default 600
    o.settings.value[ControllerSettings::kAccel] = 4000;
    Simulation sim(r, scene, o);
    const std::string text = random_program(r, rng, 25);
    const Program p = r.has_motors ? parse_protocol_program(text, "abuse.arm", r) : parse_robosim(text, "abuse.robosim", r);
    sim.load_program(p);
    ASSERT_GT(sim.end_time(), 3);
    const auto& lo = scene.world_min;
    const auto& hi = scene.world_max;
    int removed = 0;
    while (!sim.done()) {
      // The time of the simulation's steps only (not of this test's checks), per second simulated,
      // as this thread's CPU time: on a shared machine the wall clock also counts the others.
      const double t0 = sim.time();
      double wall = 0;
      while (!sim.done() && sim.time() < t0 + 1 - 1e-9) {
        const double w0 = thread_seconds();
        sim.step();
        wall += thread_seconds() - w0;
        for (double q : sim.joints()) ASSERT_TRUE(std::isfinite(q)) << "t = " << sim.time();
        for (int i = 0; i < sim.num_objects(); ++i) {
          const Vec3<double> c = sim.object_pose(i).p;
          ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) << sim.object(i).name;
          ASSERT_TRUE(c.x >= lo.x && c.y >= lo.y && c.z >= lo.z && c.x <= hi.x && c.y <= hi.y && c.z <= hi.z)
              << sim.object(i).name << " at t = " << sim.time();
        }
      }
      const double ratio = (sim.time() - t0) / std::max(wall, 1e-9);
      if (ratio < worst_ratio) {
        worst_ratio = ratio;
        worst_where = r.name + " at t = " + std::to_string(t0) + " s";
      }
      EXPECT_GE(ratio, 50) << r.name << ": simulated " << sim.time() - t0 << " s in " << wall << " s at t = " << t0;
    }
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
  std::printf("worst simulated/CPU time ratio over 1 s chunks: %.0f (%s)\n", worst_ratio, worst_where.c_str());
}

}  // namespace
