// articula/planner.h - the look-ahead planner: how fast a stream of queued moves may pass
// from one to the next, in the ramp levels of motion.h.
//
// Each move is a straight line in step space, timed by a StepProfile of its dominant
// motor's n steps. Speeds are ramp levels: level L is the speed sqrt(2 a L) of the
// dominant motor, in its steps, L steps after a start from rest (motion.h). At a junction
// the level carries over: the dominant motor of the move before and the one after both step
// at the level's speed.
//
// The junction rule, in step space (after GRBL's junction deviation, planner.c). GRBL rounds
// a corner with a circular arc whose distance from the corner is the junction deviation d,
// and takes the speed at which the arc's centripetal acceleration is the acceleration limit.
// Our moves are in motor steps, not millimetres, and each motor has its own acceleration
// limit, so the same idea is applied per motor. At the junction motor i's rate changes from
// v u_i to v w_i (v the dominant rate, u = delta / n of the move before, w of the move
// after, each |u_i| <= 1). Blended at the acceleration a, a change dv takes dv / a and
// leaves the motor dv^2 / (8 a) behind (or ahead of) the sharp corner; allowing every
// motor a deviation d (in steps) gives dv <= sqrt(8 a d), so
//
//   v^2 <= 8 a d / m^2,   m = max_i |u_i - w_i|,   and the level  v^2 / (2 a) <= 4 d / m^2.
//
// The acceleration cancels: the junction level depends on the geometry and d only. Two
// moves in the same direction (m = 0) pass at any speed; a reversal (m = 2) at 4 d / 4 = d.
// It runs in the main loop when a move is queued, in integers and three IEEE float
// operations, so the Nano and the host's prediction plan the same levels.
//
// The plan (GRBL's reverse pass; the forward pass is the step interrupt itself, which
// climbs at most one level a step and so never goes faster than it can): the newest move
// ends at rest; going back, each move's entry is min(its junction level, its exit + its
// steps), and a move's exit is the next one's entry. A move that is not a move (a pause, the
// gripper, homing) ends the stream: the move before it ends at rest.
#ifndef ARTICULA_PLANNER_H
#define ARTICULA_PLANNER_H

#include "platform.h"

namespace articula {

// Junction levels are capped here (a uint16_t in the queue). The cruise level of the
// fastest settings is far below it at sensible accelerations (600 steps/s at 2000 steps/s^2
// is level 90); above it the cap only lowers the junction speed.
static const uint16_t kMaxJunctionLevel = 65535;

namespace detail {
// A move's deltas scaled down until its dominant count is at most 1023 (exact for shorter
// moves; for a longer one the direction to within a tenth of a percent): the junction then
// needs no 64-bit arithmetic.
inline uint32_t junction_direction(int32_t* out, const int32_t* delta, uint32_t n, uint8_t motors) {
  uint8_t shift = 0;
  while ((n >> shift) > 1023) ++shift;
  uint32_t m = 0;
  for (uint8_t i = 0; i < motors; ++i) {
    const uint32_t a = uint32_t(delta[i] < 0 ? -delta[i] : delta[i]) >> shift;
    out[i] = delta[i] < 0 ? -int32_t(a) : int32_t(a);
    if (a > m) m = a;
  }
  return m;
}
}  // namespace detail

// The level at which a move of delta_b (n_b dominant steps) may follow a move of delta_a
// (n_a), for a junction deviation of `deviation` hundredths of a step (the setting; 0: every
// junction at rest). Equal directions pass at kMaxJunctionLevel.
//
// level = 4 (deviation / 100) / m^2 = deviation r^2 / 25, r = n_a n_b / M = 1 / m, with
// M = max_i |a_i n_b - b_i n_a| in integers (exact: n at most 1023, M < 2^21) and r and the
// level in float: IEEE single precision, each operation rounded the same way on the Nano,
// the host and the web engine (three operations, no library call; 64-bit integers would
// cost the Nano 1.5 KB of flash).
// MaxMotors: the arrays' size (the Nano's three; its stack is short).
template <int MaxMotors>
uint16_t junction_level(const int32_t* delta_a, uint32_t n_a, const int32_t* delta_b, uint32_t n_b, uint8_t motors,
                        uint32_t deviation) {
  if (deviation == 0 || n_a == 0 || n_b == 0 || motors > MaxMotors) return 0;
  int32_t a[MaxMotors], b[MaxMotors];
  n_a = detail::junction_direction(a, delta_a, n_a, motors);
  n_b = detail::junction_direction(b, delta_b, n_b, motors);
  if (n_a == 0 || n_b == 0) return 0;
  int32_t big_m = 0;
  for (uint8_t i = 0; i < motors; ++i) {
    int32_t x = a[i] * int32_t(n_b) - b[i] * int32_t(n_a);
    if (x < 0) x = -x;
    if (x > big_m) big_m = x;
  }
  if (big_m == 0) return kMaxJunctionLevel;
  const volatile float r = float(int32_t(n_a * n_b)) / float(big_m);  // volatile: no contraction
  const volatile float r2 = r * r;
  const float level = float(int32_t(deviation)) * r2 / 25.0f;
  return level >= float(kMaxJunctionLevel) ? kMaxJunctionLevel : uint16_t(level);
}

// The motion queue's places (the firmware's queue::kSize, the prediction's): how far the
// planner sees ahead. As many as the Nano's RAM holds with 128 bytes of stack to spare at the
// deepest (20 bytes each; GRBL has 16 of 32 bytes and 1,633 bytes of static RAM).
static const uint8_t kQueueSize = 12;

// What the planner keeps of each queued action (the firmware's queue::Action, the host's
// model of it).
struct PlanBlock {
  uint16_t steps;      // a move's dominant steps, at most 65535 (no level is higher: the plan
                       // is the same); 0 for an action that is not a move
  uint16_t max_entry;  // the junction level with the move before (0 after rest or a non-move)
  uint16_t entry;      // the level the plan lets it start at
  uint16_t cruise4;    // a straight line's segment: its own cruise interval in units of 4
                       // ticks (line.h, segment_cruise4); 0: the settings' ($0)
};

// A move's cruise interval in whole ticks: its own, unless the settings' is slower.
inline uint32_t block_cruise(const PlanBlock& b, uint32_t settings_cruise) {
  return max_of(uint32_t(b.cruise4) * 4, settings_cruise);
}

// The reverse pass over `count` blocks, oldest first: block(k) reads block k (a ring, an
// array), set_entry(k, e) stores its entry (the firmware: with interrupts off, as the step
// interrupt reads it). The newest ends at rest. Returns the entry of the oldest (the exit of
// the move under way before it, when that is a move).
template <class BlockAt, class SetEntry, class Count>
uint16_t plan_entries(BlockAt block, SetEntry set_entry, Count count) {
  uint32_t exit = 0;
  for (Count k = count; k-- > 0;) {
    const PlanBlock& b = block(k);
    uint32_t e = 0;  // an action that is not a move: the move before it ends at rest
    if (b.steps != 0) {
      e = exit + b.steps;
      if (e > b.max_entry) e = b.max_entry;
    }
    set_entry(k, uint16_t(e));
    exit = e;
  }
  return uint16_t(exit);
}

}  // namespace articula

#endif  // ARTICULA_PLANNER_H
