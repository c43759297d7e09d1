// host/lib/replay.h - one move stepped as the firmware steps it (firmware/src/stepper.cpp's
// begin_move and move_tick): LineStepper spreads the dominant motor's steps over the others,
// StepProfile times them, and a move that follows one that ended moving goes on from its
// speed (a blended junction). The prediction's schedule (schedule.cpp) and the physics
// (host/physics/sim.cpp) replay a program's moves through it, so both step where and when the
// arm steps; predict.h's records say what each command is (PredictRecord::command).
//
//   MoveStepper m;
//   uint64_t t = t0 + m.begin(delta, motors, k, exit, cruise);  // 0 ticks: nothing to step
//   for (;;) {
//     const uint8_t mask = m.step();     // the step due at t: a bit per motor, signs in negative()
//     const uint32_t dt = m.next();      // the ticks to the next step; 0: the move is done
//     if (dt == 0) break;
//     t += dt;
//   }
#ifndef ARTICULA_HOST_REPLAY_H
#define ARTICULA_HOST_REPLAY_H

#include <articula/motion.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace articula::host {

class MoveStepper {
 public:
  static constexpr size_t kMaxMotors = 8;  // LineStepper's mask is a byte (the Nano drives 3)

  // begin_move(): a move of `delta` steps (per motor) to end at level `exit` (0: at rest),
  // cruising at `cruise` whole ticks a step when that is slower than k's (a straight line's
  // segment; 0: k's); `stopping`: cut to rest at once (a '!'). The ticks to its first step;
  // 0 when there is nothing to step (the profile is then left as it was). A robot of more
  // than kMaxMotors motors is timed by its dominant motor, its steps not spread (step() gives
  // no bits: the caller spreads them in proportion).
  uint32_t begin(const int32_t* delta, size_t motors, const ProfileConstants& k, uint32_t exit, uint32_t cruise,
                 bool stopping = false) {
    uint32_t dominant = 0;
    spread_ = motors <= kMaxMotors;
    if (spread_) {
      line_.start(delta, uint8_t(motors));
      dominant = line_.dominant;
    } else {
      for (size_t i = 0; i < motors; ++i) dominant = max_of(dominant, uint32_t(std::labs(long(delta[i]))));
    }
    dominant_ = dominant;
    if (dominant == 0) return 0;
    const uint32_t c = max_of(cruise, k.cruise);
    if (profile_.level() > 0)
      profile_.follow(dominant, exit, c);
    else
      profile_.start(dominant, k, exit, c);
    if (stopping) profile_.stop();
    return profile_.next_interval();
  }

  // The step due now (stage_move_step()): a bit per motor that steps.
  uint8_t step() { return spread_ ? line_.next() : 0; }
  // Of the last step's motors, those that step towards negative counts.
  uint8_t negative() const { return spread_ ? line_.negative : 0; }

  // move_tick(), after a step: `stop` (a '!') cuts the move to rest; the ticks to the next
  // step, 0 when the move is done.
  uint32_t next(bool stop = false) {
    if (stop) profile_.stop();
    if (profile_.done()) return 0;
    return profile_.next_interval();
  }

  // halt(): at rest; the next move starts from rest.
  void halt() { profile_ = StepProfile(); }
  // The move's speed as a level (0: at rest), and the level it is to end at.
  uint32_t level() const { return profile_.level(); }
  bool raise_exit(uint32_t exit) { return profile_.raise_exit(exit); }
  // The dominant motor's steps in the move begun last.
  uint32_t dominant() const { return dominant_; }

 private:
  StepProfile profile_;
  LineStepper<kMaxMotors> line_{};
  bool spread_ = true;
  uint32_t dominant_ = 0;
};

}  // namespace articula::host

#endif  // ARTICULA_HOST_REPLAY_H
