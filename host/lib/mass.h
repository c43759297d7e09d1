// host/lib/mass.h - mass, centre of mass and inertia of a link from the shapes of the robot
// file (robots/README.md, "Links and shapes").
//
// Each shape is a solid of uniform density: its given `mass`, or its volume times `density`
// (1240 kg/m^3, PLA, by default). A body's properties are the sum of its shapes' by the
// parallel-axis theorem. Units: the robot file's shapes are in mm, but what comes out here is
// SI (kg, m, kg*m^2), what physics works in; positions are in the frame the shapes are
// attached to.
//
// A mesh shape has no size here (the file names a mesh the host does not read), so it needs
// an explicit `mass`: that mass is taken as a point at the shape's origin (no inertia of its
// own). A mesh without `mass` is an error that says so.
#ifndef ARTICULA_HOST_MASS_H
#define ARTICULA_HOST_MASS_H

#include <articula/transform.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

inline constexpr double kPlaDensity = 1240.0;  // kg/m^3, the robot file's default

// The mass properties of a rigid body in some frame.
struct MassProperties {
  double mass = 0;                                               // kg
  Vec3<double> com{0, 0, 0};                                     // centre of mass in the frame, m
  Mat3<double> inertia{{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};       // about the com, frame axes, kg*m^2
};

// A shape whose mass cannot be known (a mesh without "mass"): what() says why.
class MassError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Volume of a primitive shape in m^3 (box, cylinder, capsule, sphere). Throws MassError for
// a mesh.
double shape_volume(const Shape& s);

// One shape's properties in the frame it is attached to (its pose T_frame_shape applied).
// Throws MassError for a mesh without a mass.
MassProperties shape_mass(const Shape& s);

// The body made of a and b (both in the same frame).
MassProperties combine(const MassProperties& a, const MassProperties& b);

// The properties of a body given in frame b, expressed in frame a: T_a_b in the robot file's
// units (mm, the core's Transform).
MassProperties transformed(const Transform<double>& T_a_b, const MassProperties& m);

// Every shape of robot.links[link] together, in the frame they are attached to. Throws
// RobotFileError (robot_file.h) naming the robot's file and the shape's JSON pointer
// (/links/i/shapes/k) for a mesh without a mass.
MassProperties link_mass(const Robot& robot, int link);

// Per frame 0 .. num_rows (0 = the base): the sum of all links attached to it. Frames
// without shapes have mass 0. Throws like link_mass.
std::vector<MassProperties> frame_masses(const Robot& robot);

}  // namespace articula::host

#endif  // ARTICULA_HOST_MASS_H
