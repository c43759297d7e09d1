// articula/motion.h - the step timing of a move: when each step happens, in timer ticks.
//
// The firmware steps the motors from a timer interrupt with this code, and the host
// predicts a move's duration and every step's time by running the same code. So all of it
// is integer arithmetic (uint32 per step, uint64 only when a move starts): the Nano and the
// host compute the same intervals, tick for tick.
//
// The speed profile (after Atmel's application note AVR446, "Linear speed control of
// stepper motor"). From rest at a constant acceleration a (steps/s^2) the motor is at
// x = a t^2 / 2, so step k comes at t_k = sqrt(2k / a). In ticks of a timer at f Hz the
// intervals are
//
//   c_n = t_{n+1} - t_n = c0 (sqrt(n + 1) - sqrt(n)),   c0 = f sqrt(2 / a)   (n = 0, 1, ...)
//
// AVR446 replaces the square roots with the first terms of their Taylor series, a
// recurrence of one division per step:
//
//   c_n = c_{n-1} - 2 c_{n-1} / (4n + 1)
//
// Its product of (4n - 1) / (4n + 1) tends to G(5/4) / G(3/4) / sqrt(n) = 0.7397 / sqrt(n)
// (G the gamma function) while the ideal c_n tends to c0 / (2 sqrt(n)); so the recurrence
// starts from c0' = c0 G(3/4) / (2 G(5/4)) = 0.67598 c0 (AVR446's "0.676") and its
// intervals converge to the ideal ones (2.1 % short at n = 1, 0.75 % at n = 2, under 0.05 %
// from n = 10). The first interval itself, from rest to step 1, is the exact c0: then every
// step comes within 0.014 c0 of its ideal time (0.3 ms for the MK2 base at 4000 steps/s^2).
//
// Exact integers. C = c * 256 (8 fraction bits), and the division's remainder r is carried
// to the next step so rounding never accumulates. Climbing from level n - 1 to n:
//
//   q = (2C + r) / (4n + 1),   r' = (2C + r) % (4n + 1),   C' = C - q
//
// is a bijection: r <= 4n - 4 (the previous remainder) leaves one q that fits, so descending
// undoes it
//
//   q = ceil((2C' - r') / (4n - 1))  (0 when 2C' <= r'),   r = q (4n - 1) - (2C' - r'),   C = C' + q
//
// and gives back, bit for bit, the (C, r) the climb started from: the deceleration replays
// the acceleration's values in reverse. c0 = isqrt(2^17 f^2 / a) / 256, once per move.
//
// Whole ticks. Each interval is C rounded on its own. Carrying the fraction instead would
// keep every step within half a tick of the fixed-point time, but near a half tick the
// intervals would then alternate (20, 21, 20, ...): not monotone, a tick of jitter. Rounded
// alone they stay monotone and mirror exactly, at a bias of under half a tick a step (under
// 0.025 % of the MK2's 2000-tick cruise, 2.5 % at the 20-tick floor). The host runs this
// same code, so its predictions are exact either way.
//
// The shape. L is the ramp level (steps taken while accelerating; the state holds c_{L-1})
// and R the steps left, counting the one being timed:
//   R <= L      decelerate: the interval is c_{R-1}, the mirror of the climb (then R == L);
//   R == L + 1  the middle step: c_L without climbing, so the descent mirrors the climb
//               (a triangle for short moves: c_0 .. c_{m-1} c_m c_{m-1} .. c_0);
//   else        climb to c_L, unless c_L is below the cruise interval round(f / max_rate):
//               then cruise at that interval until R == L.
// The ramp to max_rate takes about max_rate^2 / (2 accel) steps, and so does a stop().
#ifndef ARTICULA_MOTION_H
#define ARTICULA_MOTION_H

#include "platform.h"

namespace articula {

// The firmware's step timer: Timer1 at 16 MHz with prescaler 8, 2,000,000 ticks a second. Every
// time the firmware keeps, and every time the host predicts, is in its ticks: this is the one
// place the figure is written (the host library, Python's articula._core.STEP_TICK_HZ and the
// web engine's stepTickHz take it from here).
static const uint32_t kStepTickHz = 2000000UL;

struct MotionSettings {
  uint32_t tick_hz;   // timer ticks per second (the firmware: kStepTickHz)
  uint32_t max_rate;  // top step rate of the dominant motor, steps/s
  uint32_t accel;     // acceleration of the dominant motor, steps/s^2
};

// Fastest timer: 16 MHz (no AVR timer counts faster than its clock); keeps 2^16 f^2 in a
// uint64.
static const uint32_t kMaxTickHz = 16000000UL;
// Shortest interval: leaves the interrupt time to step three motors and work out the next one.
static const uint32_t kMinStepTicks = 20;
// Longest interval (first step or cruise): keeps 2 * 256 * c in a uint32 (2.1 s at 2 MHz).
static const uint32_t kMaxStepTicks = 4194304UL;  // 2^22
// Longest ramp: c0 below 2^13 cruise intervals, i.e. max_rate^2 / (2 accel) below 2^24
// steps (c0 / cruise = 2 sqrt(ramp)). Keeps the level n, 4n + 1 and 2C + r in a uint32.
static const uint32_t kMaxRampRatio = 8192;  // 2^13

enum MotionError : uint8_t {
  kMotionOk = 0,
  kMotionZero,          // a setting is zero
  kMotionTickTooFast,   // tick_hz above kMaxTickHz
  kMotionTooFast,       // cruise interval round(tick_hz / max_rate) below kMinStepTicks
  kMotionTooSlow,       // cruise or first interval beyond kMaxStepTicks
  kMotionRampTooLong,   // c0 of kMaxRampRatio cruise intervals or more: a ramp of ~2^24 steps
};

// Short texts: on the Nano they sit in RAM.
inline const char* motion_error_text(MotionError e) {
  switch (e) {
    case kMotionOk: return "ok";
    case kMotionZero: return "a setting is 0";
    case kMotionTickTooFast: return "tick_hz above 16 MHz";
    case kMotionTooFast: return "interval below 20 ticks";
    case kMotionTooSlow: return "interval above 2^22 ticks";
    case kMotionRampTooLong: return "ramp of 2^24 steps";
  }
  return "?";
}

namespace detail {
// Fixed point: intervals in 1/256 tick.
static const uint8_t kMotionFracBits = 8;
static const uint32_t kMotionHalfTick = 128;

// floor(sqrt(hi * 2^32 + lo)) for values up to 2^60, one result bit per round (the binary
// digit-by-digit method) in 32-bit words: the remainder stays below 2 root + 1 <= 2^31 + 1.
inline uint32_t isqrt64(uint32_t hi, uint32_t lo) {
  uint32_t root = 0, rem = 0;
  for (uint8_t i = 0; i < 32; ++i) {
    rem = (rem << 2) | (hi >> 30);
    hi = (hi << 2) | (lo >> 30);
    lo <<= 2;
    root <<= 1;
    if (rem > 2 * root) {  // rem >= 2 root + 1
      rem -= 2 * root + 1;
      root |= 1;
    }
  }
  return root;
}

// Fixed-point interval to whole ticks, rounded.
inline uint32_t whole_ticks(uint32_t c) { return (c + kMotionHalfTick) >> kMotionFracBits; }

// The checks of validate() and, on the way, the two constants a move starts from: the
// cruise interval round(f / v) in ticks and c0 = f sqrt(2 / a) in ticks * 256.
inline MotionError motion_constants(uint32_t& cruise_out, uint32_t& c0_out, const MotionSettings& s) {
  const uint32_t f = s.tick_hz, v = s.max_rate, a = s.accel;  // copies: the outputs may alias s
  cruise_out = c0_out = 0;
  if (f == 0 || v == 0 || a == 0) return kMotionZero;
  if (f > kMaxTickHz) return kMotionTickTooFast;
  uint32_t cruise = f / v;
  const uint32_t rest = f % v;
  if (rest >= v - rest) ++cruise;  // halves round up
  if (cruise < kMinStepTicks) return kMotionTooFast;
  if (cruise > kMaxStepTicks) return kMotionTooSlow;
  // (256 c0)^2 = 2^17 f^2 / a, as 2 * floor(2^16 f^2 / a) (f < 2^24: no overflow).
  const uint64_t sq = ((uint64_t(f) * f << 16) / a) << 1;
  const uint32_t hi = uint32_t(sq >> 32);
  if (hi >= (1UL << 28)) return kMotionTooSlow;  // c0 >= 2^22 ticks
  const uint32_t c0 = isqrt64(hi, uint32_t(sq));
  cruise_out = cruise;
  c0_out = c0;
  if ((c0 >> 8) / kMaxRampRatio >= cruise) return kMotionRampTooLong;  // c0 >= 2^13 cruise
  return kMotionOk;
}
}  // namespace detail

inline MotionError validate(const MotionSettings& s) {
  uint32_t cruise, c0;
  return detail::motion_constants(cruise, c0, s);
}

// What a StepProfile starts from, which depends on the settings only: computing it costs a
// 64-bit division and a 32-round square root (1.3 ms on the Nano), so the firmware does it
// once per settings change, in its main loop, and starts each move in the step interrupt
// from these (StepProfile::start(total_steps, constants)). All zero for invalid settings.
struct ProfileConstants {
  uint32_t cruise;  // cruise interval round(f / max_rate), whole ticks
  uint32_t first;   // the first interval c0 in whole ticks, never below the cruise interval
  uint32_t c0r;     // the recurrence's start c0' = 0.675978 c0, ticks * 256
};

inline MotionError profile_constants(ProfileConstants& out, const MotionSettings& s) {
  uint32_t cruise, c0;
  const MotionError e = detail::motion_constants(cruise, c0, s);
  if (e != kMotionOk) {
    out.cruise = out.first = out.c0r = 0;
    return e;
  }
  out.cruise = cruise;
  out.first = max_of(detail::whole_ticks(c0), cruise);
  // c0' = c0 G(3/4) / (2 G(5/4)) = 0.675978 c0 = c0 * 44301 / 2^16, rounded.
  out.c0r = uint32_t((uint64_t(c0) * 44301UL + 0x8000UL) >> 16);
  return kMotionOk;
}

// The intervals of one move of the dominant motor. start(), then next_interval() until
// done(). Small enough to live in the firmware's interrupt state (30 bytes on the Nano).
//
// Blending (the look-ahead planner, planner.h). A move need not end at rest: it ends at an
// exit level E, the ramp level the next move starts from, and the next move follow()s on
// from the state this one left (level, interval, remainder), so the speed carries over the
// junction. Such a move is the part of a rest-to-rest move of entry + steps + E steps that
// lies after its first `entry` steps: the rules above hold with R = steps left + E. With
// E = 0 everywhere every move is today's rest-to-rest move, tick for tick.
//
// The exit may be raised while the move runs (a line arrived behind it), until the first
// step whose interval depends on it: the middle step of a triangle or the first step of the
// descent. That step latches the exit; a later raise is refused. Every interval before the
// latch is the same for any higher exit, so a raise that comes in time gives the very move
// it would have been had the next line been there from the start.
class StepProfile {
 public:
  // (constexpr: a static one is all zero in .bss, with no constructor run at start-up)
  constexpr StepProfile()
      : left_(0), level_(0), c_(0), rem_(0), cruise_(0), first_(0), exit_(0), cruising_(false), latched_(false) {}

  // A move of total_steps from rest to rest. Invalid settings (validate()) give an empty
  // move. Costs a 64-bit division and a 32-round square root: call it outside the
  // interrupt if that matters, or use the overload below.
  void start(uint32_t total_steps, const MotionSettings& s) {
    ProfileConstants k;
    profile_constants(k, s);
    start(total_steps, k);
  }

  // The same move from constants computed beforehand (profile_constants()): a few
  // assignments, cheap enough for an interrupt. Constants of invalid settings (all zero)
  // give an empty move. `exit`: the level to end at (0: at rest). `cruise`: this move's
  // own cruise interval in whole ticks, slower than the settings' (a straight line's
  // segment at its tool speed, line.h); 0: the settings' (k.cruise).
  void start(uint32_t total_steps, const ProfileConstants& k, uint32_t exit = 0, uint32_t cruise = 0) {
    left_ = k.cruise != 0 ? total_steps : 0;
    level_ = 0;
    rem_ = 0;
    cruising_ = false;
    latched_ = false;
    exit_ = exit;
    cruise_ = max_of(cruise, k.cruise) << detail::kMotionFracBits;
    first_ = k.first;
    c_ = k.c0r;
  }

  // The next move of a blended stream, from where the last one ended (its level, at its
  // exit), to end at level `exit`, cruising at `cruise` whole ticks (its own, or the
  // settings'). After a move that ended at rest it is start(). A faster cruise climbs on
  // from the level reached; a slower one is entered at or below its level
  // (cruise_level_cap(), which the planner keeps to), so every interval stays on the ramp.
  void follow(uint32_t total_steps, uint32_t exit, uint32_t cruise) {
    left_ = cruise_ != 0 ? total_steps : 0;
    exit_ = exit;
    latched_ = false;
    if (cruise_ != 0) cruise_ = cruise << detail::kMotionFracBits;
    cruising_ = false;  // the next climb looks at this move's cruise again
  }

  // Raises the level the move ends at, unless a step already depended on it. True when taken.
  bool raise_exit(uint32_t exit) {
    if (latched_ || exit < exit_) return false;
    exit_ = exit;
    return true;
  }

  bool done() const { return left_ == 0; }
  uint32_t steps_left() const { return left_; }
  // The ramp level now: about v^2 / (2 accel) at the speed v of the last step.
  uint32_t level() const { return level_; }
  uint32_t exit_level() const { return exit_; }
  bool latched() const { return latched_; }

  // Ticks from the previous step (or the start) to the next step; 0 once done().
  uint32_t next_interval() {
    const uint32_t left = left_;
    if (left == 0) return 0;
    left_ = left - 1;
    const uint32_t r = left + exit_;  // R: steps left of the rest-to-rest move this is part of
    if (r <= level_) {
      // Descend: emit c_{L-1}, then go one level down with the exact inverse of a climb,
      // q = ceil((2C - r) / d) written as floor((2C - r + d - 1) / d) (never negative:
      // r <= d + 1), which also gives q = 0, r -= 2C when 2C <= r.
      latched_ = true;
      cruising_ = false;  // a move that follows may climb again
      if (--level_ == 0) return first_interval();
      const uint32_t out = detail::whole_ticks(c_);
      const uint32_t d = 4 * level_ - 1;
      const uint32_t y = 2 * c_ + (d - 1) - rem_;
      c_ += y / d;
      rem_ = (d - 1) - y % d;
      return out;
    }
    if (cruising_) return cruise_ >> detail::kMotionFracBits;
    if (level_ == 0) {
      if (r > 1)
        level_ = 1;  // the state already holds c_0'
      else
        latched_ = true;
      return first_interval();
    }
    // Climb: c_L from c_{L-1}, the one division of the step.
    const uint32_t y = 2 * c_ + rem_;
    const uint32_t d = 4 * level_ + 1;
    const uint32_t next = c_ - y / d;
    if (next < cruise_) {
      cruising_ = true;  // top speed: the level stays, the descent starts from c_{L-1}
      return cruise_ >> detail::kMotionFracBits;
    }
    if (r > level_ + 1) {  // else the middle step: c_L without climbing
      c_ = next;
      rem_ = y % d;
      ++level_;
    } else {
      latched_ = true;
    }
    return detail::whole_ticks(next);
  }

  // Decelerate now, from the current speed, to rest in as few steps as accel allows: the
  // current ramp level, about v^2 / (2 accel) steps. Does nothing while already slowing.
  // When fewer steps are left than that, the move ends still moving, at level() - steps
  // left: the stop goes on into the move after it (follow(..., 0) and stop() again).
  void stop() {
    left_ = min_of(left_, level_);
    exit_ = 0;
    latched_ = true;
  }

  // Steps a stop() now would still take (in this move).
  uint32_t stop_steps() const { return min_of(left_, level_); }

 private:
  // The level-0 interval: c0, or a slower cruise.
  uint32_t first_interval() const { return max_of(first_, cruise_ >> detail::kMotionFracBits); }

  uint32_t left_;    // steps still to time (cut by stop())
  uint32_t level_;   // ramp level L
  uint32_t c_;       // c_{L-1} (c_0' at level 0), ticks * 256
  uint32_t rem_;     // the recurrence's carried remainder
  uint32_t cruise_;  // cruise interval, ticks * 256
  uint32_t first_;   // the level-0 interval c0 in ticks (never below the cruise interval)
  uint32_t exit_;    // the level to end at (0: at rest)
  bool cruising_;
  bool latched_;     // a step depended on exit_: it may not change any more
};

// The highest ramp level a move cruising at `cruise` whole ticks may be entered at: a level
// whose speed is still below that cruise, so the move goes on climbing (or cruises) and never
// jumps down to it. Level n is the speed f / c_n with c_n >= 0.979 c0 / (2 sqrt(n + 1)) on
// the recurrence (2.1 % short of the ideal at n = 1, less beyond) and c0 = f sqrt(2 / a): at
// most sqrt(2 a (n + 1)) / 0.979 steps/s. So n + 1 <= 0.479 r^2 / a for the cruise rate
// r = f / cruise keeps it below; 15/32 (0.469) leaves room for whole ticks. Integers only,
// exact for every r below 2^16 (r^2 in 32 bits; r^2 * 15 would not be above 16,921 steps/s):
// floor(15 r^2 / 32) = 15 floor(r^2 / 32) + floor(15 (r^2 mod 32) / 32). A cruise no slower
// than the settings' needs no cap (0xFFFF: any level).
inline uint16_t cruise_level_cap(const MotionSettings& s, uint32_t settings_cruise, uint32_t cruise) {
  if (cruise <= settings_cruise || s.accel == 0) return 0xFFFF;
  const uint32_t r = s.tick_hz / cruise;
  const uint32_t n = uint32_t(uint64_t(r * r) * 15 >> 5) / s.accel;
  return n == 0 ? 0 : n > 0xFFFF ? 0xFFFF : uint16_t(n - 1);
}

namespace detail {
// Runs a whole profile: returns its duration in ticks and writes the first max_times step
// times (from the start) to times.
inline uint64_t run_profile(uint64_t* times, uint32_t max_times, uint32_t total_steps, const MotionSettings& s) {
  StepProfile p;
  p.start(total_steps, s);
  uint64_t t = 0;
  for (uint32_t k = 0; !p.done(); ++k) {
    t += p.next_interval();
    if (k < max_times) times[k] = t;
  }
  return t;
}
}  // namespace detail

// Sum of a move's intervals: its duration in ticks, by running the profile (O(steps)).
inline uint64_t profile_duration_ticks(uint32_t total_steps, const MotionSettings& s) {
  return detail::run_profile(NULL, 0, total_steps, s);
}

// The time of each step from the start, in ticks: times[k] for step k + 1, at most
// max_times of them. Returns how many it wrote.
inline uint32_t profile_step_times(uint64_t* times, uint32_t max_times, uint32_t total_steps,
                                   const MotionSettings& s) {
  detail::run_profile(times, max_times, total_steps, s);
  return validate(s) == kMotionOk ? min_of(max_times, total_steps) : 0;
}

// A coordinated move of several motors along a straight line in step space (Bresenham's
// line algorithm): each call of next() is one step of the dominant motor (n = max |delta|
// calls in all, timed by a StepProfile of n steps) and says which motors step on it. Motor
// i steps |delta_i| times, on the calls k where floor((floor(n/2) + k |delta_i|) / n)
// grows: its steps are spread evenly, floor(n / |delta_i|) or ceil(n / |delta_i|) calls
// apart, centred in the move, and all motors arrive together. One add, one sign test and
// sometimes one subtraction per motor and call.
template <int MaxJoints>
struct LineStepper {
  static_assert(MaxJoints >= 1 && MaxJoints <= 8, "next() returns one bit per motor in a byte");

  uint32_t dominant;          // n: calls of next() in the move
  uint32_t left;              // calls still to come
  uint32_t count[MaxJoints];  // |delta_i| (up to 2^31)
  uint32_t error[MaxJoints];  // (floor(n/2) + k |delta_i|) mod n - n, in two's complement: in [-n, 0)
  uint8_t num_motors;
  uint8_t negative;           // bit i set: motor i steps towards negative counts

  void start(const int32_t* delta_steps, uint8_t motors) {
    num_motors = motors;
    negative = 0;
    dominant = 0;
    uint8_t bit = 1;
    for (uint8_t i = 0; i < motors; ++i, bit <<= 1) {
      uint32_t d = uint32_t(delta_steps[i]);
      if (delta_steps[i] < 0) {
        d = uint32_t(0) - d;  // |INT32_MIN| = 2^31 fits too
        negative |= bit;
      }
      count[i] = d;
      dominant = max_of(dominant, d);
    }
    left = dominant;
    for (uint8_t i = 0; i < motors; ++i) error[i] = dominant / 2 - dominant;
  }

  bool done() const { return left == 0; }

  // The motors that step on this dominant step, one bit each; 0 once done().
  uint8_t next() {
    if (left == 0) return 0;
    --left;
    uint8_t mask = 0, bit = 1;
    for (uint8_t i = 0; i < num_motors; ++i, bit <<= 1) {
      // The true value stays within [-2^31, 2^31): the sign bit decides.
      uint32_t e = error[i] + count[i];
      if ((e & 0x80000000UL) == 0) {
        e -= dominant;
        mask |= bit;
      }
      error[i] = e;
    }
    return mask;
  }
};

}  // namespace articula

#endif  // ARTICULA_MOTION_H
