// host/lib/ik.cpp - the inverse kinematics solvers of ik.h. docs/ik.md describes them.
//
// The numeric solvers work in "solver coordinates" x: the joint variables q, or, for a
// robot whose motors drive the joints through a coupling other than the identity (the MK2's
// parallelogram), the motor angles u with q = C u. Then every limit the real arm has is a
// box on x (the motor limits, narrowed by the joint limits of coordinates that are joint
// variables too) plus, only for unusual couplings, linear limits on q = C x, which a step
// respects by being shortened.
#include "ik.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace articula::host {

const char* ik_method_name(IkMethod m) {
  switch (m) {
    case IkMethod::kAuto: return "auto";
    case IkMethod::kLevenbergMarquardt: return "lm";
    case IkMethod::kJacobianTranspose: return "jt";
    case IkMethod::kClosedForm: return "closed";
  }
  return "?";
}

bool parse_ik_method(const std::string& text, IkMethod& out) {
  for (IkMethod m :
       {IkMethod::kAuto, IkMethod::kLevenbergMarquardt, IkMethod::kJacobianTranspose, IkMethod::kClosedForm})
    if (text == ik_method_name(m)) {
      out = m;
      return true;
    }
  return false;
}

const char* ik_status_name(IkStatus s) {
  switch (s) {
    case IkStatus::kReached: return "reached";
    case IkStatus::kUnreachable: return "unreachable";
    case IkStatus::kLimited: return "limited";
    case IkStatus::kBudget: return "budget";
  }
  return "?";
}

Vec3<double> orientation_error(const Mat3<double>& Rt, const Mat3<double>& Rc) {
  // R = Rt Rc^T; its rotation vector. sin(angle) * axis is the skew part, cos(angle) comes
  // from the trace: atan2 of the two is accurate at every angle.
  const Mat3<double> R = Rt * transpose(Rc);
  const Vec3<double> v =
      make_vec3((R.m[2][1] - R.m[1][2]) / 2, (R.m[0][2] - R.m[2][0]) / 2, (R.m[1][0] - R.m[0][1]) / 2);
  const double s = norm(v);
  const double c = (R.m[0][0] + R.m[1][1] + R.m[2][2] - 1) / 2;
  const double angle = std::atan2(s, c);
  if (s > 1e-7) return (angle / s) * v;
  if (c > 0) return v;  // angle ~ 0: the rotation vector is the skew part itself
  // angle ~ pi: R ~ 2 a a^T - I, the axis from the largest diagonal entry of (R + I) / 2.
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (R.m[i][i] > R.m[k][k]) k = i;
  Vec3<double> a;
  for (int i = 0; i < 3; ++i) a[i] = (R.m[i][k] + R.m[k][i]) / 2 + (i == k ? 1.0 : 0.0);
  a = (1 / norm(a)) * a;
  if (dot(a, v) < 0) a = -1.0 * a;
  return angle * a;
}

// ---------------------------------------------------------------------------------------
// Preparation

InverseKinematics::InverseKinematics(const Robot& robot) : model_(robot.model) { prepare(&robot); }

InverseKinematics::InverseKinematics(const HostModel& model) : model_(model) { prepare(nullptr); }

namespace {
double deg_millideg_to_rad(int32_t millideg) { return deg_to_rad(double(millideg) / 1000.0); }

// Largest |value| a DH parameter slot can take: constant, joint variable, or linked.
double max_abs_param(const HostModel& m, int row, uint8_t param) {
  for (int j = 0; j < m.num_joints; ++j)
    if (m.joints[j].row == row && m.joints[j].param == param)
      return std::max(std::fabs(m.joints[j].lo), std::fabs(m.joints[j].hi));
  for (int k = 0; k < m.num_linked; ++k)
    if (m.linked[k].row == row && m.linked[k].param == param) {
      double v = std::fabs(m.linked[k].offset);
      for (int j = 0; j < m.num_joints; ++j)
        v += std::fabs(m.linked[k].gain[j]) * std::max(std::fabs(m.joints[j].lo), std::fabs(m.joints[j].hi));
      return v;
    }
  const DhRow<double>& r = m.rows[row];
  return std::fabs(param == kParamD ? r.d : (param == kParamTheta ? r.theta : r.alpha));
}

bool param_is_constant(const HostModel& m, int row, uint8_t param) {
  for (int j = 0; j < m.num_joints; ++j)
    if (m.joints[j].row == row && m.joints[j].param == param) return false;
  for (int k = 0; k < m.num_linked; ++k)
    if (m.linked[k].row == row && m.linked[k].param == param) return false;
  return true;
}
}  // namespace

void InverseKinematics::prepare(const Robot* robot) {
  n_ = model_.num_joints;
  for (int j = 0; j < n_; ++j) {
    qlo_[j] = xlo_[j] = model_.joints[j].lo;
    qhi_[j] = xhi_[j] = model_.joints[j].hi;
    for (int k = 0; k < n_; ++k) C_[j][k] = Cinv_[j][k] = j == k ? 1.0 : 0.0;
  }
  const bool motors = robot && robot->has_motors && robot->actuation.num_motors == n_;
  if (motors) {
    const HostActuation& a = robot->actuation;
    bool identity = true;
    for (int j = 0; j < n_; ++j)
      for (int k = 0; k < n_; ++k) {
        C_[j][k] = a.coupling[j][k];
        Cinv_[j][k] = a.coupling_inv[j][k];
        identity = identity && a.coupling[j][k] == (j == k ? 1.0 : 0.0);
      }
    coupled_ = !identity;
    for (int k = 0; k < n_; ++k) {
      const double lo = deg_millideg_to_rad(a.motors[k].min), hi = deg_millideg_to_rad(a.motors[k].max);
      if (coupled_) {
        xlo_[k] = lo;
        xhi_[k] = hi;
      } else {
        xlo_[k] = std::max(xlo_[k], lo);
        xhi_[k] = std::min(xhi_[k], hi);
      }
    }
    // A joint variable driven by one motor alone (its row of C a unit vector) narrows that
    // motor's box directly.
    if (coupled_)
      for (int j = 0; j < n_; ++j) {
        int only = -1, count = 0;
        for (int k = 0; k < n_; ++k)
          if (C_[j][k] != 0) ++count, only = k;
        if (count == 1 && C_[j][only] == 1.0) {
          xlo_[only] = std::max(xlo_[only], qlo_[j]);
          xhi_[only] = std::min(xhi_[only], qhi_[j]);
        }
      }
  }

  // The closed form: the YPP family, with the motors' limits when they can be expressed.
  has_ypp_ = ypp_from_model(ypp_, model_);
  if (has_ypp_ && motors) {
    if (!ypp_limits_from_actuation(ypp_, robot->actuation)) {
      has_ypp_ = false;
    } else {
      // Narrow by the joint limits of the actuated coordinates that are joint variables.
      for (int i = 0; i < 3; ++i)
        if (i < 2 || !ypp_.parallelogram) {
          ypp_.lo[i] = std::max(ypp_.lo[i], qlo_[i]);
          ypp_.hi[i] = std::min(ypp_.hi[i], qhi_[i]);
        }
    }
  }

  // Reach bound: the tool lies within reach_ of centre_. The origin of frame 1 does not
  // depend on theta1 (it is (a, -sin(alpha) d, cos(alpha) d) of row 1), so when d1 is
  // constant and alpha1 constant or d1 = 0, it is a fixed centre; every later row adds at
  // most sqrt(a^2 + |d|max^2) (a lies along x(i-1), d along z(i), perpendicular), and the
  // tool its offset.
  int first = 0;
  centre_ = make_vec3(0.0, 0.0, 0.0);
  if (model_.num_rows > 0 && param_is_constant(model_, 0, kParamD)) {
    const DhRow<double>& r = model_.rows[0];
    if (param_is_constant(model_, 0, kParamAlpha))
      centre_ = make_vec3(r.a, -std::sin(r.alpha) * r.d, std::cos(r.alpha) * r.d), first = 1;
    else if (r.d == 0)
      centre_ = make_vec3(r.a, 0.0, 0.0), first = 1;
  }
  reach_ = norm(model_.T_last_tool.p);
  for (int i = first; i < model_.num_rows; ++i) {
    const double a = model_.rows[i].a, d = max_abs_param(model_, i, kParamD);
    reach_ += std::sqrt(a * a + d * d);
  }
}

bool InverseKinematics::within_all_limits(const std::vector<double>& q) const {
  if (int(q.size()) != n_) return false;
  for (int j = 0; j < n_; ++j)
    if (!(q[j] >= qlo_[j] && q[j] <= qhi_[j])) return false;
  // Motor limits (u = C^-1 q), with room for the rounding of the product.
  for (int k = 0; k < n_; ++k) {
    double u = 0;
    for (int j = 0; j < n_; ++j) u += Cinv_[k][j] * q[j];
    const double slack = 1e-9 * (1 + std::fabs(u));
    if (!(u >= xlo_[k] - slack && u <= xhi_[k] + slack)) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// The solvers

namespace {
using MatMN = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxJoints>;
using MatSq = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxJoints, kMaxJoints>;
using VecN = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxJoints, 1>;

// splitmix64: small, fast, and the same sequence everywhere.
struct Rng {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

// One pose and what the solvers need to know about it.
struct Eval {
  double x[kMaxJoints];
  double q[kMaxJoints];
  HostFrames frames;
  double e[6];   // error, target - current; rotation rows scaled to mm
  double err2;   // |e|^2
  double pos_err, rot_err;
};

enum class End { kReached, kStationary, kCap, kBudget };
}  // namespace

struct InverseKinematics::Impl {
  const InverseKinematics& ik;
  const IkTarget& target;
  const IkOptions& opt;
  int n, m;
  double scale;  // mm per rad of orientation error
  double sw[kMaxJoints];  // square roots of the weights
  bool frozen[kMaxJoints];
  int budget;
  int used = 0;
  bool timed;
  std::chrono::steady_clock::time_point deadline;

  Impl(const InverseKinematics& k, const IkTarget& t, const IkOptions& o, int default_budget)
      : ik(k), target(t), opt(o), n(k.n_), m(t.has_rotation ? 6 : 3) {
    scale = opt.orientation_scale_mm > 0 ? opt.orientation_scale_mm : std::max(ik.reach_ / 4, 1.0);
    for (int j = 0; j < n; ++j) {
      const double w = opt.weights.empty() ? 1.0 : opt.weights[j];
      sw[j] = std::sqrt(w);
      frozen[j] = w == 0;
    }
    budget = opt.max_iterations > 0 ? opt.max_iterations : default_budget;
    timed = opt.time_budget_s > 0;
    if (timed) {
      using Clock = std::chrono::steady_clock;
      const std::chrono::duration<double> budget_s(opt.time_budget_s);
      deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(budget_s);
    }
  }

  bool out_of_budget() const { return used >= budget || (timed && std::chrono::steady_clock::now() >= deadline); }

  void evaluate(Eval& ev) const {
    if (ik.coupled_) {
      for (int j = 0; j < n; ++j) {
        double v = 0;
        for (int k = 0; k < n; ++k) v += ik.C_[j][k] * ev.x[k];
        ev.q[j] = std::min(std::max(v, ik.qlo_[j]), ik.qhi_[j]);  // rounding only
      }
    } else {
      for (int j = 0; j < n; ++j) ev.q[j] = ev.x[j];
    }
    forward_kinematics(ev.frames, ik.model_, ev.q);
    const Transform<double>& T = ev.frames.T_base_tool;
    const Vec3<double> ep = target.position - T.p;
    ev.e[0] = ep.x, ev.e[1] = ep.y, ev.e[2] = ep.z;
    ev.pos_err = norm(ep);
    ev.err2 = dot(ep, ep);
    ev.rot_err = 0;
    if (target.has_rotation) {
      const Vec3<double> er = orientation_error(target.rotation, T.R);
      ev.rot_err = norm(er);
      ev.e[3] = scale * er.x, ev.e[4] = scale * er.y, ev.e[5] = scale * er.z;
      ev.err2 += scale * scale * ev.rot_err * ev.rot_err;
    }
  }

  bool reached(const Eval& ev) const {
    return ev.pos_err <= opt.position_tolerance_mm &&
           (!target.has_rotation || ev.rot_err <= opt.orientation_tolerance_rad);
  }

  // The Jacobian in solver coordinates, rotation rows scaled, columns not yet weighted.
  void jacobian_x(const Eval& ev, MatMN& J) const {
    double Jq[6][kMaxJoints];
    jacobian(Jq, ik.model_, ev.frames);
    J.resize(m, n);
    for (int r = 0; r < m; ++r) {
      const double s = r < 3 ? 1.0 : scale;
      for (int k = 0; k < n; ++k) {
        double v;
        if (ik.coupled_) {
          v = 0;
          for (int j = 0; j < n; ++j) v += Jq[r][j] * ik.C_[j][k];
        } else {
          v = Jq[r][k];
        }
        J(r, k) = s * v;
      }
    }
  }

  // x + dx, kept within every limit: clamped into the box, then (only for couplings that
  // leave joint limits outside the box) shortened until q = C x is within its limits.
  void project(const double* x, const double* dx, double* out) const {
    for (int k = 0; k < n; ++k) out[k] = std::min(std::max(x[k] + dx[k], ik.xlo_[k]), ik.xhi_[k]);
    if (!ik.coupled_) return;
    double t = 1;
    for (int j = 0; j < n; ++j) {
      double q = 0, dq = 0;
      for (int k = 0; k < n; ++k) q += ik.C_[j][k] * x[k], dq += ik.C_[j][k] * (out[k] - x[k]);
      if (q + dq > ik.qhi_[j] && dq > 0) t = std::min(t, (ik.qhi_[j] - q) / dq);
      if (q + dq < ik.qlo_[j] && dq < 0) t = std::min(t, (ik.qlo_[j] - q) / dq);
    }
    t = std::max(t, 0.0);
    if (t < 1)
      for (int k = 0; k < n; ++k) out[k] = x[k] + t * (out[k] - x[k]);
  }

  void random_start(Eval& ev, const double* start, Rng& rng) const {
    for (int attempt = 0; attempt < 20; ++attempt) {
      for (int k = 0; k < n; ++k)
        ev.x[k] = frozen[k] ? start[k] : ik.xlo_[k] + rng.uniform() * (ik.xhi_[k] - ik.xlo_[k]);
      if (!ik.coupled_ || feasible(ev.x)) return;
    }
  }

  bool feasible(const double* x) const {
    for (int j = 0; j < n; ++j) {
      double q = 0;
      for (int k = 0; k < n; ++k) q += ik.C_[j][k] * x[k];
      if (q < ik.qlo_[j] - 1e-9 || q > ik.qhi_[j] + 1e-9) return false;
    }
    return true;
  }

  // One damped least-squares step: dx = W^1/2 (Jw^T Jw + lambda I)^-1 Jw^T e with
  // Jw = J W^1/2, solved in the smaller of the two equivalent forms.
  void lm_step(const MatMN& J, const Eval& ev, double lambda, const bool* locked, double* dx) const {
    MatMN Jw(m, n);
    for (int k = 0; k < n; ++k) Jw.col(k) = J.col(k) * (locked[k] ? 0.0 : sw[k]);
    Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 1>> e(ev.e, m);
    VecN dz(n);
    if (n > m) {
      MatSq A = Jw * Jw.transpose();
      A.diagonal().array() += lambda;
      const Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 6, 1> y = A.llt().solve(e);
      dz = Jw.transpose() * y;
    } else {
      MatSq A = Jw.transpose() * Jw;
      A.diagonal().array() += lambda;
      dz = A.llt().solve(Jw.transpose() * e);
    }
    for (int k = 0; k < n; ++k) dx[k] = locked[k] ? 0.0 : sw[k] * dz[k];
  }

  // The step with the limits taken into account: a coordinate at a limit that the step
  // would push beyond it is held there and the step solved again without it, so that the
  // others make up for it in the same iteration (an active set) rather than losing the
  // clamped part of the step.
  void lm_step_limited(const MatMN& J, const Eval& ev, double lambda, double* dx) const {
    bool locked[kMaxJoints];
    for (int k = 0; k < n; ++k) locked[k] = false;
    lm_step(J, ev, lambda, locked, dx);
    for (int round = 0; round < 3; ++round) {
      bool again = false;
      for (int k = 0; k < n; ++k) {
        if (locked[k]) continue;
        const bool at_lo = ev.x[k] <= ik.xlo_[k] && dx[k] < 0, at_hi = ev.x[k] >= ik.xhi_[k] && dx[k] > 0;
        if (at_lo || at_hi) locked[k] = again = true;
      }
      if (!again) return;
      lm_step(J, ev, lambda, locked, dx);
    }
  }

  // Levenberg-Marquardt from ev.x until reached, stationary, `cap` iterations or the budget.
  // The damping lambda = mu (E + wbar) follows Sugihara (2011): E = err2 / 2 makes far
  // targets take short, safe steps and near ones Gauss-Newton steps; mu grows on a step
  // that does not help (it is retried, shorter) and shrinks on one that does.
  End lm_attempt(Eval*& cur, Eval*& trial, int cap) {
    const double wbar = 1e-6 * ik.reach_ * ik.reach_;
    double mu = 1;
    int still = 0;  // iterations in a row without real progress
    MatMN J;
    bool need_jacobian = true;
    for (int it = 0; it < cap; ++it) {
      if (reached(*cur)) return End::kReached;
      if (out_of_budget()) return End::kBudget;
      ++used;
      if (need_jacobian) jacobian_x(*cur, J);
      double dx[kMaxJoints];
      lm_step_limited(J, *cur, mu * (0.5 * cur->err2 + wbar), dx);
      project(cur->x, dx, trial->x);
      evaluate(*trial);
      const double gain = (cur->err2 - trial->err2) / std::max(cur->err2, 1e-300);
      if (trial->err2 < cur->err2) {
        std::swap(cur, trial);
        need_jacobian = true;
        mu = std::max(mu * 0.5, 1e-3);
      } else {
        need_jacobian = false;
        mu *= 8;
      }
      still = gain > 1e-7 ? 0 : still + 1;
      if (still >= 6 || mu > 1e12) return reached(*cur) ? End::kReached : End::kStationary;
    }
    return reached(*cur) ? End::kReached : End::kCap;
  }

  // Which limits hold the arm back at ev: a coordinate at its limit whose descent direction
  // (W J^T e) points out of the box. Empty when none.
  void binding_limits(const Eval& ev, std::vector<int>& joints, std::vector<int>& motors) const {
    MatMN J;
    jacobian_x(ev, J);
    Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 1>> e(ev.e, m);
    const VecN g = J.transpose() * e;
    const double en = e.norm();
    auto at = [](double v, double lim) { return std::fabs(v - lim) <= 1e-9 * (1 + std::fabs(lim)); };
    for (int k = 0; k < n; ++k) {
      if (frozen[k]) continue;
      const double c = g[k] / std::max(J.col(k).norm() * en, 1e-300);
      if ((at(ev.x[k], ik.xlo_[k]) && c < -1e-6) || (at(ev.x[k], ik.xhi_[k]) && c > 1e-6))
        (ik.coupled_ ? motors : joints).push_back(k);
    }
    if (!ik.coupled_) return;
    // Joint limits on q = C x: the descent moves q by C g (the sign is what counts; the
    // scale only keeps the threshold relative).
    const double jn = J.norm();
    for (int j = 0; j < n; ++j) {
      double gq = 0, q = 0;
      for (int k = 0; k < n; ++k) gq += ik.C_[j][k] * (frozen[k] ? 0.0 : g[k]), q += ik.C_[j][k] * ev.x[k];
      const double c = gq / std::max(jn * en, 1e-300);
      if ((at(q, ik.qlo_[j]) && c < -1e-6) || (at(q, ik.qhi_[j]) && c > 1e-6)) joints.push_back(j);
    }
  }

  void finish(IkResult& r, const Eval& best, End end) const {
    r.q.assign(best.q, best.q + n);
    r.tool = best.frames.T_base_tool;
    r.position_error_mm = best.pos_err;
    r.orientation_error_rad = best.rot_err;
    r.iterations = used;
    r.beyond_reach = norm(target.position - ik.centre_) > ik.reach_ * (1 + 1e-12);
    if (reached(best)) {
      r.status = IkStatus::kReached;
    } else if (end != End::kStationary) {
      r.status = IkStatus::kBudget;
    } else {
      binding_limits(best, r.limited_joints, r.limited_motors);
      r.status = r.limited_joints.empty() && r.limited_motors.empty() ? IkStatus::kUnreachable : IkStatus::kLimited;
    }
  }

  IkResult solve_lm(const double* x0) {
    IkResult r;
    r.method = IkMethod::kLevenbergMarquardt;
    Eval pool[3];
    Eval *cur = &pool[0], *trial = &pool[1], *best = &pool[2];
    Rng rng{opt.seed * 0x2545F4914F6CDD1DULL + 0x1234567ULL};
    const bool beyond = norm(target.position - ik.centre_) > ik.reach_ * (1 + 1e-12);
    // Attempts use at most 3/4 of the budget; the rest polishes the best pose when no
    // attempt reached the target, so that what is reported is a converged optimum.
    const int attempts_budget = std::max(1, budget - budget / 4);
    best->err2 = -1;
    End best_end = End::kCap;
    int stationary = 0;
    int attempts = 0;
    for (; attempts <= opt.max_restarts; ++attempts) {
      if (attempts == 0)
        for (int k = 0; k < n; ++k) cur->x[k] = x0[k];
      else
        random_start(*cur, x0, rng);
      evaluate(*cur);
      // Beyond the reach bound the answer is the stretched pose nearest the target, which
      // converges slowly (the arm is singular there): attempts then run to the end.
      const int per_attempt = beyond ? std::max(opt.attempt_iterations, attempts_budget / 3) : opt.attempt_iterations;
      const int cap = std::min(per_attempt, attempts_budget - used);
      const End end = cap > 0 ? lm_attempt(cur, trial, cap) : (reached(*cur) ? End::kReached : End::kBudget);
      if (best->err2 < 0 || cur->err2 < best->err2) {
        std::swap(best, cur);
        best_end = end;
      }
      if (end == End::kReached) {
        ++attempts;
        break;
      }
      if (end == End::kStationary) ++stationary;
      if (end == End::kBudget || used >= attempts_budget) {
        ++attempts;
        break;
      }
      // Beyond the reach bound no restart can reach it: a few stationary ends settle
      // which direction to stretch.
      if (beyond && stationary >= 3) {
        ++attempts;
        break;
      }
    }
    r.attempts = attempts;
    if (best_end != End::kReached && best_end != End::kStationary && !out_of_budget()) {
      // Polish the best pose with what is left.
      std::swap(cur, best);
      best_end = lm_attempt(cur, trial, budget - used);
      std::swap(cur, best);
    }
    finish(r, *best, best_end);
    return r;
  }

  // The thesis's method (section 2.2): dq = h J^T e, here with the weights (dq = h W J^T e)
  // and the limits (the step is clamped). No line search, no restarts: as the original.
  // Stops when reached, when the error has shrunk by less than 0.1 % over the last 100
  // iterations (stationary: the method "believes it needs no more rotations"), or when the
  // budget is spent (overtime).
  IkResult solve_jt(const double* x0) {
    IkResult r;
    r.method = IkMethod::kJacobianTranspose;
    r.attempts = 1;
    Eval pool[3];
    Eval *cur = &pool[0], *next = &pool[1], *best = &pool[2];
    for (int k = 0; k < n; ++k) cur->x[k] = x0[k];
    evaluate(*cur);
    *best = *cur;
    const double h = opt.jt_gain / std::max(ik.reach_ * ik.reach_, 1e-12);
    const int window = 100;
    std::vector<double> history;
    history.reserve(size_t(budget) + 1);
    End end = End::kBudget;
    MatMN J;
    for (;;) {
      if (reached(*cur)) {
        end = End::kReached;
        break;
      }
      history.push_back(best->err2);
      const int it = int(history.size()) - 1;
      if (it >= window && history[size_t(it - window)] - best->err2 <= 1e-3 * history[size_t(it - window)]) {
        end = End::kStationary;
        break;
      }
      if (out_of_budget()) break;
      ++used;
      jacobian_x(*cur, J);
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 1>> e(cur->e, m);
      const VecN g = J.transpose() * e;
      double dx[kMaxJoints];
      for (int k = 0; k < n; ++k) dx[k] = h * sw[k] * sw[k] * g[k];
      project(cur->x, dx, next->x);
      evaluate(*next);
      std::swap(cur, next);
      if (cur->err2 < best->err2) *best = *cur;
    }
    finish(r, reached(*cur) ? *cur : *best, end);
    return r;
  }
};

IkResult InverseKinematics::solve(const IkTarget& target, const std::vector<double>& start,
                                  const IkOptions& options) const {
  if (int(start.size()) != n_)
    throw std::invalid_argument("ik: the start has " + std::to_string(start.size()) + " values; the robot has " +
                                std::to_string(n_) + " joint variables");
  if (!options.weights.empty() && int(options.weights.size()) != n_)
    throw std::invalid_argument("ik: " + std::to_string(options.weights.size()) + " weights for " +
                                std::to_string(n_) + " joint variables");
  for (double w : options.weights)
    if (!(w >= 0) || !std::isfinite(w)) throw std::invalid_argument("ik: a weight must be finite and >= 0");
  for (double v : start)
    if (!std::isfinite(v)) throw std::invalid_argument("ik: the start is not finite");
  if (!is_finite(target.position.x) || !is_finite(target.position.y) || !is_finite(target.position.z))
    throw std::invalid_argument("ik: the target is not finite");
  if (target.has_rotation)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (!std::isfinite(target.rotation.m[i][j]))
          throw std::invalid_argument("ik: the target rotation is not finite");
  if (!(options.position_tolerance_mm > 0) || !(options.orientation_tolerance_rad > 0))
    throw std::invalid_argument("ik: tolerances must be > 0");

  bool any_frozen = false;
  for (double w : options.weights) any_frozen = any_frozen || w == 0;

  // The start in solver coordinates, within the limits.
  double x0[kMaxJoints];
  for (int k = 0; k < n_; ++k) {
    double v;
    if (coupled_) {
      v = 0;
      for (int j = 0; j < n_; ++j) v += Cinv_[k][j] * start[size_t(j)];
    } else {
      v = start[size_t(k)];
    }
    const bool frozen = !options.weights.empty() && options.weights[size_t(k)] == 0;
    const double slack = 1e-9 * (1 + std::fabs(v));
    if (frozen && (v < xlo_[k] - slack || v > xhi_[k] + slack))
      throw std::invalid_argument("ik: joint " + std::to_string(k) +
                                  " has weight 0 (frozen) but starts outside its limits");
    x0[k] = std::min(std::max(v, xlo_[k]), xhi_[k]);
  }

  if (n_ == 0) {  // nothing to move: the pose is what it is
    Impl impl(*this, target, options, 1);
    Eval ev;
    impl.evaluate(ev);
    IkResult r;
    r.method = options.method == IkMethod::kAuto ? IkMethod::kLevenbergMarquardt : options.method;
    r.attempts = 1;
    impl.finish(r, ev, End::kStationary);
    return r;
  }

  IkMethod method = options.method;
  if (method == IkMethod::kAuto)
    method = has_ypp_ && !target.has_rotation && !any_frozen ? IkMethod::kClosedForm : IkMethod::kLevenbergMarquardt;
  if (method == IkMethod::kClosedForm) {
    if (!has_ypp_) throw std::invalid_argument("ik: the closed form needs a yaw-pitch-pitch arm (ik_ypp.h)");
    if (any_frozen) throw std::invalid_argument("ik: the closed form cannot keep a joint frozen (weight 0)");
  }

  if (method == IkMethod::kLevenbergMarquardt || method == IkMethod::kJacobianTranspose) {
    Impl impl(*this, target, options, method == IkMethod::kJacobianTranspose ? 2000 : 1000);
    return method == IkMethod::kJacobianTranspose ? impl.solve_jt(x0) : impl.solve_lm(x0);
  }

  // Closed form. Among the solutions within every limit, the nearest to the start (and, for
  // a full pose, the one nearest in orientation first).
  YppResult<double> yr;
  ypp_solve(yr, ypp_, target.position, true);
  Impl impl(*this, target, options, 1);
  Eval ev;
  IkResult r;
  r.method = IkMethod::kClosedForm;
  r.attempts = 1;
  bool found = false;
  double best_rot = 0, best_d = 0;
  for (int i = 0; i < yr.count; ++i) {
    if (!yr.solutions[i].in_limits) continue;
    const std::vector<double> q(yr.solutions[i].q, yr.solutions[i].q + 3);
    if (!within_all_limits(q)) continue;
    Eval e;
    for (int k = 0; k < 3; ++k) e.x[k] = coupled_ ? (k == 2 ? q[1] + q[2] : q[size_t(k)]) : q[size_t(k)];
    impl.evaluate(e);
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (e.x[k] - x0[k]) * (e.x[k] - x0[k]);
    const bool better =
        !found || e.rot_err < best_rot - 1e-12 || (std::fabs(e.rot_err - best_rot) <= 1e-12 && d < best_d);
    if (better) {
      ev = e;
      found = true;
      best_rot = e.rot_err;
      best_d = d;
    }
  }
  if (!found) {
    const std::vector<double> q(yr.nearest_q, yr.nearest_q + 3);
    if (!within_all_limits(q)) {
      // Joint limits the closed form's box does not express: the numeric solver instead.
      Impl lm(*this, target, options, 1000);
      return lm.solve_lm(x0);
    }
    for (int k = 0; k < 3; ++k) ev.x[k] = coupled_ ? (k == 2 ? q[1] + q[2] : q[size_t(k)]) : q[size_t(k)];
    impl.evaluate(ev);
  }
  r.q.assign(ev.q, ev.q + n_);
  r.tool = ev.frames.T_base_tool;
  r.position_error_mm = ev.pos_err;
  r.orientation_error_rad = ev.rot_err;
  r.beyond_reach = yr.status == kYppOutOfReach;
  if (impl.reached(ev)) {
    r.status = IkStatus::kReached;
  } else if (found || yr.status == kYppOutOfReach) {
    r.status = IkStatus::kUnreachable;  // beyond the geometry, or the orientation is not the arm's to choose
  } else {
    // Reachable only outside the limits: which limits hold the nearest pose.
    impl.binding_limits(ev, r.limited_joints, r.limited_motors);
    r.status = IkStatus::kLimited;
  }
  return r;
}

IkResult solve_ik(const Robot& robot, const IkTarget& target, const std::vector<double>& start,
                  const IkOptions& options) {
  return InverseKinematics(robot).solve(target, start, options);
}

}  // namespace articula::host
