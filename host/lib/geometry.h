// host/lib/geometry.h - the arm's shapes, as the physics collides them and the studio draws
// them: one home for the default capsules of a robot file without link shapes and for where
// the gripper's fingers sit.
#ifndef ARTICULA_HOST_GEOMETRY_H
#define ARTICULA_HOST_GEOMETRY_H

#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

// The robot file's link shapes sorted by frame; for a file without any, a capsule along each
// row's fixed offset (a(i-1) and a constant d(i)) on the frame before it, radius 6 % of the
// arm's reach (5 .. 40 mm), so every robot can be drawn and collide.
std::vector<LinkGeometry> arm_geometry(const Robot& robot);

// Where a mesh shape's file is: relative to the robot file (robots/README.md).
std::string mesh_path(const Robot& robot, const Shape& s);

// A finger of the gripper: a box finger_length x finger_thickness x finger_height (mm) centred
// at this pose, half its length along the tool's x, the opening between the two fingers
// along the tool's y. side: +1 the left finger (+y), -1 the right one.
Transform<double> finger_pose(const Gripper& gripper, const Transform<double>& T_base_tool, double opening_mm, int side);

}  // namespace articula::host

#endif  // ARTICULA_HOST_GEOMETRY_H
