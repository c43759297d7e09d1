// host/physics/world_detail.h - what the world, its arms' bodies and their drivers share inside
// the physics (not for the library's users): units, contact limits, ODE conversions.
#ifndef ARTICULA_PHYSICS_WORLD_DETAIL_H
#define ARTICULA_PHYSICS_WORLD_DETAIL_H

#include <ode/ode.h>

#include <string>

#include "robot.h"

namespace articula::host::detail {

constexpr double kMm = 0.001;  // mm -> m
constexpr int kMaxContacts = 4;
// A mesh against the ground gives its vertices below it in file order, not the deepest first:
// the step check asks for more of them.
constexpr int kMaxMeshContacts = 32;
constexpr double kArmFriction = 0.6;
constexpr double kFingerFriction = 1.0;

void init_ode();
void to_ode(const Mat3<double>& R, dMatrix3 out);
Mat3<double> from_ode(const dReal* R);
Transform<double> inverse(const Transform<double>& T);
bool aabb_overlap(dGeomID a, dGeomID b);
// The rotation R_new R_old^T as a rotation vector (axis * angle), rad.
Vec3<double> rotation_vector(const Mat3<double>& R_new, const Mat3<double>& R_old);
// A distance in an event's message ("the gripper hit the cube 3.2 mm above the table"): one
// decimal, what the physics' own accuracy supports (not a protocol number).
std::string fmt_mm(double v);
inline bool is_mesh(dGeomID g) { return dGeomGetClass(g) == dTriMeshClass; }
// A body placed at a pose given in mm.
void set_body_pose(dBodyID body, const Transform<double>& T_mm);

}  // namespace articula::host::detail

#endif  // ARTICULA_PHYSICS_WORLD_DETAIL_H
