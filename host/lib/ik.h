// host/lib/ik.h - inverse kinematics for any robot file: numeric solvers for any mix of
// theta, d and alpha variables (and linked parameters), and the closed form for
// yaw-pitch-pitch arms. docs/ik.md explains the methods, the statuses and the defaults.
//
// Units as everywhere on the host: millimetres and radians (a d variable in mm), positions
// in the base frame. Joint values in and out are the model's joint variables q, in model
// order. The pose returned always lies within the joint limits, and, for a robot with motors,
// within the motors' limits too (u = C^-1 q).
#ifndef ARTICULA_HOST_IK_H
#define ARTICULA_HOST_IK_H

#include <cstdint>
#include <string>
#include <vector>

#include <articula/ik_ypp.h>

#include "robot.h"

namespace articula::host {

enum class IkMethod {
  kAuto,                // closed form for a recognised yaw-pitch-pitch arm and a position target, else kLm
  kLevenbergMarquardt,  // "lm": damped least squares with limits and seeded random restarts
  kJacobianTranspose,   // "jt": the thesis's dq = h J^T e (section 2.2), limits clamped
  kClosedForm,          // "closed": articula::ypp_solve; only for yaw-pitch-pitch arms
};

enum class IkStatus {
  kReached,      // position error <= tolerance and (full pose) orientation error <= tolerance
  kUnreachable,  // not reached; the best pose is an optimum of the distance that no limit holds
                 // back: the arm stretches (or folds) toward the target. See beyond_reach.
  kLimited,      // not reached; at the best pose a joint (or motor) limit holds the arm back
  kBudget,       // not reached; the iteration or time budget ran out while still improving
};

// "auto", "lm", "jt", "closed" and back; parse returns false for anything else.
const char* ik_method_name(IkMethod m);
bool parse_ik_method(const std::string& text, IkMethod& out);
// "reached", "unreachable", "limited", "budget".
const char* ik_status_name(IkStatus s);

struct IkTarget {
  Vec3<double> position{0, 0, 0};  // tool point, mm, base frame
  bool has_rotation = false;       // false: position only
  Mat3<double> rotation = identity3<double>();  // tool orientation in the base frame

  static IkTarget at(const Vec3<double>& p) {
    IkTarget t;
    t.position = p;
    return t;
  }
  static IkTarget pose(const Transform<double>& T) {
    IkTarget t;
    t.position = T.p;
    t.has_rotation = true;
    t.rotation = T.R;
    return t;
  }
};

struct IkOptions {
  IkMethod method = IkMethod::kAuto;
  double position_tolerance_mm = 0.01;
  double orientation_tolerance_rad = 1e-4;
  // Per joint variable, >= 0: how much each takes part (RoboSim's angle weights); 0 freezes
  // the joint at its start value. Empty: all 1. With a coupling other than the identity (the
  // MK2), the numeric solvers move the motors, and the weights are per motor.
  std::vector<double> weights;
  // Budgets. max_iterations counts solver iterations over all restarts (0: the method's
  // default: lm 1000, jt 2000). time_budget_s > 0 also stops on the wall clock (the result
  // then depends on the machine; leave 0 for reproducible results).
  int max_iterations = 0;
  double time_budget_s = 0;
  // lm: iterations per attempt before a restart, and how many restarts at most.
  int attempt_iterations = 20;
  int max_restarts = 100;
  std::uint64_t seed = 1;  // restarts draw from this seed only: same inputs, same result
  // jt: the gain h of dq = h W J^T e, relative to the robot's size: h = jt_gain / L^2 (L the
  // reach bound, mm), which makes it independent of the units and the robot's scale.
  double jt_gain = 0.5;
  // Full pose: an orientation error of 1 rad weighs as much as this many mm of position
  // error in the numeric solvers' error (0: a quarter of the reach bound).
  double orientation_scale_mm = 0;
};

struct IkResult {
  IkStatus status = IkStatus::kBudget;
  IkMethod method = IkMethod::kAuto;  // the solver that ran (never kAuto)
  std::vector<double> q;              // the best pose found; within the limits
  Transform<double> tool = Transform<double>::identity();  // forward kinematics at q
  double position_error_mm = 0;       // |target - tool.p|
  double orientation_error_rad = 0;   // angle of R_target R_tool^T; 0 for a position target
  int iterations = 0;                 // solver iterations, all attempts together
  int attempts = 0;                   // 1 + restarts
  // The target is provably out of reach: farther from the first joint than the longest the
  // chain can be (the reach bound), or, for the closed form, outside the arm's geometry.
  bool beyond_reach = false;
  // kLimited: the joint variables, and with motors the motors, whose limit holds the arm
  // back at q (the distance would shrink if that limit were not there).
  std::vector<int> limited_joints;
  std::vector<int> limited_motors;

  bool reached() const { return status == IkStatus::kReached; }
};

// A robot prepared for repeated solves (the reach bound, the closed-form arm, the limits
// in the coordinates the solvers move). Cheap to copy; the robot's model is copied in.
class InverseKinematics {
 public:
  explicit InverseKinematics(const Robot& robot);
  explicit InverseKinematics(const HostModel& model);  // no motors

  // Solves from `start` (one value per joint variable; clamped into the limits first, except
  // that a frozen joint (weight 0) outside its limits is an error). Throws std::invalid_argument
  // for a start or weights of the wrong size, a negative or non-finite weight, a start or
  // target that is not finite, a tolerance <= 0, or kClosedForm asked of a robot it does not
  // fit (not a yaw-pitch-pitch arm, or a frozen joint). Thread-safe: const, no shared state.
  IkResult solve(const IkTarget& target, const std::vector<double>& start, const IkOptions& options = {}) const;

  // The closed form applies (a yaw-pitch-pitch arm whose motor limits, if any, it can
  // express: identity or parallelogram coupling).
  bool has_closed_form() const { return has_ypp_; }
  // Longest distance from the reach centre to the tool point any pose could give, mm.
  double reach_bound() const { return reach_; }
  const Vec3<double>& reach_centre() const { return centre_; }
  int num_joints() const { return n_; }
  const HostModel& model() const { return model_; }

  // Whether q lies within every limit: the joint limits exactly, and for a robot with
  // motors the motor limits of u = C^-1 q (up to 1e-9 of rounding in the product).
  bool within_all_limits(const std::vector<double>& q) const;

  struct Impl;  // the solvers, in ik.cpp

 private:
  void prepare(const Robot* robot);

  HostModel model_{};
  int n_ = 0;
  bool coupled_ = false;  // solvers move motor angles u, q = C u
  double C_[kMaxJoints][kMaxJoints]{};
  double Cinv_[kMaxJoints][kMaxJoints]{};
  double xlo_[kMaxJoints]{}, xhi_[kMaxJoints]{};  // box in solver coordinates
  double qlo_[kMaxJoints]{}, qhi_[kMaxJoints]{};  // joint limits
  bool has_ypp_ = false;
  YppArm<double> ypp_{};
  double reach_ = 0;
  Vec3<double> centre_{0, 0, 0};
};

// One-shot convenience: InverseKinematics(robot).solve(target, start, options).
IkResult solve_ik(const Robot& robot, const IkTarget& target, const std::vector<double>& start,
                  const IkOptions& options = {});

// The rotation vector (axis * angle, rad) of R_target R_current^T: the rotation that takes
// the current orientation to the target's, in the base frame. Exact at every angle up to pi.
Vec3<double> orientation_error(const Mat3<double>& R_target, const Mat3<double>& R_current);

}  // namespace articula::host

#endif  // ARTICULA_HOST_IK_H
