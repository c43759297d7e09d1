// host/lib/stall.h - will the steppers keep up? The torque each motor must supply along a
// move against its pull-out torque at the step rate it runs at (docs/stall.md).
//
// The model, in short:
//   - joint forces by recursive Newton-Euler on the modified-DH chain (gravity 9.81 m/s^2
//     along -z of the base frame, the links' mass and inertia from their shapes (mass.h),
//     a payload as a point mass at the tool point), computed for every DH parameter that
//     moves (theta: a torque about z, d: a force along z, alpha: a torque about x) and
//     gathered onto the joint variables by virtual work, tau_q = G^T tau_p: a linked
//     parameter (the MK2's theta4 = -(q2 + q3)) passes its share to the joints it follows;
//   - through the coupling (q = C u): tau_u = C^T tau_q at the gears' outputs;
//   - at the motor shaft: tau_u / ratio + rotor_inertia * ratio * u'' (ratio = gear
//     num / den, motor turns per actuator turn); no friction, no gear losses;
//   - against the pull-out curve (robot.h MotorTorque) at the motor's full-step rate.
// Along a queued move the motors' rates and accelerations come from the controller's own
// step timing (motion.h StepProfile, the dominant motor; the others in proportion).
//
// Units: q, qd, qdd as robot.h keeps joint values (rad or mm, per second and second^2);
// torques N*m, forces N, masses kg.
#ifndef ARTICULA_HOST_STALL_H
#define ARTICULA_HOST_STALL_H

#include <cstdint>
#include <vector>

#include "mass.h"
#include "predict.h"
#include "robot.h"

namespace articula::host {

inline constexpr double kGravity = 9.81;  // m/s^2, along -z of the base frame

// The pull-out torque of a curve at a full-step rate (the sign of the rate ignored): linear
// between points, 0 beyond the last. N*m.
double pull_out_torque(const MotorTorque& t, double full_steps_per_s);

// One motor at one instant.
struct MotorLoad {
  double required_nm = 0;       // |torque| the motor shaft must supply, N*m
  double available_nm = 0;      // pull-out torque at this rate; +infinity for a motor without a curve
  double full_steps_per_s = 0;  // |rate|, full steps/s
  double shaft_nm = 0;          // signed: positive turns the actuator towards larger angles
  bool rated = false;           // the motor has a pull-out curve

  double margin_nm() const { return available_nm - required_nm; }
  bool skips() const { return rated && required_nm > available_nm; }
};

// One motor over a whole move.
struct MotorCheck {
  double worst_margin_nm = 0;  // least (available - required) over the move
  double at_s = 0;             // where, seconds from the start of the move
  MotorLoad at_worst;          // the load there
  double peak_required_nm = 0;
  bool skips = false;  // a rated motor whose margin goes below 0
};

struct MoveCheck {
  bool skips = false;      // some motor skips
  double duration_s = 0;   // of the move (the action's whole duration)
  int samples = 0;         // instants evaluated
  std::vector<MotorCheck> motors;
};

class StallModel {
 public:
  // Throws PredictError for a robot without motors, RobotFileError for a link whose mass
  // cannot be known (a mesh shape without "mass").
  explicit StallModel(const Robot& robot);

  // Some motor has a pull-out curve (else nothing can skip: available is +infinity).
  bool has_torque_curves() const;
  // The links have mass (else only payload and rotors load the motors).
  double total_link_mass_kg() const { return link_mass_kg_; }

  // Generalized forces per joint variable (N*m for an angle, N for a d), with the payload
  // (kg) at the tool point. Sizes: one per joint variable.
  std::vector<double> joint_forces(const std::vector<double>& q, const std::vector<double>& qd,
                                   const std::vector<double>& qdd, double payload_kg) const;
  // The same at the gears' outputs, per motor (tau_u = C^T tau_q), N*m.
  std::vector<double> actuator_torques(const std::vector<double>& q, const std::vector<double>& qd,
                                       const std::vector<double>& qdd, double payload_kg) const;
  // Per motor: shaft torque, rate and pull-out torque. qd and qdd give the motors' rates
  // and accelerations through C^-1.
  std::vector<MotorLoad> loads(const std::vector<double>& q, const std::vector<double>& qd,
                               const std::vector<double>& qdd, double payload_kg) const;
  // The static loads (at rest) at q.
  std::vector<MotorLoad> holding_loads(const std::vector<double>& q, double payload_kg) const;

  // A move of the controller from `start_deg` (actuator angles the steps give, degrees, per
  // motor) by `delta_steps` (per motor), timed by the controller with `settings`, sampled
  // at every step of the dominant motor (its rate and acceleration from the real step
  // times, the others in proportion, positions interpolated along the line in step
  // space). `offset_s` is added to every time reported (a homing seek before the move).
  // No steps: the static load at start_deg.
  MoveCheck check_steps(const std::vector<double>& start_deg, const std::vector<int32_t>& delta_steps,
                        const ControllerSettings& settings, double payload_kg, double offset_s = 0) const;

  // A queued move of the controller (predict.h): from the state `before` (the record of the
  // statement before it) to `move`'s; per motor the worst margin, where and whether it
  // skips. An action that moves no motor (a gripper action) is checked at rest.
  MoveCheck check_move(const PredictRecord& before, const PredictRecord& move, const ControllerSettings& settings,
                       double payload_kg) const;

 private:
  Robot robot_;
  int n_ = 0;                           // joint variables = motors
  std::vector<MassProperties> bodies_;  // per frame 0..rows, in the frame, SI
  double link_mass_kg_ = 0;
  std::vector<double> joint_si_;        // per joint: 1 (angle) or 1e-3 (mm to m)
};

}  // namespace articula::host

#endif  // ARTICULA_HOST_STALL_H
