// virtual-nano/servo_decoder.h - what a hobby servo makes of its signal pin: the width of each
// pulse, as the position the servo is asked to hold.
//
// Pure logic, no simavr: the virtual Nano feeds it the pin's level each time its port is
// written, with the CPU cycle. Written from what a servo takes (a pulse every 20 ms or so, its
// width the angle), not from the firmware:
//   - a pulse is a rise and the next fall; its width, in the pulse's own unit (`cycles_per_tick`
//     CPU cycles: 8 for Timer1's 0.5 us at 16 MHz), is rounded to the nearest unit;
//   - the position is that width less the width at step 0 (the calibration's first pulse), so
//     it counts in the same steps as the firmware's motor;
//   - a pulse whose width lies more than one unit from the position held is a change (the
//     servo is asked to move); one within one unit moves it only when the pulse before had
//     the same width: a lone pulse one unit off is the edges' jitter (the firmware's edges lie
//     within a few cycles of their ticks, and a width that falls half a unit off rounds either
//     way), as a servo's deadband takes it; the first pulse is the start position;
//   - so the position a decoder holds is the firmware's within one unit while it moves, and
//     the firmware's own two pulses after it stops.
// It keeps the period between rises and every width's spread, for the report.
#ifndef ARTICULA_VIRTUAL_NANO_SERVO_DECODER_H
#define ARTICULA_VIRTUAL_NANO_SERVO_DECODER_H

#include <cstdint>

namespace vnano {

struct ServoChange {
  bool pulse = false;    // a pulse ended now
  int64_t delta = 0;     // its position less the previous pulse's (0 for the first)
  uint64_t cycles = 0;   // its width, CPU cycles
};

class ServoDecoder {
 public:
  static constexpr int64_t kDeadband = 1;  // units a lone width may lie off the position held

  ServoDecoder() = default;
  ServoDecoder(uint64_t cycles_per_tick, int64_t zero_ticks) : per_tick_(cycles_per_tick), zero_(zero_ticks) {}

  ServoChange feed(bool level, uint64_t cycle) {
    ServoChange c;
    if (level && !high_) {
      if (rises_ > 0) {
        const uint64_t p = cycle - rise_at_;
        if (p < min_period_ || rises_ == 1) min_period_ = p;
        if (p > max_period_) max_period_ = p;
      }
      ++rises_;
      rise_at_ = cycle;
    } else if (!level && high_) {
      c.pulse = true;
      c.cycles = cycle - rise_at_;
      const int64_t ticks = int64_t((c.cycles + per_tick_ / 2) / per_tick_);
      const int64_t position = ticks - zero_;
      if (pulses_ == 0) {
        position_ = position;
      } else if (position > position_ + kDeadband || position < position_ - kDeadband ||
                 (position != position_ && position == last_)) {
        c.delta = position - position_;
        position_ = position;
      }
      last_ = position;
      // How far the width lies from its whole tick, in cycles: the edges' jitter.
      const int64_t off = int64_t(c.cycles) - ticks * int64_t(per_tick_);
      const uint64_t a = uint64_t(off < 0 ? -off : off);
      if (a > max_off_cycles_) max_off_cycles_ = a;
      ++off_count_[(off + 8) & 15];
      ++pulses_;
    }
    high_ = level;
    return c;
  }

  int64_t position() const { return position_; }
  uint64_t pulses() const { return pulses_; }
  bool high() const { return high_; }
  uint64_t min_period_cycles() const { return min_period_; }
  uint64_t max_period_cycles() const { return max_period_; }
  // The most a pulse's width lay from its whole number of ticks, CPU cycles.
  uint64_t max_off_cycles() const { return max_off_cycles_; }
  int64_t zero_ticks() const { return zero_; }
  // How many widths lay `off` cycles from their whole tick (off -8..7).
  uint64_t off_count(int off) const { return off_count_[(off + 8) & 15]; }

 private:
  uint64_t per_tick_ = 8;
  int64_t zero_ = 0;
  bool high_ = false;
  uint64_t rise_at_ = 0, rises_ = 0, pulses_ = 0;
  uint64_t min_period_ = 0, max_period_ = 0, max_off_cycles_ = 0;
  int64_t position_ = 0;
  int64_t last_ = 0;  // the previous pulse's width less the zero
  uint64_t off_count_[16] = {};
};

}  // namespace vnano

#endif  // ARTICULA_VIRTUAL_NANO_SERVO_DECODER_H
