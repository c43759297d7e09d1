// host/lib/stall.cpp - motor torques along a move against the pull-out curves (stall.h,
// docs/stall.md).
#include "stall.h"

#include <articula/motion.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace articula::host {

namespace {

using V = Vec3<double>;

constexpr double kMetresPerMm = 1e-3;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Longest move evaluated at every step; longer ones are sampled every few steps.
constexpr uint32_t kMaxSamples = 20000;

// SI units per model unit of a DH parameter: m per mm for d, 1 for the angles.
double param_si(uint8_t param) { return param == kParamD ? kMetresPerMm : 1.0; }

V zero3() { return make_vec3(0.0, 0.0, 0.0); }

void check_size(const std::vector<double>& v, int n, const char* what) {
  if (int(v.size()) != n)
    throw std::invalid_argument(std::string("StallModel: ") + what + " has " + std::to_string(v.size()) +
                                " values, the robot has " + std::to_string(n) + " joint variables");
}

}  // namespace

double pull_out_torque(const MotorTorque& t, double full_steps_per_s) {
  if (t.pull_out.empty()) return 0;
  const double r = std::fabs(full_steps_per_s);
  const auto& p = t.pull_out;
  if (r <= p.front()[0]) return p.front()[1];
  for (std::size_t k = 1; k < p.size(); ++k) {
    if (r <= p[k][0]) {
      const double s = (r - p[k - 1][0]) / (p[k][0] - p[k - 1][0]);
      return p[k - 1][1] + s * (p[k][1] - p[k - 1][1]);
    }
  }
  return 0;  // beyond the curve: nothing known, nothing promised
}

StallModel::StallModel(const Robot& robot) : robot_(robot) {
  if (!robot.has_motors) throw PredictError(robot.name + ": the robot has no motors: there is nothing to check for stalls");
  n_ = robot.model.num_joints;
  bodies_ = frame_masses(robot);
  for (std::size_t i = 1; i < bodies_.size(); ++i) link_mass_kg_ += bodies_[i].mass;
  robot_.motor_torque.resize(std::size_t(n_));  // a Robot built in code may have none
  for (int j = 0; j < n_; ++j) joint_si_.push_back(param_si(robot.model.joints[j].param));
}

bool StallModel::has_torque_curves() const {
  for (const MotorTorque& t : robot_.motor_torque)
    if (t.given()) return true;
  return false;
}

// Recursive Newton-Euler (Craig 6.5, Featherstone's RNEA) in base coordinates, on the
// elementary motions of each DH row in their order: Rot_x(alpha) about x(i-1) through
// o(i-1), Trans_x(a), Rot_z(theta) about z(i), Trans_z(d) along z(i). Gravity enters as an
// upward acceleration of the base. Outward: angular velocity w, angular acceleration dw and
// the linear acceleration of each frame's origin. Inward: the force f and the moment n
// (about the frame's origin) that frame i and everything after it need; each moving DH
// parameter's generalized force is its axis's component of them.
std::vector<double> StallModel::joint_forces(const std::vector<double>& q, const std::vector<double>& qd,
                                             const std::vector<double>& qdd, double payload_kg) const {
  check_size(q, n_, "q");
  check_size(qd, n_, "qd");
  check_size(qdd, n_, "qdd");
  const HostModel& m = robot_.model;
  const int rows = m.num_rows;
  HostFrames fr;
  forward_kinematics(fr, m, q.data());
  auto origin = [&](int i) { return kMetresPerMm * fr.T_base_frame[i].p; };  // m

  // Rates of every DH parameter, SI, indexed [DhParam][row]: the variables' own, plus the
  // linked ones' (a linked value is offset + sum gain * q, so its rates are sum gain * q').
  double pd[3][kMaxRows] = {}, pdd[3][kMaxRows] = {};
  for (int j = 0; j < n_; ++j) {
    const int k = detail::param_index(m.joints[j].param), row = m.joints[j].row;
    pd[k][row] += joint_si_[j] * qd[j];
    pdd[k][row] += joint_si_[j] * qdd[j];
  }
  for (int l = 0; l < m.num_linked; ++l) {
    const LinkedParam<double, kMaxJoints>& lp = m.linked[l];
    const int k = detail::param_index(lp.param);
    for (int j = 0; j < n_; ++j) {
      pd[k][lp.row] += param_si(lp.param) * lp.gain[j] * qd[j];
      pdd[k][lp.row] += param_si(lp.param) * lp.gain[j] * qdd[j];
    }
  }

  // Outward.
  V w[kMaxRows + 1], dw[kMaxRows + 1], acc[kMaxRows + 1];
  w[0] = dw[0] = zero3();
  acc[0] = make_vec3(0.0, 0.0, kGravity);
  for (int r = 0; r < rows; ++r) {
    const V x = fr.T_base_frame[r].R.col(0), z = fr.T_base_frame[r + 1].R.col(2);
    const double ad = pd[kParamAlpha][r], add = pdd[kParamAlpha][r];
    const double td = pd[kParamTheta][r], tdd = pdd[kParamTheta][r];
    const double dd = pd[kParamD][r], ddd = pdd[kParamD][r];
    // Rot_x(alpha): x(i-1) is fixed in frame i-1.
    const V w1 = w[r] + ad * x;
    const V dw1 = dw[r] + add * x + cross(w[r], ad * x);
    // Trans_x(a): to the point p1 where the row's z axis starts.
    const V o = origin(r), p1 = o + kMetresPerMm * m.rows[r].a * x;
    const V r1 = p1 - o;
    const V a1 = acc[r] + cross(dw1, r1) + cross(w1, cross(w1, r1));
    // Rot_z(theta): z(i) is fixed in the frame after Rot_x(alpha).
    w[r + 1] = w1 + td * z;
    dw[r + 1] = dw1 + tdd * z + cross(w1, td * z);
    // Trans_z(d): slides along z(i), which turns with w(i): the Coriolis term 2 w x d' z.
    const V r2 = origin(r + 1) - p1;
    acc[r + 1] = a1 + cross(dw[r + 1], r2) + cross(w[r + 1], cross(w[r + 1], r2)) + 2.0 * cross(w[r + 1], dd * z) + ddd * z;
  }

  // Inward.
  double Q[3][kMaxRows] = {};  // generalized force of each DH parameter, SI
  V f = zero3(), nm = zero3();  // of frames > i, about o(i+1) until moved
  for (int i = rows; i >= 1; --i) {
    const V o = origin(i);
    if (i < rows) nm = nm + cross(origin(i + 1) - o, f);
    const Mat3<double>& R = fr.T_base_frame[i].R;
    auto add_body = [&](double mass, const V& com_local, const Mat3<double>& I_local) {
      if (!(mass > 0)) return;
      const V rc = R * com_local;
      const V ac = acc[i] + cross(dw[i], rc) + cross(w[i], cross(w[i], rc));
      const V F = mass * ac;
      const Mat3<double> Iw = R * I_local * transpose(R);
      const V N = Iw * dw[i] + cross(w[i], Iw * w[i]);
      f = f + F;
      nm = nm + N + cross(rc, F);
    };
    add_body(bodies_[std::size_t(i)].mass, bodies_[std::size_t(i)].com, bodies_[std::size_t(i)].inertia);
    if (i == rows && payload_kg > 0) {
      const Mat3<double> none = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
      add_body(payload_kg, kMetresPerMm * m.T_last_tool.p, none);
    }
    const int r = i - 1;  // the row that makes frame i
    const V z = R.col(2), x = fr.T_base_frame[r].R.col(0);
    Q[kParamTheta][r] = dot(z, nm);  // about z(i) through o(i) (p1 lies on that axis too)
    Q[kParamD][r] = dot(z, f);
    Q[kParamAlpha][r] = dot(x, nm + cross(o - origin(r), f));  // about x(i-1) through o(i-1)
  }

  // Onto the joint variables by virtual work: tau_j = sum over parameters p of Q_p dp/dq_j
  // (all in SI; dp/dq_j is 1 for the variable's own parameter, the gain for a linked one).
  std::vector<double> tau(std::size_t(n_), 0.0);
  for (int j = 0; j < n_; ++j) tau[std::size_t(j)] = Q[detail::param_index(m.joints[j].param)][m.joints[j].row];
  for (int l = 0; l < m.num_linked; ++l) {
    const LinkedParam<double, kMaxJoints>& lp = m.linked[l];
    const double Qp = Q[detail::param_index(lp.param)][lp.row];
    for (int j = 0; j < n_; ++j) tau[std::size_t(j)] += Qp * param_si(lp.param) * lp.gain[j] / joint_si_[std::size_t(j)];
  }
  return tau;
}

std::vector<double> StallModel::actuator_torques(const std::vector<double>& q, const std::vector<double>& qd,
                                                 const std::vector<double>& qdd, double payload_kg) const {
  const std::vector<double> tq = joint_forces(q, qd, qdd, payload_kg);
  // q_SI = S C u (S: m per mm for the d variables), so tau_u = (S C)^T tau_q.
  std::vector<double> tu(std::size_t(n_), 0.0);
  for (int k = 0; k < n_; ++k)
    for (int i = 0; i < n_; ++i) tu[std::size_t(k)] += robot_.actuation.coupling[i][k] * joint_si_[std::size_t(i)] * tq[std::size_t(i)];
  return tu;
}

std::vector<MotorLoad> StallModel::loads(const std::vector<double>& q, const std::vector<double>& qd,
                                         const std::vector<double>& qdd, double payload_kg) const {
  const std::vector<double> tu = actuator_torques(q, qd, qdd, payload_kg);
  double ud[kMaxJoints], udd[kMaxJoints];
  actuators_from_joints(ud, robot_.actuation, qd.data());
  actuators_from_joints(udd, robot_.actuation, qdd.data());
  std::vector<MotorLoad> out(static_cast<std::size_t>(n_));
  for (int k = 0; k < n_; ++k) {
    const MotorSpec& s = robot_.actuation.motors[k];
    const MotorTorque& t = robot_.motor_torque[std::size_t(k)];
    const double ratio = double(s.gear_num) / double(s.gear_den);  // motor turns per actuator turn
    MotorLoad& l = out[std::size_t(k)];
    l.shaft_nm = tu[std::size_t(k)] / ratio + t.rotor_inertia * ratio * udd[k];
    l.required_nm = std::fabs(l.shaft_nm);
    l.full_steps_per_s = std::fabs(ud[k]) * ratio * s.full_steps_per_rev / (2 * pi<double>());
    l.rated = t.given();
    l.available_nm = l.rated ? pull_out_torque(t, l.full_steps_per_s) : kInf;
  }
  return out;
}

std::vector<MotorLoad> StallModel::holding_loads(const std::vector<double>& q, double payload_kg) const {
  const std::vector<double> none(std::size_t(n_), 0.0);
  return loads(q, none, none, payload_kg);
}

MoveCheck StallModel::check_steps(const std::vector<double>& start_deg, const std::vector<int32_t>& delta_steps,
                                  const ControllerSettings& settings, double payload_kg, double offset_s) const {
  check_size(start_deg, n_, "start_deg");
  if (int(delta_steps.size()) != n_)
    throw std::invalid_argument("StallModel: delta_steps has " + std::to_string(delta_steps.size()) + " values, the robot has " +
                                std::to_string(n_) + " motors");
  uint32_t n = 0;
  for (int32_t d : delta_steps) n = std::max(n, uint32_t(d < 0 ? -int64_t(d) : int64_t(d)));

  // The dominant motor's step intervals, as the controller times them.
  const MotionSettings ms = settings.motion();
  std::vector<uint32_t> c;
  if (n > 0 && validate(ms) == kMotionOk) {
    StepProfile p;
    p.start(n, ms);
    c.reserve(n);
    while (!p.done()) c.push_back(p.next_interval());
  } else {
    n = 0;  // no steps, or settings that time nothing: at rest
  }
  const double f = ms.tick_hz;
  // Step k (0 = the start, n = the end): time, rate (steps/s: around the step, from the two
  // intervals beside it; 0 at both ends) and acceleration (steps/s^2: the set one from rest
  // and into the stop, central differences of the rates between).
  std::vector<double> t(n + 1, 0.0), v(n + 1, 0.0), a(n + 1, 0.0);
  for (uint32_t k = 1; k <= n; ++k) t[k] = t[k - 1] + c[k - 1] / f;
  for (uint32_t k = 1; k < n; ++k) v[k] = 2 * f / (double(c[k - 1]) + double(c[k]));
  if (n > 0) {
    a[0] = ms.accel;
    a[n] = -double(ms.accel);
  }
  for (uint32_t k = 1; k < n; ++k) a[k] = (v[k + 1] - v[k - 1]) / (t[k + 1] - t[k - 1]);

  MoveCheck out;
  out.duration_s = n > 0 ? t[n] : 0;
  out.motors.resize(std::size_t(n_));
  std::vector<double> key(std::size_t(n_), kInf);  // the worst so far: margin, or -required without a curve
  const HostActuation& act = robot_.actuation;
  const uint32_t stride = n > kMaxSamples ? (n + kMaxSamples - 1) / kMaxSamples : 1;
  const std::size_t nj = static_cast<std::size_t>(n_);
  std::vector<double> q(nj), qd(nj), qdd(nj);
  for (uint32_t k = 0;; k = std::min(n, k + stride)) {
    double u[kMaxJoints], ud[kMaxJoints], udd[kMaxJoints];  // rad, rad/s, rad/s^2
    for (int i = 0; i < n_; ++i) {
      const MotorSpec& s = act.motors[i];
      // Degrees per dominant step along the line in step space.
      const double per = n > 0 ? s.direction * double(delta_steps[std::size_t(i)]) / n * degrees_per_step<double>(s) : 0.0;
      u[i] = deg_to_rad(start_deg[std::size_t(i)] + per * k);
      ud[i] = deg_to_rad(per * v[k]);
      udd[i] = deg_to_rad(per * a[k]);
    }
    joints_from_actuators(q.data(), act, u);
    joints_from_actuators(qd.data(), act, ud);
    joints_from_actuators(qdd.data(), act, udd);
    const std::vector<MotorLoad> ls = loads(q, qd, qdd, payload_kg);
    ++out.samples;
    for (int i = 0; i < n_; ++i) {
      const MotorLoad& l = ls[std::size_t(i)];
      MotorCheck& mc = out.motors[std::size_t(i)];
      mc.peak_required_nm = std::max(mc.peak_required_nm, l.required_nm);
      const double kk = l.rated ? l.margin_nm() : -l.required_nm;
      if (kk < key[std::size_t(i)]) {
        key[std::size_t(i)] = kk;
        mc.worst_margin_nm = l.margin_nm();
        mc.at_s = offset_s + t[k];
        mc.at_worst = l;
      }
    }
    if (k == n) break;
  }
  for (MotorCheck& mc : out.motors) {
    mc.skips = mc.at_worst.rated && mc.worst_margin_nm < 0;
    out.skips = out.skips || mc.skips;
  }
  return out;
}

MoveCheck StallModel::check_move(const PredictRecord& before, const PredictRecord& move, const ControllerSettings& settings,
                                 double payload_kg) const {
  const std::size_t n = std::size_t(n_);
  if (before.steps.size() != n || move.steps.size() != n || before.actuator_deg.size() != n || move.actuator_deg.size() != n)
    throw std::invalid_argument("StallModel::check_move: the records do not hold one step count and angle per motor (" +
                                std::to_string(n) + ")");
  if (!move.queued || move.reply != kOk) {
    MoveCheck c = check_steps(move.actuator_deg, std::vector<int32_t>(n, 0), settings, payload_kg);
    c.duration_s = move.seconds();
    return c;
  }
  std::vector<int32_t> delta(n);
  uint32_t dominant = 0;
  for (std::size_t i = 0; i < n; ++i) {
    delta[i] = move.steps[i] - before.steps[i];
    dominant = std::max(dominant, uint32_t(delta[i] < 0 ? -int64_t(delta[i]) : int64_t(delta[i])));
  }
  // What the action spends before its move (H's seek of the switches) comes first.
  const uint64_t profile = profile_duration_ticks(dominant, settings.motion());
  const double offset = move.ticks > profile ? double(move.ticks - profile) / kStepTickHz : 0.0;
  MoveCheck c = check_steps(before.actuator_deg, delta, settings, payload_kg, offset);
  c.duration_s = move.seconds();
  return c;
}

}  // namespace articula::host
