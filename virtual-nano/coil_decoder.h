// virtual-nano/coil_decoder.h - what a stepper motor makes of its driver's four inputs: a
// bipolar motor on an L298N, or a unipolar one (a 28BYJ-48) on a ULN2003.
//
// Pure logic, no simavr: the virtual Nano feeds it every new IN1..IN4 pattern of one motor
// (bit 0 = IN1 .. bit 3 = IN4, as firmware/src/hal.h) and it answers whether the motor
// stepped, by how much, or could not have followed.
//
// The eight half-step states, in the order a motor turns forwards (IN1..IN4):
//   L298N:   1000, 1010, 0010, 0110, 0100, 0101, 0001, 1001
//   ULN2003: 1000, 1100, 0100, 0110, 0010, 0011, 0001, 1001
// The full-step sequence (two phases on) is every other one: 1010, 0110, 0101, 1001 (or
// 1100, 0110, 0011, 1001).
// Positions are counted in half steps; a motor that has never shown a one-coil state is
// taken to be driven in full steps and its step count is half of that.
//
// Rules (a transition between two energised patterns):
//   - one place in the table: a half step (+1 or -1 half step);
//   - two places, both two-coil states: a full step (+-2 half steps);
//   - two places between one-coil states (1000 -> 0010: the 1010 between is skipped),
//     three or four places: a fault, the rotor cannot follow; the position is left as it
//     was and counting goes on from the new pattern;
//   - a pattern that is not in the table and not 0000 (1100, 0011, 1111, ...): a fault, the
//     position and the reference pattern stay;
//   - 0000: coils released, not a fault; the next energised pattern is compared with the
//     last energised one (same: no step; adjacent: a step; otherwise: a fault).
#ifndef ARTICULA_VIRTUAL_NANO_COIL_DECODER_H
#define ARTICULA_VIRTUAL_NANO_COIL_DECODER_H

#include <articula/drive.h>

#include <cstdint>
#include <string>

namespace vnano {

// IN1..IN4 as bits 0..3, in forward order: an L298N's, and a ULN2003's (the core's table,
// articula/drive.h, which the firmware writes).
constexpr const uint8_t* kHalfStepSequence = articula::kCoilSequence[0];
constexpr const uint8_t* kUnipolarSequence = articula::kCoilSequence[1];

constexpr int kReleased = -1;  // phase_of(0)
constexpr int kIllegal = -2;   // phase_of(a pattern not in the table)

// The pattern's place in kHalfStepSequence (kUnipolarSequence with `unipolar`) (0..7),
// kReleased for 0000, kIllegal otherwise.
inline int phase_of(uint8_t pattern, bool unipolar = false) {
  pattern &= 0xF;
  if (pattern == 0) return kReleased;
  const uint8_t* table = unipolar ? kUnipolarSequence : kHalfStepSequence;
  for (int i = 0; i < 8; ++i)
    if (table[i] == pattern) return i;
  return kIllegal;
}

// "1010" for IN1=1, IN2=0, IN3=1, IN4=0 (IN1 first, as the L298N's terminals are read).
inline std::string pattern_string(uint8_t pattern) {
  std::string s(4, '0');
  for (int i = 0; i < 4; ++i)
    if (pattern & (1u << i)) s[size_t(i)] = '1';
  return s;
}

enum class CoilEvent {
  kNone,       // same pattern as before
  kStep,       // the motor moved delta_half half steps
  kReleased,   // 0000
  kEnergised,  // energised again on the reference state (or for the first time): no motion
  kFault,      // a transition the motor cannot follow, or an illegal pattern
};

enum class FaultKind { kNone, kIllegalPattern, kSkippedPhase };

inline const char* fault_name(FaultKind k) {
  switch (k) {
    case FaultKind::kIllegalPattern:
      return "illegal pattern";
    case FaultKind::kSkippedPhase:
      return "skipped phase";
    default:
      return "none";
  }
}

struct CoilChange {
  CoilEvent event = CoilEvent::kNone;
  int delta_half = 0;  // kStep only: -2, -1, +1 or +2
  FaultKind fault = FaultKind::kNone;
  uint8_t from = 0;    // the previous pattern (as written, 0000 after a release)
  uint8_t reference = 0;  // the last legal energised pattern the change was judged against
};

class CoilDecoder {
 public:
  // A motor on a ULN2003 (the unipolar table) rather than an L298N.
  explicit CoilDecoder(bool unipolar = false) : unipolar_(unipolar) {}
  bool unipolar() const { return unipolar_; }
  // The same, said once the decoder exists (before the motor's first energised pattern).
  void set_unipolar(bool unipolar) { unipolar_ = unipolar; }

  // Forces half-step counting (steps() == half_steps()) from the start.
  void force_half_step() { half_mode_ = forced_ = true; }

  CoilChange feed(uint8_t pattern) {
    CoilChange c;
    pattern &= 0xF;
    c.from = pattern_;
    c.reference = last_phase_ >= 0 ? (unipolar_ ? kUnipolarSequence : kHalfStepSequence)[last_phase_] : 0;
    if (pattern == pattern_) return c;
    pattern_ = pattern;
    const int ph = phase_of(pattern, unipolar_);
    if (ph == kReleased) {
      c.event = CoilEvent::kReleased;
      return c;
    }
    if (ph == kIllegal) {
      c.event = CoilEvent::kFault;
      c.fault = FaultKind::kIllegalPattern;
      return c;
    }
    if ((ph & 1) == 0) half_mode_ = true;  // a one-coil state: driven in half steps
    if (last_phase_ < 0) {
      last_phase_ = ph;
      c.event = CoilEvent::kEnergised;
      return c;
    }
    int d = (ph - last_phase_ + 8) % 8;
    if (d > 4) d -= 8;  // -3..4
    const bool both_two_coil = (ph & 1) && (last_phase_ & 1);
    last_phase_ = ph;
    if (d == 0) {
      c.event = CoilEvent::kEnergised;
      return c;
    }
    if (d == 1 || d == -1 || ((d == 2 || d == -2) && both_two_coil)) {
      half_ += d;
      c.event = CoilEvent::kStep;
      c.delta_half = d;
      return c;
    }
    c.event = CoilEvent::kFault;
    c.fault = FaultKind::kSkippedPhase;
    return c;
  }

  int64_t half_steps() const { return half_; }
  // In the motor's own steps: half steps for a half-stepped motor, full steps otherwise.
  int64_t steps() const { return half_mode_ ? half_ : half_ / 2; }
  bool half_step_mode() const { return half_mode_; }
  bool forced_half_step() const { return forced_; }
  uint8_t pattern() const { return pattern_; }
  bool energised() const { return pattern_ != 0; }

 private:
  bool unipolar_;
  uint8_t pattern_ = 0;
  int last_phase_ = -1;  // the last legal energised state, -1 before the first
  int64_t half_ = 0;
  bool half_mode_ = false;
  bool forced_ = false;
};

}  // namespace vnano

#endif  // ARTICULA_VIRTUAL_NANO_COIL_DECODER_H
