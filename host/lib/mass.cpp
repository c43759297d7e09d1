// host/lib/mass.cpp - mass properties of shapes and links (mass.h).
//
// Inertia of the primitives about their centre, in the shape's own axes (the cylinder's
// and the capsule's axis is z; r radius, l length, m mass):
//   box a x b x c:  m/12 (b^2 + c^2, a^2 + c^2, a^2 + b^2)
//   cylinder:       Izz = m r^2 / 2,  Ixx = Iyy = m (3 r^2 + l^2) / 12
//   sphere:         2/5 m r^2
//   capsule (a cylinder of length l, mass mc, and two hemispheres of radius r, together a
//   sphere of mass ms): Izz = mc r^2/2 + 2/5 ms r^2, Ixx = mc (3 r^2 + l^2)/12 +
//   ms (2/5 r^2 + l^2/4 + 3 l r / 8) (each hemisphere about its own centre of mass,
//   3r/8 from its flat face, is 83/320 (ms/2) r^2; moved to the capsule's centre by the
//   parallel-axis theorem). The capsule's `length` is its cylinder's, without the caps,
//   as ODE's dCreateCapsule takes it.
#include "mass.h"

#include <cmath>

#include "robot_file.h"

namespace articula::host {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMm = 1e-3;  // m per mm

Mat3<double> diagonal(double x, double y, double z) { return {{{x, 0, 0}, {0, y, 0}, {0, 0, z}}}; }

Mat3<double> add(const Mat3<double>& a, const Mat3<double>& b) {
  Mat3<double> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][j] + b.m[i][j];
  return r;
}

// The inertia a point mass m at offset d adds about the origin: m (|d|^2 E - d d^T).
Mat3<double> parallel_axis(double m, const Vec3<double>& d) {
  const double d2 = dot(d, d);
  Mat3<double> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = m * ((i == j ? d2 : 0.0) - d[i] * d[j]);
  return r;
}

double density_of(const Shape& s) { return s.density > 0 ? s.density : kPlaDensity; }

}  // namespace

double shape_volume(const Shape& s) {
  const double a = s.size[0] * kMm, b = s.size[1] * kMm, c = s.size[2] * kMm;
  switch (s.type) {
    case Shape::Type::kBox: return a * b * c;
    case Shape::Type::kCylinder: return kPi * a * a * b;
    case Shape::Type::kCapsule: return kPi * a * a * b + 4.0 / 3.0 * kPi * a * a * a;
    case Shape::Type::kSphere: return 4.0 / 3.0 * kPi * a * a * a;
    case Shape::Type::kMesh: break;
  }
  throw MassError("the volume of a mesh is not computed: give the shape a \"mass\"");
}

MassProperties shape_mass(const Shape& s) {
  MassProperties local;  // about the shape's centre, its own axes
  if (s.type == Shape::Type::kMesh) {
    if (!(s.mass > 0))
      throw MassError("a mesh shape needs a \"mass\" (kg): the mesh's volume is not computed, so its density cannot be used");
    local.mass = s.mass;  // a point at the shape's origin
  } else {
    const double m = s.mass > 0 ? s.mass : density_of(s) * shape_volume(s);
    const double a = s.size[0] * kMm, b = s.size[1] * kMm, c = s.size[2] * kMm;
    local.mass = m;
    switch (s.type) {
      case Shape::Type::kBox:
        local.inertia = diagonal(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12);
        break;
      case Shape::Type::kCylinder: {
        const double across = m * (3 * a * a + b * b) / 12;
        local.inertia = diagonal(across, across, m * a * a / 2);
        break;
      }
      case Shape::Type::kSphere: local.inertia = diagonal(0.4 * m * a * a, 0.4 * m * a * a, 0.4 * m * a * a); break;
      case Shape::Type::kCapsule: {
        const double r = a, l = b;
        const double vc = kPi * r * r * l, vs = 4.0 / 3.0 * kPi * r * r * r;
        const double mc = m * vc / (vc + vs), ms = m * vs / (vc + vs);  // split by volume
        const double axial = mc * r * r / 2 + 0.4 * ms * r * r;
        const double across = mc * (3 * r * r + l * l) / 12 + ms * (0.4 * r * r + l * l / 4 + 3 * l * r / 8);
        local.inertia = diagonal(across, across, axial);
        break;
      }
      case Shape::Type::kMesh: break;
    }
  }
  return transformed(s.T_frame_shape, local);
}

MassProperties combine(const MassProperties& a, const MassProperties& b) {
  MassProperties r;
  r.mass = a.mass + b.mass;
  if (!(r.mass > 0)) return r;
  r.com = (1.0 / r.mass) * (a.mass * a.com + b.mass * b.com);
  r.inertia = add(add(a.inertia, parallel_axis(a.mass, a.com - r.com)), add(b.inertia, parallel_axis(b.mass, b.com - r.com)));
  return r;
}

MassProperties transformed(const Transform<double>& T_a_b, const MassProperties& m) {
  MassProperties r;
  r.mass = m.mass;
  r.com = T_a_b.R * m.com + kMm * T_a_b.p;
  r.inertia = T_a_b.R * m.inertia * transpose(T_a_b.R);
  return r;
}

MassProperties link_mass(const Robot& robot, int link) {
  const LinkGeometry& l = robot.links.at(std::size_t(link));
  MassProperties total;
  for (std::size_t k = 0; k < l.shapes.size(); ++k) {
    try {
      total = combine(total, shape_mass(l.shapes[k]));
    } catch (const MassError& e) {
      throw RobotFileError(robot.source, "/links/" + std::to_string(link) + "/shapes/" + std::to_string(k), e.what());
    }
  }
  return total;
}

std::vector<MassProperties> frame_masses(const Robot& robot) {
  std::vector<MassProperties> out(std::size_t(robot.model.num_rows) + 1);
  for (std::size_t i = 0; i < robot.links.size(); ++i) {
    const int f = robot.links[i].frame;
    if (f < 0 || f >= int(out.size())) continue;  // the loader never lets this happen
    out[std::size_t(f)] = combine(out[std::size_t(f)], link_mass(robot, int(i)));
  }
  return out;
}

}  // namespace articula::host
