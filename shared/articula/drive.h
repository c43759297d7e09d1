// articula/drive.h - how a motor is driven: the drive kinds, and the STEP/DIR driver chips with
// what their datasheets promise. One home for the host (a robot file's "driver", checked by
// host/lib/robot_file.cpp against the board's pins, host/lib/wiring.cpp) and the firmware (the
// STEP pulse's width and the DIR setup time it must give). The boards and their pins are
// firmware/src/board.h's.
#ifndef ARTICULA_DRIVE_H
#define ARTICULA_DRIVE_H

#include "platform.h"

namespace articula {

// A motor's driver, as a robot file names it.
enum DriveKind : uint8_t {
  kDriveL298n = 0,    // a bipolar stepper on an L298N H-bridge: four inputs IN1..IN4
  kDriveUln2003 = 1,  // a unipolar stepper (28BYJ-48) on a ULN2003 Darlington array: four inputs
  kDriveStepDir = 2,  // a stepper on a STEP/DIR driver module in a CNC shield's socket
  kDriveServo = 3,    // a hobby servo: one signal pin, a pulse every 20 ms
};
static const uint8_t kDriveKinds = 4;

// The eight half-step states of a four-input driver, IN1..IN4 as bits 0..3, in the order a
// motor turns forwards: an L298N's bipolar motor ([0]: 1000 1010 0010 0110 0100 0101 0001 1001)
// and a ULN2003's unipolar one ([1]: 1000 1100 0100 0110 0010 0011 0001 1001). The full-step
// sequence (two phases on) is every other state, the odd places. The firmware writes them
// (firmware/src/coils.cpp); the virtual Nanos' coil decoder (virtual-nano/coil_decoder.h), and
// through it the SITL, reads them back.
static const uint8_t kCoilSequence[2][8] = {{0x1, 0x5, 0x4, 0x6, 0x2, 0xA, 0x8, 0x9},
                                            {0x1, 0x3, 0x2, 0x6, 0x4, 0xC, 0x8, 0x9}};

struct DriveKindInfo {
  const char* id;     // the robot file's "kind"
  const char* title;  // as a person reads it
  uint16_t microsteps_mask;  // bit k: 2^k steps per full step may be asked for (0: no steps at all)
};
static const DriveKindInfo kDriveKindInfo[kDriveKinds] = {
    {"l298n", "L298N", 0x03},      // full and half steps (the coil table's odd states, or all)
    {"uln2003", "ULN2003", 0x03},  // likewise, on a unipolar motor's four half-coils
    {"step-dir", "STEP/DIR", 0},   // the chip says (kStepDirChip)
    {"servo", "servo", 0},         // a pulse width, not steps
};

// A STEP/DIR driver module (Pololu's footprint: the CNC shields' sockets). Its microstep modes
// are what its MS pins select without a serial interface; the timing is the datasheet's
// minimum STEP high time and DIR-to-STEP setup time.
struct StepDirChip {
  const char* id;
  const char* title;
  uint16_t microsteps_mask;  // bit k: 2^k microsteps per full step
  uint16_t step_high_ns;     // the STEP pulse's minimum width
  uint16_t dir_setup_ns;     // DIR must hold this long before STEP rises
};
static const uint8_t kStepDirChips = 4;
static const StepDirChip kStepDirChip[kStepDirChips] = {
    {"a4988", "A4988", 0x1F, 1000, 200},      // 1, 2, 4, 8, 16 (MS1..MS3)
    {"drv8825", "DRV8825", 0x3F, 1900, 650},  // 1 .. 32 (MODE0..MODE2)
    {"tmc2208", "TMC2208", 0x1E, 100, 20},    // 2, 4, 8, 16 (MS1, MS2 standalone)
    {"tmc2209", "TMC2209", 0x78, 100, 20},    // 8, 16, 32, 64 (MS1, MS2 standalone)
};

// Whether `microsteps` is one of a mask's modes.
inline bool microsteps_allowed(uint16_t mask, uint16_t microsteps) {
  for (uint8_t k = 0; k < 16; ++k)
    if ((mask & (1u << k)) && microsteps == (1u << k)) return true;
  return false;
}

// A hobby servo's pulse may be asked for within these widths; beyond them servos hit their
// stops or ignore the pulse.
static const uint16_t kServoPulseMinUs = 400;
static const uint16_t kServoPulseMaxUs = 2600;
// A servo joint's steps are Timer1's ticks (0.5 us): the pulse's resolution.
static const uint8_t kServoTicksPerUs = 2;

}  // namespace articula

#endif  // ARTICULA_DRIVE_H
