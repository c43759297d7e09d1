// articula/ik_ypp.h - closed-form inverse kinematics for yaw-pitch-pitch arms.
//
// The family: a base that turns about the vertical (yaw), a shoulder and an elbow that
// pitch in the vertical plane of the yaw, and a tool kept level (mechanically, as the MK2
// arm's parallelogram does) at a fixed offset from the wrist. In modified DH:
//
//   row  a(i-1)  alpha(i-1)  d(i)   theta(i)
//   1    0       0           h      q0 (yaw)
//   2    s       +90 deg     0      q1 (upper arm elevation above the horizontal)
//   3    L1      0           0      q2 (elbow, relative to the upper arm)
//   4    L2      0           0      -(q1 + q2)   (linked: keeps the tool level)
//   tool: translation (f, u, 0) in frame 4 (x4 points forward, y4 up), any rotation.
//
// The actuated coordinates are q itself, or, with the parallelogram coupling, the forearm's
// elevation q1 + q2 instead of q2. Limits are given on the actuated coordinates.
//
// Geometry (all planar once the yaw is fixed): with r the signed horizontal distance of the
// target along the yaw direction and z its height, the wrist sits at
//   (r - f - s, z - u - h) relative to the shoulder,
// and the two-link solution is the law of cosines (Craig 4.4, the planar RR arm):
//   cos q2 = (D^2 - L1^2 - L2^2) / (2 L1 L2),  q1 = atan2(v, w) - atan2(L2 sin q2, L1 + L2 cos q2).
// Two yaws (facing the target, or facing away and reaching back over the top) times two
// elbows give up to four solutions.
//
// Float-safe: no subtraction of nearly equal large numbers beyond the law of cosines, whose
// argument is clamped; a target a hair beyond full reach (rounding) counts as reached.
#ifndef ARTICULA_IK_YPP_H
#define ARTICULA_IK_YPP_H

#include "actuation.h"
#include "dh.h"

namespace articula {

template <typename Scalar>
struct YppArm {
  Scalar base_height;      // h, mm: height of the shoulder axis
  Scalar shoulder_offset;  // s, mm: from the yaw axis to the shoulder axis, forward
  Scalar upper;            // L1, mm: shoulder to elbow
  Scalar fore;             // L2, mm: elbow to wrist
  Scalar tool_forward;     // f, mm: wrist to tool point, horizontal
  Scalar tool_up;          // u, mm: wrist to tool point, vertical
  bool parallelogram;      // actuated coordinate 2 is the forearm elevation q1 + q2
  Scalar lo[3], hi[3];     // limits of the actuated coordinates, rad
};

enum YppStatus : uint8_t {
  kYppReached = 0,    // at least one solution within the limits
  kYppOutOfReach,     // too far (or too close to the shoulder) for any pose
  kYppLimited,        // reachable in geometry, but every solution breaks a limit
};

template <typename Scalar>
struct YppSolution {
  Scalar q[3];     // DH joint values (q0, q1, q2), rad
  bool in_limits;  // the actuated coordinates are within the limits
};

template <typename Scalar>
struct YppResult {
  YppStatus status;
  uint8_t count;                   // geometric solutions found (0 when out of reach)
  YppSolution<Scalar> solutions[4];  // in-limits ones first
  // When not reached: the pose within the limits that comes nearest, found by polishing
  // the clamped closed-form candidates and six other starts (the best of several local
  // optima, not a proof of the global one), and where it puts the tool. When reached: the first in-limits solution and the target itself.
  Scalar nearest_q[3];
  Vec3<Scalar> nearest;
  Scalar distance;  // mm from the target to `nearest` (0 when reached)
};

// The tool position of a YPP arm, closed form (agrees with the DH chain; tested).
template <typename S>
inline Vec3<S> ypp_tool_position(const YppArm<S>& arm, const S* q) {
  const S r = arm.shoulder_offset + arm.upper * Math<S>::cos(q[1]) + arm.fore * Math<S>::cos(q[1] + q[2]) + arm.tool_forward;
  const S z = arm.base_height + arm.upper * Math<S>::sin(q[1]) + arm.fore * Math<S>::sin(q[1] + q[2]) + arm.tool_up;
  return make_vec3(r * Math<S>::cos(q[0]), r * Math<S>::sin(q[0]), z);
}

template <typename S>
inline void ypp_actuated(S* act, const YppArm<S>& arm, const S* q) {
  act[0] = q[0];
  act[1] = q[1];
  act[2] = arm.parallelogram ? q[1] + q[2] : q[2];
}

template <typename S>
inline bool ypp_within_limits(const YppArm<S>& arm, const S* q) {
  S act[3];
  ypp_actuated(act, arm, q);
  for (int i = 0; i < 3; ++i)
    if (!(act[i] >= arm.lo[i] && act[i] <= arm.hi[i])) return false;
  return true;
}

namespace detail {
// Wraps an angle into (-pi, pi].
template <typename S>
inline S wrap_angle(S a) {
  while (a > pi<S>()) a -= S(2) * pi<S>();
  while (a <= -pi<S>()) a += S(2) * pi<S>();
  return a;
}

// Clamps the actuated coordinates into the limits and returns the DH values.
template <typename S>
inline void ypp_clamp(S* q, const YppArm<S>& arm) {
  S act[3];
  ypp_actuated(act, arm, q);
  for (int i = 0; i < 3; ++i) act[i] = clamp(act[i], arm.lo[i], arm.hi[i]);
  q[0] = act[0];
  q[1] = act[1];
  q[2] = arm.parallelogram ? act[2] - act[1] : act[2];
}

// Tool position and its Jacobian with respect to the actuated coordinates act[3].
template <typename S>
inline Vec3<S> ypp_position_and_jacobian(S J[3][3], const YppArm<S>& arm, const S* act) {
  const S q1 = act[1];
  const S q12 = arm.parallelogram ? act[2] : act[1] + act[2];  // forearm elevation
  const S c0 = Math<S>::cos(act[0]), s0 = Math<S>::sin(act[0]);
  const S c1 = Math<S>::cos(q1), s1 = Math<S>::sin(q1);
  const S c12 = Math<S>::cos(q12), s12 = Math<S>::sin(q12);
  const S r = arm.shoulder_offset + arm.upper * c1 + arm.fore * c12 + arm.tool_forward;
  const S z = arm.base_height + arm.upper * s1 + arm.fore * s12 + arm.tool_up;
  // d(r, z)/d act1 and d act2; act1 moves the forearm too unless the parallelogram holds it.
  const S dr2 = -arm.fore * s12, dz2 = arm.fore * c12;
  const S dr1 = -arm.upper * s1 + (arm.parallelogram ? S(0) : dr2);
  const S dz1 = arm.upper * c1 + (arm.parallelogram ? S(0) : dz2);
  J[0][0] = -r * s0; J[1][0] = r * c0; J[2][0] = S(0);
  J[0][1] = dr1 * c0; J[1][1] = dr1 * s0; J[2][1] = dz1;
  J[0][2] = dr2 * c0; J[1][2] = dr2 * s0; J[2][2] = dz2;
  return make_vec3(r * c0, r * s0, z);
}

// Solves the 3x3 system A[.][0..2] x = A[.][3] by Gaussian elimination with partial
// pivoting (A is overwritten). False when it is singular. Loops, not Cramer's rule: on the
// AVR this is a fraction of the code.
template <typename S>
inline bool solve3(S* x, S A[3][4]) {
  for (int c = 0; c < 3; ++c) {
    int p = c;
    for (int r = c + 1; r < 3; ++r)
      if (Math<S>::fabs(A[r][c]) > Math<S>::fabs(A[p][c])) p = r;
    if (!(Math<S>::fabs(A[p][c]) > S(0))) return false;
    for (int k = 0; k < 4; ++k) {
      const S t = A[c][k];
      A[c][k] = A[p][k];
      A[p][k] = t;
    }
    for (int r = c + 1; r < 3; ++r) {
      const S f = A[r][c] / A[c][c];
      for (int k = c; k < 4; ++k) A[r][k] -= f * A[c][k];
    }
  }
  for (int r = 2; r >= 0; --r) {
    S v = A[r][3];
    for (int k = r + 1; k < 3; ++k) v -= A[r][k] * x[k];
    x[r] = v / A[r][r];
  }
  return true;
}

// Moves a pose within the limits closer to the target: damped Gauss-Newton steps on the
// tool's distance, projected into the box of actuated limits, each kept only if it helps
// (Levenberg-Marquardt's rule). Turns the clamped closed-form candidates into the nearest
// reachable points they lead to. q: DH values in and out, within limits on entry.
template <typename S>
inline void ypp_polish(S* q, const YppArm<S>& arm, const Vec3<S>& target) {
  S act[3];
  ypp_actuated(act, arm, q);
  S J[3][3];
  Vec3<S> e = target - ypp_position_and_jacobian(J, arm, act);
  S err2 = dot(e, e);
  S lambda = S(1e-3);
  for (int iter = 0; iter < 80 && lambda < S(1e8); ++iter) {
    // (J^T J + lambda (diag(J^T J) + 1)) dx = J^T e.
    S A[3][4];  // the system with its right-hand side
    for (int i = 0; i < 3; ++i) {
      A[i][3] = J[0][i] * e.x + J[1][i] * e.y + J[2][i] * e.z;
      for (int k = 0; k < 3; ++k) A[i][k] = J[0][i] * J[0][k] + J[1][i] * J[1][k] + J[2][i] * J[2][k];
      A[i][i] += lambda * (A[i][i] + S(1));
    }
    S dx[3];
    if (!solve3(dx, A)) break;
    // At most 0.2 rad a step: a long Gauss-Newton jump can leave the basin it started in,
    // and the starts are chosen to cover the basins.
    const S longest = max_of(Math<S>::fabs(dx[0]), max_of(Math<S>::fabs(dx[1]), Math<S>::fabs(dx[2])));
    if (longest > S(0.2))
      for (int i = 0; i < 3; ++i) dx[i] *= S(0.2) / longest;
    S trial[3];
    for (int i = 0; i < 3; ++i) trial[i] = clamp(act[i] + dx[i], arm.lo[i], arm.hi[i]);
    S Jt[3][3];
    const Vec3<S> et = target - ypp_position_and_jacobian(Jt, arm, trial);
    const S trial_err2 = dot(et, et);
    if (trial_err2 < err2) {
      const bool converged = err2 - trial_err2 <= S(1e-7) * err2;
      for (int i = 0; i < 3; ++i) act[i] = trial[i];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) J[i][k] = Jt[i][k];
      e = et;
      err2 = trial_err2;
      lambda *= S(0.3);
      if (converged) break;
    } else {
      lambda *= S(10);
    }
  }
  q[0] = act[0];
  q[1] = act[1];
  q[2] = arm.parallelogram ? act[2] - act[1] : act[2];
}
}  // namespace detail

namespace detail {
// The best pose within the limits seen so far, for an unreachable target.
template <typename S>
struct YppBest {
  S q[3];
  S d2;  // squared distance to the target; negative until a pose was considered

  // Clamps q into the limits, polishes it if asked, and keeps it if it is the nearest yet.
  void consider(S* q_in, const YppArm<S>& arm, const Vec3<S>& target, bool polish) {
    ypp_clamp(q_in, arm);
    if (polish) ypp_polish(q_in, arm, target);
    const Vec3<S> e = ypp_tool_position(arm, q_in) - target;
    const S e2 = dot(e, e);
    if (d2 < S(0) || e2 < d2) {
      d2 = e2;
      for (int i = 0; i < 3; ++i) q[i] = q_in[i];
    }
  }
};
}  // namespace detail

namespace detail {
// The target as one facing of the base sees it: the yaw q0 (facing the target, or facing
// away and reaching back over the top), and in the arm's vertical plane the distance D
// from the shoulder to the wrist and its direction `toward`.
template <typename S>
struct YppFacing {
  S q0, D, toward;
  bool in_reach;  // the two links can span D (a hair beyond, from rounding, counts)
};

template <typename S>
inline void ypp_facings(YppFacing<S>* f, const YppArm<S>& arm, const Vec3<S>& p_base_tool) {
  const S L1 = arm.upper, L2 = arm.fore;
  const S rho = Math<S>::sqrt(p_base_tool.x * p_base_tool.x + p_base_tool.y * p_base_tool.y);
  const S yaw = rho > S(0) ? Math<S>::atan2(p_base_tool.y, p_base_tool.x) : S(0);
  const S reach_max = L1 + L2;
  const S reach_min = Math<S>::fabs(L1 - L2);
  const S tol = S(64) * Math<S>::epsilon() * (reach_max + rho + Math<S>::fabs(p_base_tool.z));
  for (int facing = 0; facing < 2; ++facing) {
    const S r = facing == 0 ? rho : -rho;
    const S w = r - arm.tool_forward - arm.shoulder_offset;
    const S v = p_base_tool.z - arm.tool_up - arm.base_height;
    YppFacing<S>& fa = f[facing];
    fa.q0 = facing == 0 ? yaw : wrap_angle(yaw + pi<S>());
    fa.D = Math<S>::sqrt(w * w + v * v);
    fa.toward = Math<S>::atan2(v, w);
    fa.in_reach = !(fa.D > reach_max + tol || fa.D < reach_min - tol);
  }
}
}  // namespace detail

// The closed form alone: every geometric solution for the tool point p_base_tool (mm, base
// frame, finite), at most four (two facings times two elbows), the ones within the limits
// first, and otherwise in the order facing the target, elbow up. Sets out.count and
// out.solutions only, and returns how many solutions are within the limits. What the
// firmware needs for P (none within the limits: refused, no search for the nearest pose);
// ypp_solve starts with it.
// With sort = false the solutions stay in that order, each marked in_limits, and the
// count within the limits is still returned (the Nano's P and T look at all of them).
template <typename S>
inline int ypp_closed_form(YppResult<S>& out, const YppArm<S>& arm, const Vec3<S>& p_base_tool, bool sort = true) {
  const S L1 = arm.upper, L2 = arm.fore;
  detail::YppFacing<S> f[2];
  detail::ypp_facings(f, arm, p_base_tool);
  out.count = 0;
  for (int facing = 0; facing < 2; ++facing) {
    if (!f[facing].in_reach) continue;
    const S D = f[facing].D;
    const S c2 = clamp((D * D - L1 * L1 - L2 * L2) / (S(2) * L1 * L2), S(-1), S(1));
    const S base_q2 = Math<S>::acos(c2);
    for (int elbow = 0; elbow < 2; ++elbow) {
      const S q2 = elbow == 0 ? base_q2 : -base_q2;
      if (elbow == 1 && base_q2 == S(0)) break;  // stretched: both elbows are one pose
      YppSolution<S>& sol = out.solutions[out.count++];
      sol.q[0] = f[facing].q0;
      sol.q[2] = q2;
      sol.q[1] = detail::wrap_angle(f[facing].toward - Math<S>::atan2(L2 * Math<S>::sin(q2), L1 + L2 * Math<S>::cos(q2)));
      sol.in_limits = ypp_within_limits(arm, sol.q);
    }
  }
  // In-limits solutions first, keeping the order otherwise.
  int first_out = 0;
  for (int i = 0; i < out.count; ++i) {
    if (!out.solutions[i].in_limits) continue;
    if (!sort) {
      ++first_out;
      continue;
    }
    const YppSolution<S> t = out.solutions[i];
    for (int k = i; k > first_out; --k) out.solutions[k] = out.solutions[k - 1];
    out.solutions[first_out++] = t;
  }
  return first_out;
}

// Solves for the tool point p_base_tool (mm, base frame), which must be finite: callers
// reject NaN and inf before they get here. The closed form (ypp_closed_form), and when no
// solution is within the limits, a search for the nearest pose within them: with
// polish = false an unreachable target's `nearest` is only the best clamped candidate;
// with polish = true each candidate, and six more starts, are polished into a local
// optimum within the limits (the host's "stretch toward the target").
template <typename S>
inline void ypp_solve(YppResult<S>& out, const YppArm<S>& arm, const Vec3<S>& p_base_tool, bool polish = true) {
  if (ypp_closed_form(out, arm, p_base_tool) > 0) {
    out.status = kYppReached;
    for (int i = 0; i < 3; ++i) out.nearest_q[i] = out.solutions[0].q[i];
    out.nearest = ypp_tool_position(arm, out.nearest_q);
    out.distance = S(0);
    return;
  }
  const S L1 = arm.upper, L2 = arm.fore;
  detail::YppFacing<S> f[2];
  detail::ypp_facings(f, arm, p_base_tool);
  detail::YppBest<S> best = {{S(0), S(0), S(0)}, S(-1)};
  // Out of reach for a facing: stretch (or fold) toward the target.
  for (int facing = 0; facing < 2; ++facing) {
    if (f[facing].in_reach) continue;
    S q[3];
    q[0] = f[facing].q0;
    if (f[facing].D > L1 + L2) {
      q[1] = f[facing].toward;
      q[2] = S(0);
    } else {
      q[2] = L1 >= L2 ? pi<S>() : -pi<S>();
      q[1] = L1 >= L2 ? f[facing].toward : detail::wrap_angle(f[facing].toward + pi<S>());
    }
    best.consider(q, arm, p_base_tool, polish);
  }
  // Reachable only outside the limits: the clamped geometric solutions are candidates too.
  for (int i = 0; i < out.count; ++i) {
    S q[3] = {out.solutions[i].q[0], out.solutions[i].q[1], out.solutions[i].q[2]};
    best.consider(q, arm, p_base_tool, polish);
  }
  // More starts, facing the target as nearly as the base allows, with the shoulder at
  // either limit and mid-range: far below or behind the base the nearest point is often
  // reached back over the top, which the stretched and clamped candidates never try.
  for (int start = 0; polish && start < 6; ++start) {
    const int facing = start / 3, shoulder = start % 3;
    S act[3] = {clamp(f[facing].q0, arm.lo[0], arm.hi[0]),
                shoulder == 0 ? arm.lo[1] : (shoulder == 1 ? (arm.lo[1] + arm.hi[1]) / S(2) : arm.hi[1]),
                (arm.lo[2] + arm.hi[2]) / S(2)};
    S q[3] = {act[0], act[1], arm.parallelogram ? act[2] - act[1] : act[2]};
    best.consider(q, arm, p_base_tool, true);
  }
  out.status = out.count > 0 ? kYppLimited : kYppOutOfReach;
  for (int i = 0; i < 3; ++i) out.nearest_q[i] = best.q[i];
  out.nearest = ypp_tool_position(arm, best.q);
  out.distance = norm(out.nearest - p_base_tool);
}

// Recognises a model of the YPP family (the table above, with the joint order q0, q1, q2)
// and fills `arm` from it; the limits come from the joint specs unless the caller passes
// actuated limits afterwards. False for any other model.
template <typename S, int J, int R>
inline bool ypp_from_model(YppArm<S>& arm, const Model<S, J, R>& m) {
  const S eps = S(1e-6);
  if (m.num_rows != 4 || m.num_joints != 3 || m.num_linked != 1) return false;
  for (int j = 0; j < 3; ++j)
    if (m.joints[j].row != j || m.joints[j].param != kParamTheta) return false;
  const LinkedParam<S, J>& l = m.linked[0];
  if (l.row != 3 || l.param != kParamTheta || Math<S>::fabs(l.offset) > eps) return false;
  if (Math<S>::fabs(l.gain[0]) > eps || Math<S>::fabs(l.gain[1] + S(1)) > eps || Math<S>::fabs(l.gain[2] + S(1)) > eps)
    return false;
  const DhRow<S>* r = m.rows;
  if (Math<S>::fabs(r[0].a) > eps || Math<S>::fabs(r[0].alpha) > eps) return false;
  if (Math<S>::fabs(r[1].alpha - pi<S>() / S(2)) > eps || Math<S>::fabs(r[1].d) > eps) return false;
  if (Math<S>::fabs(r[2].alpha) > eps || Math<S>::fabs(r[2].d) > eps) return false;
  if (Math<S>::fabs(r[3].alpha) > eps || Math<S>::fabs(r[3].d) > eps) return false;
  if (Math<S>::fabs(m.T_last_tool.p.z) > eps) return false;  // no sideways tool offset
  arm.base_height = r[0].d;
  arm.shoulder_offset = r[1].a;
  arm.upper = r[2].a;
  arm.fore = r[3].a;
  arm.tool_forward = m.T_last_tool.p.x;
  arm.tool_up = m.T_last_tool.p.y;
  arm.parallelogram = false;
  for (int j = 0; j < 3; ++j) {
    arm.lo[j] = m.joints[j].lo;
    arm.hi[j] = m.joints[j].hi;
  }
  return arm.upper > S(0) && arm.fore > S(0);
}

// Puts the limits of the motors (what the firmware enforces, on the actuated coordinates)
// into a YPP arm (from ypp_from_model) and recognises how the motors drive the joints: the
// identity coupling (each motor turns its own DH joint) or the MK2's parallelogram,
// C = [[1,0,0],[0,1,0],[0,-1,1]] (motor 2 sets the forearm's elevation q1 + q2). False, and
// the arm untouched, for any other coupling or a motor count other than three.
template <typename S, int J>
inline bool ypp_limits_from_actuation(YppArm<S>& arm, const Actuation<S, J>& a) {
  static const int8_t kParallelogram[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, -1, 1}};
  if (a.num_motors != 3) return false;
  bool identity = true, parallelogram = true;
  for (int i = 0; i < 3 && i < J; ++i)
    for (int j = 0; j < 3 && j < J; ++j) {
      identity = identity && a.coupling[i][j] == S(i == j ? 1 : 0);
      parallelogram = parallelogram && a.coupling[i][j] == S(kParallelogram[i][j]);
    }
  if (!identity && !parallelogram) return false;
  arm.parallelogram = parallelogram;
  for (int i = 0; i < 3 && i < J; ++i) {
    arm.lo[i] = deg_to_rad(S(a.motors[i].min) / S(1000));
    arm.hi[i] = deg_to_rad(S(a.motors[i].max) / S(1000));
  }
  return true;
}

}  // namespace articula

#endif  // ARTICULA_IK_YPP_H
