// Tests host/physics/sim.h's world against physics: free fall, a pendulum's period, a box at rest.
#include <gtest/gtest.h>

#include <cmath>

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
