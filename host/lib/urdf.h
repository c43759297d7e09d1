// host/lib/urdf.h - a robot as URDF, for ROS tools (RViz, robot_state_publisher, MoveIt).
#ifndef ARTICULA_HOST_URDF_H
#define ARTICULA_HOST_URDF_H

#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

struct UrdfExport {
  std::string xml;
  std::vector<std::string> notes;  // what URDF expresses differently, for the user
};

// Each DH row becomes its elementary transforms, Rot_x(alpha) Trans_x(a) Rot_z(theta)
// Trans_z(d): constant ones merge into the origin of the next joint, each joint variable
// becomes a revolute (theta about z, alpha about x) or prismatic (d along z) joint, and a
// linked parameter becomes one mimic joint per joint it follows, in series about the same
// axis (a sum of rotations about one axis is the rotation by the sum), so the MK2's
// level-keeping row is exact. Frames are links "frame_<i>", the tool "tool". Metres,
// radians; link shapes become visuals.
UrdfExport export_urdf(const Robot& robot);

}  // namespace articula::host

#endif  // ARTICULA_HOST_URDF_H
