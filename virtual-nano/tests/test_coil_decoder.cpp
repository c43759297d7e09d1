// hil/tests/test_coil_decoder.cpp - the virtual Nano's rules for what a stepper motor makes
// of its four L298N inputs (virtual-nano/coil_decoder.h).
#include "coil_decoder.h"

#include <gtest/gtest.h>

#include <initializer_list>

using vnano::CoilDecoder;
using vnano::CoilEvent;
using vnano::FaultKind;

namespace {

// IN1..IN4 written as in the L298N's terminal order: "1010" -> bits 0 and 2.
uint8_t p(const char* s) {
  uint8_t v = 0;
  for (int i = 0; i < 4; ++i)
    if (s[i] == '1') v = uint8_t(v | (1u << i));
  return v;
}

const char* const kFull[4] = {"1010", "0110", "0101", "1001"};
const char* const kHalf[8] = {"1000", "1010", "0010", "0110", "0100", "0101", "0001", "1001"};

}  // namespace

TEST(CoilDecoder, TableMatchesTheFirmwaresSequence) {
  // firmware/src/coils.cpp: {0x1, 0x5, 0x4, 0x6, 0x2, 0xA, 0x8, 0x9}.
  for (int i = 0; i < 8; ++i) EXPECT_EQ(vnano::kHalfStepSequence[i], p(kHalf[i])) << i;
  EXPECT_EQ(vnano::pattern_string(p("1010")), "1010");
  EXPECT_EQ(vnano::phase_of(0), vnano::kReleased);
  EXPECT_EQ(vnano::phase_of(p("1100")), vnano::kIllegal);
}

TEST(CoilDecoder, FullStepsForwardAndBack) {
  CoilDecoder d;
  EXPECT_EQ(d.feed(p("1010")).event, CoilEvent::kEnergised);  // the first pattern: the reference
  for (int k = 1; k <= 10; ++k) {
    const auto c = d.feed(p(kFull[k % 4]));
    ASSERT_EQ(c.event, CoilEvent::kStep) << k;
    EXPECT_EQ(c.delta_half, 2);
  }
  EXPECT_EQ(d.steps(), 10);
  EXPECT_FALSE(d.half_step_mode());
  for (int k = 9; k >= -3; --k) {
    const auto c = d.feed(p(kFull[((k % 4) + 4) % 4]));
    ASSERT_EQ(c.event, CoilEvent::kStep) << k;
    EXPECT_EQ(c.delta_half, -2);
  }
  EXPECT_EQ(d.steps(), -3);
  EXPECT_EQ(d.half_steps(), -6);
}

TEST(CoilDecoder, HalfSteps) {
  CoilDecoder d;
  d.feed(p("1010"));
  for (int k = 2; k < 2 + 16; ++k) ASSERT_EQ(d.feed(p(kHalf[k % 8])).delta_half, 1) << k;
  EXPECT_TRUE(d.half_step_mode());
  EXPECT_EQ(d.steps(), 16);
  // The last pattern was kHalf[17 % 8] = 1010: 1000 is one back, then 0110 two forward (a full
  // step between two-coil states, which a half-stepped motor follows too).
  EXPECT_EQ(d.feed(p("1000")).delta_half, -1);
  EXPECT_EQ(d.steps(), 15);
  EXPECT_EQ(d.feed(p("1010")).delta_half, 1);
  EXPECT_EQ(d.feed(p("0110")).delta_half, 2);
  EXPECT_EQ(d.steps(), 18);
}

TEST(CoilDecoder, ForcedHalfStepCountsFullStepsAsTwo) {
  CoilDecoder d;
  d.force_half_step();
  d.feed(p("1010"));
  d.feed(p("0110"));
  EXPECT_EQ(d.steps(), 2);
  EXPECT_TRUE(d.forced_half_step());
}

TEST(CoilDecoder, SkippedPhasesAreFaults) {
  CoilDecoder d;
  d.feed(p("1010"));
  auto c = d.feed(p("0101"));  // two full steps at once: the rotor cannot tell which way
  EXPECT_EQ(c.event, CoilEvent::kFault);
  EXPECT_EQ(c.fault, FaultKind::kSkippedPhase);
  EXPECT_EQ(d.steps(), 0);
  // Counting goes on from the new pattern.
  EXPECT_EQ(d.feed(p("1001")).event, CoilEvent::kStep);
  EXPECT_EQ(d.half_steps(), 2);

  CoilDecoder h;
  h.feed(p("1000"));
  c = h.feed(p("0010"));  // one-coil to one-coil: the 1010 between is skipped
  EXPECT_EQ(c.event, CoilEvent::kFault);
  EXPECT_EQ(c.fault, FaultKind::kSkippedPhase);
  c = h.feed(p("1001"));  // three places back
  EXPECT_EQ(c.event, CoilEvent::kFault);
}

TEST(CoilDecoder, IllegalPatternsAreFaultsAndKeepTheReference) {
  for (const char* bad : {"1100", "0011", "1111", "1110", "0111"}) {
    CoilDecoder d;
    d.feed(p("1010"));
    const auto c = d.feed(p(bad));
    EXPECT_EQ(c.event, CoilEvent::kFault) << bad;
    EXPECT_EQ(c.fault, FaultKind::kIllegalPattern) << bad;
    // Back to a neighbour of the last legal state: a step from there.
    const auto n = d.feed(p("0110"));
    EXPECT_EQ(n.event, CoilEvent::kStep) << bad;
    EXPECT_EQ(d.steps(), 1) << bad;
  }
}

TEST(CoilDecoder, ReleaseIsNotAFaultAndCountingContinues) {
  CoilDecoder d;
  d.feed(p("1010"));
  d.feed(p("0110"));
  EXPECT_EQ(d.feed(0).event, CoilEvent::kReleased);
  EXPECT_FALSE(d.energised());
  EXPECT_EQ(d.feed(p("0110")).event, CoilEvent::kEnergised);  // same state again: no motion
  EXPECT_EQ(d.steps(), 1);
  d.feed(0);
  EXPECT_EQ(d.feed(p("0101")).event, CoilEvent::kStep);  // adjacent to the last energised one
  EXPECT_EQ(d.steps(), 2);
  d.feed(0);
  const auto c = d.feed(p("1010"));  // two places from 0101: a fault
  EXPECT_EQ(c.event, CoilEvent::kFault);
  EXPECT_EQ(c.fault, FaultKind::kSkippedPhase);
  EXPECT_EQ(c.reference, p("0101"));
}

TEST(CoilDecoder, RepeatedPatternIsNothing) {
  CoilDecoder d;
  d.feed(p("1010"));
  EXPECT_EQ(d.feed(p("1010")).event, CoilEvent::kNone);
  EXPECT_EQ(d.feed(0).event, CoilEvent::kReleased);
  EXPECT_EQ(d.feed(0).event, CoilEvent::kNone);
}

// A 28BYJ-48 on a ULN2003: the unipolar table, half steps and full steps both ways; an
// L298N's one-coil-skipping pattern (1010) is illegal there, and a ULN2003's (1100) on an L298N.
TEST(CoilDecoder, UnipolarMotorOnAUln2003) {
  const char* const half[8] = {"1000", "1100", "0100", "0110", "0010", "0011", "0001", "1001"};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(vnano::kUnipolarSequence[i], p(half[i])) << i;
  CoilDecoder d(true);
  EXPECT_TRUE(d.unipolar());
  EXPECT_EQ(d.feed(p("1100")).event, CoilEvent::kEnergised);
  for (int k = 2; k < 2 + 16; ++k) ASSERT_EQ(d.feed(p(half[k % 8])).delta_half, 1) << k;
  EXPECT_EQ(d.steps(), 16);
  for (int k = 16; k >= 1; --k) ASSERT_EQ(d.feed(p(half[k % 8])).delta_half, -1) << k;
  EXPECT_EQ(d.steps(), 0);
  EXPECT_EQ(d.feed(p("1010")).fault, FaultKind::kIllegalPattern);
  CoilDecoder full(true);
  full.feed(p("1100"));
  for (const char* f : {"0110", "0011", "1001", "1100"}) ASSERT_EQ(full.feed(p(f)).delta_half, 2) << f;
  EXPECT_EQ(full.steps(), 4);
  EXPECT_FALSE(full.half_step_mode());
  CoilDecoder bipolar;
  EXPECT_EQ(bipolar.feed(p("1100")).fault, FaultKind::kIllegalPattern);
}
