// host/lib/robot_view.h - what the bindings (python/src, wasm/src) ask of a loaded robot
// beyond the kinematics: its description in the robot file's terms (the DH table as the file
// writes it, joint variables, motors, link shapes, gripper) as JSON, a copy with other link
// lengths, and whether a pose is within the limits. One home, so the Python package and the
// web engine describe and check a robot alike. Lengths mm, angles deg.
#ifndef ARTICULA_HOST_ROBOT_VIEW_H
#define ARTICULA_HOST_ROBOT_VIEW_H

#include <nlohmann/json.hpp>

#include <vector>

#include "ik.h"
#include "robot.h"

namespace articula::host {

// The DH table as the robot file writes it, row i holding a(i-1), alpha(i-1), d(i), theta(i):
// a constant, {"joint": name, "min", "max"}, {"linked": {joint: gain}, "offset"}, or for an
// adjustable length a {"value", "min", "max"}.
nlohmann::json dh_rows_json(const Robot& r);
// The joint variables: name, row (1-based), param ("theta", "d", "alpha"), unit, min, max.
nlohmann::json joints_json(const Robot& r);
// The motors (empty for a kinematic robot): name, steps_per_rev, microsteps, gear [num, den],
// direction, zero, min, max (deg), deg_per_step, step_range [min, max], pull_out [[rpm, Nm]...].
nlohmann::json motors_json(const Robot& r);
// The gripper, or null: max_opening_mm, finger_length/thickness/height_mm, servo_open/closed_deg.
nlohmann::json gripper_json(const Robot& r);
// Link shapes per frame (geometry.h): frame, shapes [{type, size, mesh (path), pose (16
// numbers, row-major 4x4, mm), mass, density}].
nlohmann::json links_json(const Robot& r);

// A copy with other lengths a(i-1) for the rows the robot file gives a range, in row order
// (RoboSim's l). Throws std::invalid_argument naming the row for a wrong count or a value out
// of its range.
Robot with_link_lengths(const Robot& r, const std::vector<double>& values);

// Whether q (model units) is within every joint limit and, with motors, every motor limit; a
// value within 1e-9 of a limit (a round trip through degrees) counts as on it.
bool within_limits(const InverseKinematics& ik, const Robot& r, std::vector<double> q);

}  // namespace articula::host

#endif  // ARTICULA_HOST_ROBOT_VIEW_H
