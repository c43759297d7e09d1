// Tests host/physics/sim.h's world against physics: free fall, a pendulum's period, a box at rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "robot_file.h"
#include "sim.h"

using namespace articula;
using namespace articula::host;

namespace {

const std::string kRobots = std::string(ARTICULA_SOURCE_DIR) + "/robots/";

Robot mk2() { return load_robot_file(kRobots + "mk2plus.json"); }

SceneObject box(const std::string& name, double size_mm, Vec3<double> xyz, double mass) {
  SceneObject o;
  o.name = name;
  o.type = SceneObject::Type::kBox;
  o.size = {size_mm, size_mm, size_mm};
  o.xyz = xyz;
  o.movable = true;
  o.mass = mass;
  return o;
}

// z(t) = z0 - g t^2 / 2. The semi-implicit Euler step lags by g dt t / 2 (2.5 mm after 0.5 s).
TEST(World, FreeFallingBox) {
  Scene s;
  s.ground = false;
  s.objects.push_back(box("box", 30, make_vec3(1500.0, 0.0, 2000.0), 0.05));
  Simulation sim(mk2(), s);
  const double g = 9.81;
  for (double t : {0.1, 0.25, 0.5}) {
    sim.run_until(t);
    const double z = sim.object_pose(0).p.z;
    EXPECT_NEAR(z, 2000 - 1000 * g * t * t / 2, 1000 * g * 0.001 * t / 2 + 0.05) << "t = " << t;
    EXPECT_NEAR(sim.object_pose(0).p.x, 1500, 1e-9);
  }
}

// A rod-like pendulum on a hinge: T = 2 pi sqrt(I / (m g L)), I about the pivot.
TEST(World, PendulumPeriod) {
  Scene s;
  s.ground = false;
  Simulation sim(mk2(), s);
  dWorldID w = sim.world();
  const double L = 0.3, r = 0.01, m = 0.2, g = 9.81;
  dBodyID b = dBodyCreate(w);
  dMass mass;
  dMassSetSphereTotal(&mass, m, r);
  dBodySetMass(b, &mass);
  dBodySetAutoDisableFlag(b, 0);
  const double amp = 5 * M_PI / 180;
  const double pivot[3] = {2.0, 0.0, 1.0};
  dBodySetPosition(b, pivot[0] + L * std::sin(amp), pivot[1], pivot[2] - L * std::cos(amp));
  dJointID h = dJointCreateHinge(w, nullptr);
  dJointAttach(h, b, nullptr);
  dJointSetHingeAnchor(h, pivot[0], pivot[1], pivot[2]);
  dJointSetHingeAxis(h, 0, 1, 0);
  const double I = 0.4 * m * r * r + m * L * L;
  const double expected = 2 * M_PI * std::sqrt(I / (m * g * L));
  // Upward zero crossings of x - pivot x, interpolated.
  std::vector<double> crossings;
  double prev = dBodyGetPosition(b)[0] - pivot[0];
  while (sim.time() < 6 * expected) {
    sim.step();
    const double x = dBodyGetPosition(b)[0] - pivot[0];
    if (prev < 0 && x >= 0) crossings.push_back(sim.time() - sim.options().dt * x / (x - prev));
    prev = x;
  }
  ASSERT_GE(crossings.size(), 4u);
  const double period = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  // Small-amplitude formula; at 5 degrees the true period is 0.05 % longer.
  EXPECT_NEAR(period, expected * (1 + amp * amp / 16), expected * 0.003);
}

TEST(World, BoxAtRestStaysAtRest) {
  Scene s;
  s.objects.push_back(box("cube", 30, make_vec3(150.0, -250.0, 15.0), 0.027));
  Simulation sim(mk2(), s);
  sim.run_until(10);
  const Transform<double> T = sim.object_pose(0);
  EXPECT_NEAR(T.p.x, 150, 0.05);
  EXPECT_NEAR(T.p.y, -250, 0.05);
  EXPECT_NEAR(T.p.z, 15, 0.1);  // the contacts' softness: a fraction of a mm
  EXPECT_NEAR(T.R.m[2][2], 1, 1e-6);
  EXPECT_FALSE(dBodyIsEnabled(sim.object_body(0))) << "resting bodies are put to sleep";
  int started = 0;
  for (const auto& e : sim.events()) started += e.kind == SimEvent::Kind::kContactStarted;
  EXPECT_EQ(started, 1);  // the ground, once
}

// A conveyor belt (issue 53): a static box 1.4 m long whose top face runs at 100 mm/s along its
// x, turned 30 degrees about z. A 25 mm cube dropped on it travels at the belt's speed (within
// 5 %, timed over a metre of its way), neither sinks into it nor sticks to it, and stands still
// once the belt stops; started again, the belt wakes it.
TEST(World, ACubeOnARunningBeltTravelsAtTheBeltsSpeedAndStopsWithIt) {
  Scene s;
  s.ground = true;
  SceneObject belt;
  belt.name = "belt";
  belt.type = SceneObject::Type::kBox;
  belt.size = {1400, 100, 40};
  const double yaw = 30 * M_PI / 180;
  belt.xyz = make_vec3(-200.0, 500.0, 20.0);
  belt.rpy_deg = make_vec3(0.0, 0.0, 30.0);
  belt.belt = 100;
  belt.friction = 0.8;
  s.objects.push_back(belt);
  // the cube near the belt's back end (600 mm behind its centre), just above its top
  const double back = -600;
  s.objects.push_back(box("cube", 25, make_vec3(-200.0 + back * std::cos(yaw), 500.0 + back * std::sin(yaw), 53.0), 0.011));
  Simulation sim(mk2(), s);
  // along the belt's x from its centre, and across
  auto along = [&](const Transform<double>& T) { return (T.p.x + 200) * std::cos(yaw) + (T.p.y - 500) * std::sin(yaw); };
  auto across = [&](const Transform<double>& T) { return -(T.p.x + 200) * std::sin(yaw) + (T.p.y - 500) * std::cos(yaw); };
  double t0 = -1, t1 = -1, lowest = 1e9;
  for (double t = 0.01; t < 14 && t1 < 0; t += 0.01) {
    sim.run_until(t);
    const Transform<double> T = sim.object_pose(1);
    if (t > 1) lowest = std::min(lowest, T.p.z);
    if (t0 < 0 && along(T) >= back + 50) t0 = t;
    if (t1 < 0 && along(T) >= back + 1050) t1 = t;
  }
  ASSERT_GT(t0, 0) << "the cube never moved";
  ASSERT_GT(t1, 0) << "the cube did not travel a metre in 14 s";
  const double speed = 1000 / (t1 - t0);
  std::printf("  belt 100 mm/s: the cube %.2f mm/s over a metre, lowest %.2f mm (its rest 52.5)\n", speed, lowest);
  EXPECT_NEAR(speed, 100, 5) << "mm/s over a metre";
  EXPECT_GT(lowest, 40 + 12.5 - 0.5) << "the cube sank into the belt";
  EXPECT_NEAR(across(sim.object_pose(1)), 0, 2) << "the cube drifted across the belt";
  // stopped: the cube stays where it is (no creep, nothing stuck to a moving surface)
  sim.set_belt(0, 0);
  sim.run_until(sim.time() + 0.5);
  const Transform<double> at_stop = sim.object_pose(1);
  sim.run_until(sim.time() + 2);
  EXPECT_NEAR(along(sim.object_pose(1)), along(at_stop), 0.5) << "the cube moved on a stopped belt";
  // asleep on the stopped belt, then the belt runs backwards: it carries the cube back
  sim.run_until(sim.time() + 3);
  sim.set_belt(0, -100);
  sim.run_until(sim.time() + 2);
  EXPECT_LT(along(sim.object_pose(1)), along(at_stop) - 150) << "a started belt did not wake the cube";
  EXPECT_THROW(sim.set_belt(1, 10), std::invalid_argument);  // the cube is no belt
}

}  // namespace

// A box a drag lets go of: the scene as placed has it there, turned as it was, and a world built
// from that scene starts with it there (the studio's Run starts from where a student put it).
TEST(World, ADraggedBoxStartsTheNextRunWhereItWasLetGo) {
  Scene s;
  s.objects.push_back(box("box", 40, make_vec3(250.0, 0.0, 20.0), 0.05));
  s.objects.push_back(box("other", 40, make_vec3(250.0, 150.0, 20.0), 0.05));
  Simulation sim(mk2(), s);
  sim.run_until(0.2);
  sim.drag_object(0, make_vec3(180.0, -60.0, 25.0));
  sim.run_until(1.7);
  sim.release_drag();
  const Transform<double> let_go = sim.object_pose(0);
  EXPECT_NEAR(let_go.p.x, 180, 5);
  EXPECT_NEAR(let_go.p.y, -60, 5);
  const Scene placed = sim.scene_as_placed();
  EXPECT_NEAR(placed.objects[0].xyz.x, let_go.p.x, 1e-9);
  EXPECT_NEAR(placed.objects[0].xyz.y, let_go.p.y, 1e-9);
  EXPECT_NEAR(placed.objects[0].xyz.z, let_go.p.z, 1e-9);
  EXPECT_EQ(placed.objects[1].xyz.y, 150) << "an object no drag let go of keeps the scene's place";
  Simulation next(mk2(), placed);
  const Transform<double> start = next.object_pose(0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(start.R.m[r][c], let_go.R.m[r][c], 1e-9) << r << c;
  EXPECT_NEAR(start.p.x, let_go.p.x, 1e-9);
  // ... and the scene given stays as it was
  EXPECT_EQ(sim.scene_as_placed().objects.size(), 2u);
  EXPECT_EQ(s.objects[0].xyz.x, 250);
}
