// Tests of host/lib/mass.h: the mass, centre of mass and inertia of the robot file's shapes.
#include "mass.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "robot_file.h"

namespace {

using namespace articula;
using namespace articula::host;

const double kPi = 3.14159265358979323846;

Shape make_shape(Shape::Type type, double s0, double s1 = 0, double s2 = 0) {
  Shape s;
  s.type = type;
  s.size = {s0, s1, s2};
  s.density = kPlaDensity;
  return s;
}

void expect_mat_near(const Mat3<double>& a, const Mat3<double>& b, double tol) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << i << "," << j;
}

TEST(ShapeMass, BoxByFormula) {
  // 100 x 20 x 40 mm of PLA: 8e-5 m^3 -> 0.0992 kg; Ixx = m (0.02^2 + 0.04^2) / 12.
  const MassProperties p = shape_mass(make_shape(Shape::Type::kBox, 100, 20, 40));
  const double m = 1240 * 0.1 * 0.02 * 0.04;
  EXPECT_NEAR(p.mass, m, 1e-15);
  EXPECT_NEAR(p.inertia.m[0][0], m * (0.02 * 0.02 + 0.04 * 0.04) / 12, 1e-15);
  EXPECT_NEAR(p.inertia.m[1][1], m * (0.1 * 0.1 + 0.04 * 0.04) / 12, 1e-15);
  EXPECT_NEAR(p.inertia.m[2][2], m * (0.1 * 0.1 + 0.02 * 0.02) / 12, 1e-15);
  EXPECT_EQ(p.inertia.m[0][1], 0);
  EXPECT_EQ(p.com.x, 0);
}

TEST(ShapeMass, GivenMassWinsOverDensity) {
  Shape s = make_shape(Shape::Type::kSphere, 10);
  s.mass = 0.5;
  s.density = 0;
  const MassProperties p = shape_mass(s);
  EXPECT_EQ(p.mass, 0.5);
  EXPECT_NEAR(p.inertia.m[1][1], 0.4 * 0.5 * 0.01 * 0.01, 1e-16);
}

TEST(ShapeMass, CylinderAndSphereVolumes) {
  const MassProperties c = shape_mass(make_shape(Shape::Type::kCylinder, 10, 50));
  const double mc = 1240 * kPi * 0.01 * 0.01 * 0.05;
  EXPECT_NEAR(c.mass, mc, 1e-15);
  EXPECT_NEAR(c.inertia.m[2][2], mc * 0.01 * 0.01 / 2, 1e-16);
  EXPECT_NEAR(c.inertia.m[0][0], mc * (3 * 0.01 * 0.01 + 0.05 * 0.05) / 12, 1e-16);
  EXPECT_NEAR(shape_volume(make_shape(Shape::Type::kSphere, 30)), 4.0 / 3.0 * kPi * 0.03 * 0.03 * 0.03, 1e-18);
}

// The capsule's inertia by its closed form against a numerical integral over thin discs
// along its axis (a disc of radius rho at height z: Izz = dm rho^2 / 2, Ixx = dm (rho^2/4 + z^2)).
TEST(ShapeMass, CapsuleAgainstSlices) {
  const double r = 0.015, l = 0.06;  // m
  const MassProperties p = shape_mass(make_shape(Shape::Type::kCapsule, r * 1000, l * 1000));
  const int n = 200000;
  const double z0 = -(l / 2 + r), dz = (l + 2 * r) / n;
  double mass = 0, izz = 0, ixx = 0;
  for (int k = 0; k < n; ++k) {
    const double z = z0 + (k + 0.5) * dz;
    const double cap = std::fabs(z) - l / 2;
    const double rho2 = cap > 0 ? r * r - cap * cap : r * r;
    const double dm = 1240 * kPi * rho2 * dz;
    mass += dm;
    izz += dm * rho2 / 2;
    ixx += dm * (rho2 / 4 + z * z);
  }
  EXPECT_NEAR(p.mass, mass, 1e-8 * mass);
  EXPECT_NEAR(p.inertia.m[2][2], izz, 1e-7 * izz);
  EXPECT_NEAR(p.inertia.m[0][0], ixx, 1e-7 * ixx);
  EXPECT_NEAR(p.inertia.m[1][1], ixx, 1e-7 * ixx);
  // Without its cylinder a capsule is a sphere.
  const MassProperties ball = shape_mass(make_shape(Shape::Type::kCapsule, 15, 1e-9));
  const MassProperties sphere = shape_mass(make_shape(Shape::Type::kSphere, 15));
  EXPECT_NEAR(ball.mass, sphere.mass, 1e-12);
  expect_mat_near(ball.inertia, sphere.inertia, 1e-15);
}

TEST(ShapeMass, PoseMovesTheCentreAndTurnsTheInertia) {
  Shape s = make_shape(Shape::Type::kBox, 100, 20, 40);
  const MassProperties plain = shape_mass(s);
  s.T_frame_shape = make_transform(rot_z(kPi / 2), make_vec3(10.0, -20.0, 30.0));
  const MassProperties turned = shape_mass(s);
  EXPECT_NEAR(turned.com.x, 0.010, 1e-15);
  EXPECT_NEAR(turned.com.y, -0.020, 1e-15);
  EXPECT_NEAR(turned.com.z, 0.030, 1e-15);
  // A quarter turn about z exchanges the x and y moments.
  EXPECT_NEAR(turned.inertia.m[0][0], plain.inertia.m[1][1], 1e-15);
  EXPECT_NEAR(turned.inertia.m[1][1], plain.inertia.m[0][0], 1e-15);
  EXPECT_NEAR(turned.inertia.m[2][2], plain.inertia.m[2][2], 1e-15);
  EXPECT_NEAR(turned.inertia.m[0][1], 0, 1e-15);
}

// Two halves side by side are the whole box: the parallel-axis theorem in combine().
TEST(ShapeMass, HalvesCombineIntoTheWhole) {
  Shape left = make_shape(Shape::Type::kBox, 50, 20, 40), right = left;
  left.T_frame_shape.p = make_vec3(-25.0, 0.0, 0.0);
  right.T_frame_shape.p = make_vec3(25.0, 0.0, 0.0);
  const MassProperties both = combine(shape_mass(left), shape_mass(right));
  const MassProperties whole = shape_mass(make_shape(Shape::Type::kBox, 100, 20, 40));
  EXPECT_NEAR(both.mass, whole.mass, 1e-15);
  EXPECT_NEAR(both.com.x, 0, 1e-15);
  expect_mat_near(both.inertia, whole.inertia, 1e-15);
  // Combining with nothing changes nothing.
  const MassProperties same = combine(MassProperties{}, whole);
  expect_mat_near(same.inertia, whole.inertia, 0);
}

TEST(LinkMass, Mk2Frames) {
  const Robot r = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  const std::vector<MassProperties> f = frame_masses(r);
  ASSERT_EQ(f.size(), 5u);
  EXPECT_EQ(f[1].mass, 0);  // nothing attached to frame 1
  // The upper arm: a 135 x 30 x 40 mm box of PLA centred 67.5 mm along x of frame 2.
  EXPECT_NEAR(f[2].mass, 1240 * 0.135 * 0.03 * 0.04, 1e-12);
  EXPECT_NEAR(f[2].com.x, 0.0675, 1e-15);
}

TEST(LinkMass, MeshWithoutMassNamesTheShape) {
  Robot r;
  r.source = "arm.json";
  r.model.num_rows = 1;
  LinkGeometry l;
  l.frame = 1;
  l.shapes.push_back(make_shape(Shape::Type::kBox, 10, 10, 10));
  Shape mesh;
  mesh.type = Shape::Type::kMesh;
  mesh.mesh = "upper.stl";
  mesh.density = kPlaDensity;
  l.shapes.push_back(mesh);
  r.links.push_back(l);
  try {
    link_mass(r, 0);
    FAIL() << "no error";
  } catch (const RobotFileError& e) {
    EXPECT_EQ(e.json_path(), "/links/0/shapes/1");
    EXPECT_EQ(e.file(), "arm.json");
    EXPECT_NE(e.problem().find("needs a \"mass\""), std::string::npos) << e.what();
  }
  // With a mass it is a point at the shape's origin.
  r.links[0].shapes[1].mass = 0.2;
  r.links[0].shapes[1].T_frame_shape.p = make_vec3(100.0, 0.0, 0.0);
  const MassProperties p = link_mass(r, 0);
  const double box = 1240 * 1e-6;
  EXPECT_NEAR(p.mass, 0.2 + box, 1e-15);
  EXPECT_NEAR(p.com.x, 0.2 * 0.1 / (0.2 + box), 1e-15);
}

}  // namespace
