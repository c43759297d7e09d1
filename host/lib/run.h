// host/lib/run.h - runs a program (program.h) on the kinematic model: ideal joint values, no
// motor steps, no timing. What `articula run` prints; `predict` (predict.h) is the real arm.
//
// The state is the joint variables q. RoboSim statements act as in the thesis's simulator:
// m sets q, a solves the inverse kinematics (ik.h, with w's weights) from the current pose
// and moves to the best pose found whether or not it reaches the target (the status and the
// distance say how it went), l changes link lengths, h the gripper; s and z are recorded.
// Protocol lines (docs/protocol.md) work on exact commanded angles: L and M as the
// controller checks them (a target beyond a limit is refused, error:9, and nothing moves),
// P through ik.h (refused with error:10 unless reached), H, Z, G, S, $ as documented, without
// rounding to steps. For a robot with motors L and M address actuators (q = C u); for one
// without, they address the joint variables (deg, or mm for a d variable).
#ifndef ARTICULA_HOST_RUN_H
#define ARTICULA_HOST_RUN_H

#include <articula/status.h>

#include <optional>
#include <string>
#include <vector>

#include "ik.h"
#include "predict.h"
#include "program.h"
#include "robot.h"

namespace articula::host {

struct RunRecord {
  int line = 0;
  std::string text;  // the statement as written (RoboSim: "a 200 0 150")
  Status reply = kOk;
  std::string note;

  std::vector<double> joints;                              // joint variables after the statement, deg or mm
  Transform<double> tool = Transform<double>::identity();  // tool pose, mm
  Vec3<double> rpy_deg{0, 0, 0};                           // its roll, pitch, yaw (fixed X-Y-Z), deg
  int gripper_percent = -1;                                // -1: no gripper command yet
  double dwell_s = 0;                                      // D: how long the line waits

  bool has_target = false;  // RoboSim a, protocol P, T
  Vec3<double> target{0, 0, 0};
  // T: the line's segments (articula/line.h through the robot's IK), each end's joint values
  // (deg or mm) and its distance along the line (mm); the line's length and speed.
  std::vector<std::vector<double>> via_joints;
  std::vector<double> via_mm;
  double line_length_mm = 0, line_speed = 0;
  std::string ik_status;       // ik.h's status name
  double target_error_mm = 0;  // |tool - target|
};

class KinematicModel {
 public:
  // Starts at the robot's home pose, or for a robot with motors at its motors' zero angles
  // (where the real arm powers up; the MK2's home).
  explicit KinematicModel(const Robot& robot);

  RunRecord execute(const Statement& st);
  RunRecord execute_line(const std::string& line, int line_number = 0);

  const std::vector<double>& q() const { return q_; }  // model units (rad, mm)
  const Robot& robot() const { return robot_; }

 private:
  void finish(RunRecord& r) const;
  Status run_command(RunRecord& r, const std::string& text);
  void robosim(RunRecord& r, const Statement& st);
  void q_from_commanded();
  void commanded_from_q();
  Status set_commanded(const std::vector<int64_t>& target);
  Status line(RunRecord& r, const int32_t* arg);
  // The joint values (model units) of commanded thousandths, and back; limits checked by
  // set_commanded only.
  std::vector<double> q_of(const int64_t* thousandths) const;
  std::vector<int64_t> thousandths_of(const double* q) const;
  friend struct RunLineSolver;
  IkResult solve(const Vec3<double>& target, RunRecord& r);

  Robot robot_;
  int n_ = 0;  // actuators (robot with motors) or joint variables
  bool motors_ = false;
  std::vector<double> q_;
  // Protocol state: exact commanded values in thousandths (actuator degrees, or joint
  // degrees / mm without motors), and what Z shifted them by.
  std::vector<int64_t> commanded_;
  std::vector<int64_t> offset_;
  ControllerSettings settings_;
  int gripper_percent_ = -1;
  std::vector<double> weights_;
  std::optional<InverseKinematics> ik_;
};

// Runs a whole program.
std::vector<RunRecord> run_program(const Robot& robot, const Program& program);

}  // namespace articula::host

#endif  // ARTICULA_HOST_RUN_H
