// host/lib/robot_view.h - the layer under both bindings (python/src, wasm/src) for a loaded
// robot: units at the door (joint values in deg or mm outside, model units inside), the
// checks of what comes in (with one wording of every error), IK targets and options, motors
// to joints and back, the DH table at a pose, and the robot's description in the robot file's
// terms (the DH table as the file writes it, joint variables, motors, link shapes, gripper)
// as JSON. One home, so the Python package and the web engine read, check and describe a robot
// alike; the bindings only convert their languages' values. Lengths mm, angles deg.
#ifndef ARTICULA_HOST_ROBOT_VIEW_H
#define ARTICULA_HOST_ROBOT_VIEW_H

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ik.h"
#include "robot.h"

namespace articula::host {

// A transform as 16 numbers, a row-major 4x4 (mm): how poses cross into JSON.
nlohmann::json transform_json(const Transform<double>& T);
// Every frame of a pose: the base, one a DH row, the tool.
nlohmann::json frames_json(const Robot& r, const HostFrames& frames);

// The DH table as the robot file writes it, row i holding a(i-1), alpha(i-1), d(i), theta(i):
// a constant, {"joint": name, "min", "max"}, {"linked": {joint: gain}, "offset"}, or for an
// adjustable length a {"value", "min", "max"}.
nlohmann::json dh_rows_json(const Robot& r);
// The joint variables: name, row (1-based), param ("theta", "d", "alpha"), unit, min, max.
nlohmann::json joints_json(const Robot& r);
// The motors (empty for a kinematic robot): name, steps_per_rev, microsteps, gear [num, den],
// direction, zero, min, max (deg), deg_per_step, step_range [min, max], pull_out [[rpm, Nm]...],
// driver (the robot file's, robots/README.md "Drive": kind, and chip or pin, pulse, at, speed, accel).
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

// ---- units and checks (std::invalid_argument with the message the user sees)

// Joint values from an interface (deg or mm, one per joint variable) into model units: a
// wrong count, a NaN or an infinity is refused naming `what` and the joint.
std::vector<double> joints_in(const Robot& r, const double* values, size_t count, const char* what);
// The same into q_model[0..num_joints) (no allocation: the bindings' hot paths).
void joints_in(const Robot& r, const double* values, size_t count, const char* what, double* q_model);
inline std::vector<double> joints_in(const Robot& r, const std::vector<double>& v, const char* what) {
  return joints_in(r, v.data(), v.size(), what);
}
// Model units out to deg or mm.
std::vector<double> joints_out(const Robot& r, const double* q_model);
// Finite numbers of any count (targets, weights, lengths): "what[i] must be a finite number".
void check_finite(const double* values, size_t count, const char* what);
// Each joint variable's [min, max] and the home pose, deg or mm.
std::vector<std::array<double, 2>> joint_limits(const Robot& r);
std::vector<double> home_pose(const Robot& r);
// Where the arm is at power-up, deg or mm: every motor at step 0 (its zero angle); without
// motors, the home pose.
std::vector<double> power_up_pose(const Robot& r);

// Motor angles (deg, at the gears' outputs) to joint values (deg or mm), q = C u, and back.
// Refused for a robot without motors, or the wrong count.
std::vector<double> joints_from_motors(const Robot& r, const std::vector<double>& motor_deg);
std::vector<double> motors_from_joints(const Robot& r, const std::vector<double>& q_model);

// The DH table at q (model units), a row each: a(i-1) mm, alpha(i-1) deg, d(i) mm, theta(i) deg.
std::vector<std::array<double, 4>> dh_table_at(const Robot& r, const double* q_model);

// The geometric Jacobian of the tool point at q (model units), 6 x num_joints row-major, per
// unit of q as the interfaces give it (deg or mm): rows 0-2 the tool's velocity (mm per deg,
// or mm per mm), rows 3-5 its rotation (deg per deg, or deg per mm).
std::vector<double> jacobian_at(const Robot& r, const double* q_model);
// The same from frames already computed at q, into out[0 .. 6 * num_joints).
void jacobian_at(const Robot& r, const HostFrames& frames, double* out);

// ---- IK requests

// (x, y, z) mm, or (x, y, z, roll, pitch, yaw) mm and deg.
IkTarget ik_target(const double* values, size_t count);
// A 4x4 homogeneous matrix, row-major, mm.
IkTarget ik_target_pose(const double* m16);
// solver: auto, closed, lm or jt; weights (none: all 1); tolerance_mm > 0; max_iterations >= 0
// (0: the solver's default); seed for restarts.
IkOptions ik_options(const std::string& solver, const std::vector<double>* weights, double tolerance_mm,
                     int max_iterations, uint64_t seed);
// Where a solve starts: `start` (deg or mm) or the home pose; model units.
std::vector<double> ik_start(const Robot& r, const std::vector<double>* start);
// Why a solve did not reach its target, in words a student reads ("" when it did): what holds
// the tool back (the point farther than the arm is long, the arm's shape, or each joint and
// motor at the end of its range, where it stands and its range: "held back by the shoulder
// motor at 30.0° (its range 30° to 135°)"), then how near it comes. The blocks and the IK
// panel say it alike (ik_result_json's "why").
std::string ik_miss_words(const Robot& r, const IkResult& res);

}  // namespace articula::host

#endif  // ARTICULA_HOST_ROBOT_VIEW_H
