// articula/actuation.h - from motor steps to joint values and back.
//
// The chain, per motor i and for the arm as a whole:
//
//   steps s_i (integer, absolute)  --gear, direction, zero-->  actuator angle u_i
//   joint variables q = C * u      (C: the linear coupling, identity when each motor
//                                   drives its own joint)
//
// u_i is the angle of the gear's output: what the original firmware's `L <joint> <deg>`
// turns. On the MK2 arm the elbow motor sets the forearm's angle to the horizontal, so
// u = (base yaw, upper-arm elevation, forearm elevation) and the DH elbow variable is
// theta3 = u2 - u1: C = [[1,0,0],[0,1,0],[0,-1,1]]. A lead screw on a d variable is a
// coupling entry in mm per radian.
//
// Commanded angles are exact: millidegrees in an int32 (the protocol parses decimal text
// straight into them), so the quantization below is integer arithmetic and gives the same
// step on the Nano (float) and on the host (double). The rounding rule, the only one:
//
//   steps = round_half_away_from_zero( dir * (u - zero) * steps_per_turn * num / (360 deg * den) )
//
// applied to the *absolute* commanded angle, with one exception at the limits: a commanded
// angle within the limits whose nearest step lies just past a limit takes the last whole
// step inside instead (quantize_within_limits), so the arm never steps past a limit and a
// move to exactly a limit is still accepted. Relative moves add to the commanded angle
// (exactly) and quantize once, so they never drift.
#ifndef ARTICULA_ACTUATION_H
#define ARTICULA_ACTUATION_H

#include "status.h"
#include "transform.h"

namespace articula {

typedef int32_t Millideg;

// Largest |angle| the protocol and the state accept: 1,000,000 degrees. Keeps every
// product below in range of int64 and every sum in int32.
static const int32_t kMaxAbsMillideg = 1000000000L;

struct MotorSpec {
  uint16_t full_steps_per_rev;  // 200 for a 1.8 deg NEMA17
  uint8_t microsteps;           // steps per full step: 1 full step, 2 half step, ...
  int8_t direction;             // +1 or -1: sign from actuator angle to step count
  int32_t gear_num;             // motor turns per joint turn = gear_num / gear_den
  int32_t gear_den;             //   (e.g. 108/19 on the MK2 base)
  Millideg zero;                // actuator angle at step 0
  Millideg min, max;            // actuator limits
};

namespace detail {
// n / d rounded half away from zero, for d > 0.
inline int64_t div_round_half_away(int64_t n, int64_t d) {
  return n >= 0 ? (2 * n + d) / (2 * d) : -((-2 * n + d) / (2 * d));
}
inline int64_t div_floor(int64_t n, int64_t d) {
  const int64_t q = n / d;
  return (q * d != n && ((n < 0) != (d < 0))) ? q - 1 : q;
}
inline int64_t div_ceil(int64_t n, int64_t d) { return -div_floor(-n, d); }
// Steps per millidegree as the fraction num/den.
inline int64_t steps_num(const MotorSpec& m) {
  return int64_t(m.full_steps_per_rev) * m.microsteps * m.gear_num;
}
inline int64_t steps_den(const MotorSpec& m) { return int64_t(360000L) * m.gear_den; }
}  // namespace detail

// Why a motor description is not usable; kMotorOk when it is.
enum MotorError : uint8_t {
  kMotorOk = 0,
  kMotorBadSteps,      // steps per revolution or microsteps zero
  kMotorBadGear,       // gear ratio not positive
  kMotorBadDirection,  // direction not +1/-1
  kMotorBadLimits,     // min > max, zero outside them, or beyond +-kMaxAbsMillideg
  kMotorTooFine,       // steps per joint turn too large for exact integer arithmetic, or
                       // the step counts within the limits beyond an int32
};

inline const char* motor_error_text(MotorError e) {
  switch (e) {
    case kMotorOk: return "ok";
    case kMotorBadSteps: return "steps per revolution and microsteps must be at least 1";
    case kMotorBadGear: return "gear ratio must be a positive fraction";
    case kMotorBadDirection: return "direction must be +1 or -1";
    case kMotorBadLimits: return "limits inverted, zero outside the limits, or beyond 1,000,000 degrees";
    case kMotorTooFine: return "steps per joint turn exceed 2^31, or the step count between the limits exceeds 2^31";
  }
  return "unknown motor error";
}

inline MotorError validate(const MotorSpec& m) {
  if (m.full_steps_per_rev == 0 || m.microsteps == 0) return kMotorBadSteps;
  if (m.gear_num <= 0 || m.gear_den <= 0) return kMotorBadGear;
  if (m.direction != 1 && m.direction != -1) return kMotorBadDirection;
  if (m.min > m.max || m.zero < m.min || m.zero > m.max) return kMotorBadLimits;
  if (m.min < -kMaxAbsMillideg || m.max > kMaxAbsMillideg) return kMotorBadLimits;
  if (detail::steps_num(m) > 2147483647LL) return kMotorTooFine;
  // Every angle within the limits must quantize to an int32 step count. (Both factors are
  // below 2^31, so the product fits an int64.)
  const int64_t span = max_of(int64_t(m.max) - m.zero, int64_t(m.zero) - m.min);
  if (detail::div_round_half_away(span * detail::steps_num(m), detail::steps_den(m)) > 2147483647LL)
    return kMotorTooFine;
  return kMotorOk;
}

// The step an absolute actuator angle quantizes to (the rounding rule above). For an angle
// within the limits of a validated motor the result always fits; far outside them it may not.
inline int32_t quantize(const MotorSpec& m, Millideg angle) {
  const int64_t n = int64_t(m.direction) * (int64_t(angle) - m.zero) * detail::steps_num(m);
  return int32_t(detail::div_round_half_away(n, detail::steps_den(m)));
}

namespace detail {
// The last whole step inside the limits towards more steps (upper) or fewer: one function
// for both ends, so the Nano holds its 64-bit arithmetic once. ceil(x / d) = -floor(-x / d).
inline int32_t limit_steps(const MotorSpec& m, bool upper) {
  const bool at_max = upper == (m.direction > 0);  // the angle limit that bounds this end
  const int64_t x = int64_t(m.direction) * (int64_t(at_max ? m.max : m.min) - m.zero) * steps_num(m);
  const int64_t f = div_floor(upper ? x : -x, steps_den(m));
  return int32_t(upper ? f : -f);
}
}  // namespace detail

// The whole-step range inside the limits (whole steps only: never a step past a limit).
inline int32_t min_steps(const MotorSpec& m) { return detail::limit_steps(m, false); }

inline int32_t max_steps(const MotorSpec& m) { return detail::limit_steps(m, true); }

// The step a commanded angle within the limits drives to: the nearest step, but never one
// past a limit (the rule at the top of this file). Outside the limits: the nearest step.
// (Equal to clamp(quantize, min_steps, max_steps) within the limits, without their divisions:
// the nearest step is at most one step past a limit the angle is within, and step s's angle
// is zero + direction * s * den / num, so s * den against (limit - zero) * num tells. For a
// validated motor both products fit an int64: |limit - zero| * num <= 2e9 * 2^31, and s * den
// is within den / 2 of (angle - zero) * num.)
inline int32_t quantize_within_limits(const MotorSpec& m, Millideg angle) {
  const int32_t s = quantize(m, angle);
  if (angle < m.min || angle > m.max) return s;
  const int64_t at = int64_t(m.direction) * s * detail::steps_den(m), num = detail::steps_num(m);
  if (at > (int64_t(m.max) - m.zero) * num) return s - m.direction;
  if (at < (int64_t(m.min) - m.zero) * num) return s + m.direction;
  return s;
}

// Degrees per step at the actuator (the resolution a user sees).
template <typename Scalar>
inline Scalar degrees_per_step(const MotorSpec& m) {
  return Scalar(360) * Scalar(m.gear_den) / (Scalar(m.full_steps_per_rev) * Scalar(m.microsteps) * Scalar(m.gear_num));
}

// The actuator angle a step count really gives, in degrees.
template <typename Scalar>
inline Scalar steps_to_degrees(const MotorSpec& m, int32_t steps) {
  return Scalar(m.zero) / Scalar(1000) + Scalar(m.direction) * Scalar(steps) * degrees_per_step<Scalar>(m);
}

// The actuator angle a step count gives, in exact thousandths of a degree: the step's angle
// rounded to the nearest millidegree, a half away from zero (integer arithmetic, so the Nano
// and the host agree). What a status report's A field shows, and the commanded angle the
// firmware takes after a stop. For step counts within the limits of a validated motor (the
// product below then fits an int64). quantize() of the result gives the step back whenever
// a step is more than 0.002 degrees.
inline Millideg steps_to_millideg(const MotorSpec& m, int32_t steps) {
  const int64_t n = int64_t(m.direction) * steps * detail::steps_den(m);
  return Millideg(m.zero + detail::div_round_half_away(n, detail::steps_num(m)));
}

// What quantization leaves: (angle reached) - (angle commanded), in degrees.
template <typename Scalar>
inline Scalar quantization_error_degrees(const MotorSpec& m, Millideg angle) {
  // Subtract in integer-exact parts first so the double result is exact to ~1e-12 deg.
  const int32_t s = quantize(m, angle);
  return Scalar(m.zero - angle) / Scalar(1000) + Scalar(m.direction) * Scalar(s) * degrees_per_step<Scalar>(m);
}

// Degrees (any scalar) to exact millidegrees, rounded half away from zero. NaN and
// values beyond kMaxAbsMillideg give false.
template <typename Scalar>
inline bool to_millideg(Millideg& out, Scalar degrees) {
  if (!is_finite(degrees)) return false;
  const Scalar m = degrees * Scalar(1000);
  if (m > Scalar(kMaxAbsMillideg) || m < -Scalar(kMaxAbsMillideg)) return false;
  // Truncate, then round on the exact remainder (m - r is exact for |m| < 2^31): m + 0.5
  // would itself round, e.g. to the even neighbour where a float holds only integers.
  Millideg r = Millideg(m);
  const Scalar frac = m - Scalar(r);
  if (frac >= Scalar(0.5)) ++r;
  if (frac <= Scalar(-0.5)) --r;
  out = r;
  return true;
}

// All motors of an arm and how they drive its joint variables.
template <typename Scalar, int MaxJoints>
struct Actuation {
  uint8_t num_motors;
  MotorSpec motors[MaxJoints];
  Scalar coupling[MaxJoints][MaxJoints];      // q = C * u (u in rad; q in rad or mm)
  Scalar coupling_inv[MaxJoints][MaxJoints];  // u = C^-1 * q, from invert_coupling()
};

// Computes coupling_inv by Gauss-Jordan elimination with partial pivoting. False when C is
// singular (a pivot below 1e-6 of the largest entry): some joint would have no motor.
template <typename S, int J>
inline bool invert_coupling(Actuation<S, J>& a) {
  const int n = a.num_motors;
  S m[J][2 * J];
  S scale = S(0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      m[i][j] = a.coupling[i][j];
      m[i][n + j] = i == j ? S(1) : S(0);
      if (!is_finite(m[i][j])) return false;
      scale = max_of(scale, Math<S>::fabs(m[i][j]));
    }
  if (scale == S(0)) return false;
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (Math<S>::fabs(m[r][c]) > Math<S>::fabs(m[p][c])) p = r;
    if (Math<S>::fabs(m[p][c]) < S(1e-6) * scale) return false;
    for (int k = 0; k < 2 * n; ++k) {
      const S t = m[c][k];
      m[c][k] = m[p][k];
      m[p][k] = t;
    }
    const S inv = S(1) / m[c][c];
    for (int k = 0; k < 2 * n; ++k) m[c][k] *= inv;
    for (int r = 0; r < n; ++r) {
      if (r == c || m[r][c] == S(0)) continue;
      const S f = m[r][c];
      for (int k = 0; k < 2 * n; ++k) m[r][k] -= f * m[c][k];
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a.coupling_inv[i][j] = m[i][n + j];
  return true;
}

// q = C * u (u actuator angles in rad).
template <typename S, int J>
inline void joints_from_actuators(S* q, const Actuation<S, J>& a, const S* u) {
  for (int i = 0; i < a.num_motors; ++i) {
    S v = S(0);
    for (int j = 0; j < a.num_motors; ++j) v += a.coupling[i][j] * u[j];
    q[i] = v;
  }
}

// u = C^-1 * q.
template <typename S, int J>
inline void actuators_from_joints(S* u, const Actuation<S, J>& a, const S* q) {
  for (int i = 0; i < a.num_motors; ++i) {
    S v = S(0);
    for (int j = 0; j < a.num_motors; ++j) v += a.coupling_inv[i][j] * q[j];
    u[i] = v;
  }
}

// The joint values a set of step counts really gives.
template <typename S, int J>
inline void joints_from_steps(S* q, const Actuation<S, J>& a, const int32_t* steps) {
  S u[J];
  for (int i = 0; i < a.num_motors; ++i) u[i] = deg_to_rad(steps_to_degrees<S>(a.motors[i], steps[i]));
  joints_from_actuators(q, a, u);
}

// Where the motors are: the exact commanded actuator angles and the steps they quantize
// to. steps[i] == quantize_within_limits(motors[i], commanded[i]) always holds.
template <int MaxJoints>
struct MotorState {
  Millideg commanded[MaxJoints];
  int32_t steps[MaxJoints];
};

// Every motor at its zero angle (step 0).
template <typename S, int J>
inline void reset(MotorState<J>& st, const Actuation<S, J>& a) {
  for (int i = 0; i < a.num_motors; ++i) {
    st.commanded[i] = a.motors[i].zero;
    st.steps[i] = 0;
  }
}

// Sets every motor's commanded angle at once. All targets are checked before anything
// changes (on an error the state is untouched): each angle must lie within its motor's
// limits; its step is quantize_within_limits(), so never past a limit.
template <typename S, int J>
inline Status move_absolute(MotorState<J>& st, const Actuation<S, J>& a, const Millideg* target) {
  int32_t steps[J];
  for (int i = 0; i < a.num_motors; ++i) {
    if (target[i] < -kMaxAbsMillideg || target[i] > kMaxAbsMillideg) return kValueOutOfRange;
    if (target[i] < a.motors[i].min || target[i] > a.motors[i].max) return kJointLimit;
    steps[i] = quantize_within_limits(a.motors[i], target[i]);
  }
  for (int i = 0; i < a.num_motors; ++i) {
    st.commanded[i] = target[i];
    st.steps[i] = steps[i];
  }
  return kOk;
}

// Turns one actuator by a relative angle (the original `L <joint> <deg>`).
template <typename S, int J>
inline Status move_relative(MotorState<J>& st, const Actuation<S, J>& a, uint8_t motor, Millideg delta) {
  if (motor >= a.num_motors) return kBadJoint;
  Millideg target[J];
  for (int i = 0; i < a.num_motors; ++i) target[i] = st.commanded[i];
  const int64_t t = int64_t(st.commanded[motor]) + delta;
  if (t < -kMaxAbsMillideg || t > kMaxAbsMillideg) return kValueOutOfRange;
  target[motor] = Millideg(t);
  return move_absolute(st, a, target);
}

}  // namespace articula

#endif  // ARTICULA_ACTUATION_H
