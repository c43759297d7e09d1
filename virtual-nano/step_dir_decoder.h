// virtual-nano/step_dir_decoder.h - what a STEP/DIR driver module (A4988, DRV8825, TMC2208/2209)
// makes of its inputs, and how well they keep its datasheet's timing.
//
// Pure logic, no simavr: the virtual Nano feeds it the levels of one driver's STEP and DIR
// pins and of ENABLE (active low on the CNC shields' EN, given here as enabled or not) each
// time its port is written, with the CPU cycle. Written from the drivers' datasheets, not from
// the firmware:
//   - a rising STEP edge while enabled moves the motor one (micro)step: forwards (more steps)
//     while DIR is high, backwards while it is low;
//   - a rising STEP edge while disabled moves nothing (a fault here: the firmware enables the
//     drivers before a move);
//   - the STEP high time (rise to fall) and the DIR setup time (a DIR change to the next rising
//     STEP edge) are measured, the shortest of each kept, for the datasheets' minimums
//     (articula/drive.h: A4988 1 us and 200 ns, DRV8825 1.9 us and 650 ns).
#ifndef ARTICULA_VIRTUAL_NANO_STEP_DIR_DECODER_H
#define ARTICULA_VIRTUAL_NANO_STEP_DIR_DECODER_H

#include <cstdint>

namespace vnano {

struct StepDirChange {
  int delta = 0;         // +1 or -1: the motor stepped
  bool ignored = false;  // a STEP edge while the driver was disabled
  bool fell = false;     // STEP fell: a pulse ended (its width is in pulse_cycles)
  uint64_t pulse_cycles = 0;
};

class StepDirDecoder {
 public:
  static constexpr uint64_t kNone = ~uint64_t(0);

  StepDirChange feed(bool step, bool dir, bool enabled, uint64_t cycle) {
    StepDirChange c;
    if (dir != dir_) {
      dir_ = dir;
      dir_changed_at_ = cycle;
      dir_changed_ = true;
    }
    if (step && !step_) {
      rise_at_ = cycle;
      if (!enabled) {
        c.ignored = true;
        ++ignored_;
      } else {
        c.delta = dir ? 1 : -1;
        steps_ += c.delta;
        ++pulses_;
        if (dir_changed_ && cycle - dir_changed_at_ < min_dir_setup_) min_dir_setup_ = cycle - dir_changed_at_;
      }
      dir_changed_ = false;
    } else if (!step && step_) {
      c.fell = true;
      c.pulse_cycles = cycle - rise_at_;
      if (c.pulse_cycles < min_pulse_) min_pulse_ = c.pulse_cycles;
      if (c.pulse_cycles > max_pulse_ || max_pulse_ == kNone) max_pulse_ = c.pulse_cycles;
    }
    step_ = step;
    return c;
  }

  int64_t steps() const { return steps_; }
  uint64_t pulses() const { return pulses_; }
  uint64_t ignored() const { return ignored_; }
  bool step_high() const { return step_; }
  bool dir_high() const { return dir_; }
  // The shortest STEP high time and DIR setup time seen, in cycles (kNone: none yet); the
  // longest STEP high time.
  uint64_t min_pulse_cycles() const { return min_pulse_; }
  uint64_t max_pulse_cycles() const { return max_pulse_; }
  uint64_t min_dir_setup_cycles() const { return min_dir_setup_; }

 private:
  bool step_ = false, dir_ = false, dir_changed_ = false;
  uint64_t rise_at_ = 0, dir_changed_at_ = 0;
  int64_t steps_ = 0;
  uint64_t pulses_ = 0, ignored_ = 0;
  uint64_t min_pulse_ = kNone, max_pulse_ = kNone, min_dir_setup_ = kNone;
};

}  // namespace vnano

#endif  // ARTICULA_VIRTUAL_NANO_STEP_DIR_DECODER_H
