// articula/line.h - the straight-line command, `T <x> <y> <z> <mm/s>`: the tool from where it
// is to a point along a straight line, at a tool speed.
//
// A move (M, P) is a straight line in step space, which is a curve in space. T cuts the line
// in space into segments whose ends lie on it, each one a move into the planner (planner.h,
// so they blend), short enough that the tool strays at most the chord tolerance ($7) from the
// line between them. The rule is this file's LineCutter, the same code on the Nano (through
// the closed form, in float) and on the host (the same, in float, for yaw-pitch-pitch arms;
// through the robot's own IK, in double, for every other robot):
//
//   From the last end, at fraction s of the line, try the end at s + h: solve it (the
//   solution nearest the last end's actuator angles), put the midpoint of the two ends'
//   actuator angles through the forward kinematics, and measure its distance from the line.
//   Farther than the tolerance: halve h and try again. Within it: that is the segment, and
//   the next try is twice as long. The first try is the whole line.
//
// A move is straight in actuator space, so its tool path bows the most near its middle: the
// midpoint is where the chord error is measured (Marlin and GRBL cut arcs by a chord error
// in the same spirit). A try no longer than the tolerance that still strays is the pose
// jumping (a singularity, or the nearest IK solution changing branch): the line is refused
// with kLineNotFollowed.
//
// Never stopped half way: a controller runs the rule over the whole line once to check it
// (every end solved within the limits; a segment between two ends within the limits stays
// within them, as the limits are a box in actuator space and a move is straight in it), then
// again to queue the segments. The same float operations give the same ends both times.
//
// Speed: each segment's dominant motor cruises at the rate that covers the segment's length
// at the tool speed (segment_ticks4, segment_cruise4), unless the settings' rate ($0) is
// slower. The planner
// blends the segments; a segment may be entered only at a ramp level below its own cruise
// (motion.h, cruise_level_cap).
#ifndef ARTICULA_LINE_H
#define ARTICULA_LINE_H

#include "actuation.h"
#include "ik_ypp.h"
#include "status.h"

namespace articula {

// P's rule (the firmware's point_angles, the prediction's solve_point): the closed form in
// float, the in-limits solution nearest `near` (least sum of squared actuator differences, in
// float), each angle rounded to a millidegree and clamped into its limits (in float the
// solution is within them, at most a rounding beyond). kUnreachable when no solution is within
// the limits. Three motors.
inline Status ypp_point_angles(Millideg* best, const YppArm<float>& arm, const MotorSpec* motors, const Vec3<float>& p,
                               const Millideg* near) {
  YppResult<float> r;
  if (ypp_closed_form(r, arm, p, false) == 0) return kUnreachable;
  float best_d2 = -1;
  for (uint8_t k = 0; k < r.count; ++k) {
    if (!r.solutions[k].in_limits) continue;
    float act[3];
    ypp_actuated(act, arm, r.solutions[k].q);
    Millideg t[3];
    float d2 = 0;
    for (uint8_t i = 0; i < 3; ++i) {
      if (!to_millideg(t[i], rad_to_deg(act[i]))) return kUnreachable;
      t[i] = clamp(t[i], motors[i].min, motors[i].max);
      d2 += square(float(t[i] - near[i]));
    }
    if (best_d2 < 0 || d2 < best_d2) {
      best_d2 = d2;
      for (uint8_t i = 0; i < 3; ++i) best[i] = t[i];
    }
  }
  return kOk;
}

// The tool point (mm, x y z into p) of a yaw-pitch-pitch arm at actuator angles in
// millidegrees.
inline void ypp_tool_at(float* p, const YppArm<float>& arm, const Millideg* act) {
  float q[3];
  for (uint8_t i = 0; i < 3; ++i) q[i] = deg_to_rad(float(act[i]) * 0.001f);
  if (arm.parallelogram) q[2] -= q[1];
  const Vec3<float> t = ypp_tool_position(arm, q);
  p[0] = t.x;
  p[1] = t.y;
  p[2] = t.z;
}

// LineCutter's solver for a yaw-pitch-pitch arm: the Nano's, and the host's for such arms.
struct YppLineSolver {
  const YppArm<float>* arm;
  const MotorSpec* motors;

  Status solve(Millideg* out, const float* p, const Millideg* near) const {
    return ypp_point_angles(out, *arm, motors, make_vec3(p[0], p[1], p[2]), near);
  }
  void tool(float* p, const Millideg* act) const { ypp_tool_at(p, *arm, act); }
};

// The segments of one straight line, one at a time (the rule above). S: float on the Nano
// and for its arms on the host, double for the host's other robots. J: room for the motors.
// A Solver has
//   Status solve(Millideg* out, const S* p, const Millideg* near) const;  // p: x y z, mm
//   void tool(S* p, const Millideg* act) const;
// Written with loops over x, y, z rather than vector expressions: on the Nano each float
// operation is a call, and a loop holds one copy of it.
template <typename S, int J>
class LineCutter {
 public:
  // The line from `from` to `to` (mm, x y z); `at`: the actuator angles at `from` (millidegrees,
  // `motors` of them); `tolerance`: the chord tolerance, mm. A line of length 0 is done at
  // once: it has no segment.
  void start(const S* from, const S* to, const Millideg* at, uint8_t motors, S tolerance) {
    S l2 = 0;
    for (uint8_t k = 0; k < 3; ++k) {
      from_[k] = from[k];
      d_[k] = to[k] - from[k];
      l2 += d_[k] * d_[k];
    }
    len_ = Math<S>::sqrt(l2);
    tol_ = tolerance;
    motors_ = motors;
    for (uint8_t i = 0; i < motors; ++i) at_[i] = at[i];
    s_ = len_ > S(0) ? S(0) : S(1);
    h_ = S(1);
    seg_ = S(0);
  }

  bool done() const { return !(s_ < S(1)); }
  S length() const { return len_; }
  // The length of the segment next() gave last, mm.
  S segment_length() const { return seg_; }
  // The fraction of the line done (after a refusal: up to the last end that was good).
  S done_fraction() const { return s_; }
  // The fraction of the line at the try next() refused last.
  S refused_fraction() const { return s_ + h_ < S(1) ? s_ + h_ : S(1); }

  // The next segment's end into end[] (actuator angles, millidegrees): kOk, or why the line
  // cannot be followed there (the solver's status, or kLineNotFollowed). Call while !done().
  template <class Solver>
  Status next(const Solver& solver, Millideg* end) {
    for (;;) {
      S s1 = s_ + h_;
      if (!(s1 < S(1))) s1 = S(1);
      S p[3];
      for (uint8_t k = 0; k < 3; ++k) p[k] = from_[k] + s1 * d_[k];
      const Status st = solver.solve(end, p, at_);
      if (st != kOk) return st;
      Millideg mid[J];
      for (uint8_t i = 0; i < motors_; ++i) mid[i] = at_[i] + (end[i] - at_[i]) / 2;
      // The midpoint's distance from the line is |(m - from) x d| / len.
      S v[3], c2 = 0;
      solver.tool(v, mid);
      for (uint8_t k = 0; k < 3; ++k) v[k] -= from_[k];
      for (uint8_t k = 0; k < 3; ++k) {
        const uint8_t a = k == 2 ? 0 : k + 1, b = k == 0 ? 2 : k - 1;
        const S c = v[a] * d_[b] - v[b] * d_[a];
        c2 += c * c;
      }
      const S h = s1 - s_;
      const S seg = h * len_;
      if (c2 > tol_ * tol_ * len_ * len_) {
        if (!(seg > tol_)) return kLineNotFollowed;
        h_ = h * S(0.5);
        continue;
      }
      h_ = h * S(2);
      s_ = s1;
      seg_ = seg;
      for (uint8_t i = 0; i < motors_; ++i) at_[i] = end[i];
      return kOk;
    }
  }

 private:
  S from_[3], d_[3];
  S len_, tol_, s_, h_, seg_;
  Millideg at_[J];
  uint8_t motors_;
};

// A segment's duration at the tool speed, in units of 4 timer ticks: tick_hz * length /
// speed / 4, rounded, at most 2^31. In float, the same on the Nano and the host (a
// multiplication and a division). Each segment's own cruise interval is this over its
// dominant steps (segment_cruise4).
inline uint32_t segment_ticks4(float length_mm, float speed, uint32_t tick_hz) {
  if (!(speed > 0.0f)) return 0;
  const volatile float ticks = float(int32_t(tick_hz / 4)) * length_mm;  // volatile: no contraction
  const float c = ticks / speed;
  return c >= 2147483648.0f ? 0x80000000UL : uint32_t(c + 0.5f);
}

// PlanBlock::cruise4 of a segment of `steps` dominant steps that lasts `ticks4`
// (segment_ticks4): the interval in units of 4 ticks, rounded, at most 65535 (262,140
// ticks: 7.6 steps a second at 2 MHz). 0 for a segment without steps, or a move that is not a
// segment (ticks4 0).
inline uint16_t segment_cruise4(uint32_t steps, uint32_t ticks4) {
  if (steps == 0 || ticks4 == 0) return 0;
  const uint32_t c = (ticks4 + steps / 2) / steps;
  return c > 0xFFFF ? 0xFFFF : uint16_t(c);
}

}  // namespace articula

#endif  // ARTICULA_LINE_H
