// firmware/src/robot.h - the arm this firmware drives: the robot configuration
// (articula/config.h) read from EEPROM at power-up and again whenever `$199` commits a new
// one. A blank or corrupt EEPROM gets the MK2 (builtin_config.h, the image the host makes
// from robots/mk2plus.json). Every computation on it is the shared core's, as on the host.
#ifndef ARTICULA_FIRMWARE_ROBOT_H
#define ARTICULA_FIRMWARE_ROBOT_H

#include <articula/config.h>

#include "board.h"
#include "ram.h"

namespace robot {

// EEPROM: [kEepromAddress] kEepromVersion, the image, its CRC-16 (low byte first). The
// settings (settings.h) sit below it.
static const uint16_t kEepromAddress = 32;
static const uint8_t kEepromVersion = 3;  // 2: the image carries $131 (the drive); 3: $132..$139 (servos)
static const uint16_t kEepromImageAt = kEepromAddress + 1;                           // the image
static const uint16_t kEepromCrcAt = kEepromImageAt + articula::kConfigImageSize;  // its CRC-16

// Room for the most motors a configuration has; count() of them are used. The Nano's build has
// the three its pins wire; a build for the host (firmware/sitl) may have more
// (ARTICULA_FIRMWARE_MOTORS, up to 8: LineStepper's byte of bits), from the same source.
#ifndef ARTICULA_FIRMWARE_MOTORS
#define ARTICULA_FIRMWARE_MOTORS 3
#endif
static const uint8_t kJoints = ARTICULA_FIRMWARE_MOTORS;
static_assert(ARTICULA_FIRMWARE_MOTORS >= articula::kMaxConfigMotors && ARTICULA_FIRMWARE_MOTORS <= 8,
              "from the configuration's motors to LineStepper's eight");

// The drive kinds this build drives (bit k: articula::DriveKind k); a configuration asking for
// another is refused (kConfigInvalid). The 4-wire ones share the Nano's pins and coil code.
// The build for a CNC shield (ARTICULA_CNC_SHIELD, board.h's shield pins) drives STEP/DIR only,
// the build for servo arms (ARTICULA_SERVO_ARM: a pulse train on the pins the configuration
// names) servos only.
#ifndef ARTICULA_FIRMWARE_DRIVES
#if defined(ARTICULA_CNC_SHIELD)
#define ARTICULA_FIRMWARE_DRIVES (1u << articula::kDriveStepDir)
#elif defined(ARTICULA_SERVO_ARM)
#define ARTICULA_FIRMWARE_DRIVES (1u << articula::kDriveServo)
#else
#define ARTICULA_FIRMWARE_DRIVES ((1u << articula::kDriveL298n) | (1u << articula::kDriveUln2003))
#endif
#endif
static const uint8_t kDrives = ARTICULA_FIRMWARE_DRIVES;

typedef articula::Actuation<float, kJoints> Actuation;
typedef articula::MotorState<kJoints> State;

// The configuration's state (state.h holds it; only robot.cpp writes it).
struct Ram {
  articula::ConfiguredArm<kJoints> config;
  uint16_t checksum;
  int32_t home_steps[kJoints];
  bool in_eeprom;  // the EEPROM holds the configuration in use (robot.cpp ensure_in_eeprom)
};
ARTICULA_FIRMWARE_RAM(Ram, ram)


// The configuration in use: motors, coupling, home (motor angles), P's arm, servo, name.
inline articula::ConfiguredArm<kJoints>& config() { return ram().config; }
// Its checksum (the I banner's K).
inline uint16_t checksum() { return ram().checksum; }
// The steps the home pose quantizes to.
inline const int32_t* home_steps() { return ram().home_steps; }

inline const Actuation& actuation() { return config().actuation; }
inline uint8_t count() { return config().actuation.num_motors; }
inline const articula::MotorSpec& motor(uint8_t i) { return config().actuation.motors[i]; }
// Whether the motors are on STEP/DIR drivers: a constant in a build that drives one family (the
// other family's code is then never compiled in), the configuration's word in one with both.
inline bool step_dir() {
  const uint8_t sd = uint8_t(1u << articula::kDriveStepDir);
  return kDrives == sd || ((kDrives & sd) != 0 && config().drive == articula::kDriveStepDir);
}
// Whether the motors are hobby servos: a step is one Timer1 tick (0.5 us) more or less on the
// motor's pulse, which the HAL takes as it takes a STEP pulse (hal::stage_pulse). Constant in
// a build that drives only servos or none.
inline bool servos() {
  const uint8_t sv = uint8_t(1u << articula::kDriveServo);
  return kDrives == sv || ((kDrives & sv) != 0 && config().drive == articula::kDriveServo);
}
// Whether a step is a pulse to the HAL (STEP/DIR drivers and servos) rather than a coil pattern.
inline bool pulsed() { return step_dir() || servos(); }

// The header pins the drive keeps (board.h's masks, bit n pin n): O and W take the others, and the
// status report's I shows those. A servo arm keeps its servos' signal pins, which its
// configuration names ($135..$137), beside the serial line, the LED and the gripper's.
inline uint32_t kept_pins() {
  uint32_t kept = board::kept_by(step_dir(), servos());
  if (servos())
    for (uint8_t i = 0; i < count() && i < articula::kMaxConfigMotors; ++i) kept |= uint32_t(1) << config().servo_pin[i];
  return kept;
}
static_assert(board::kHeaderPins == articula::kIoPins, "O and W name the header's pins");

// steps_to_millideg(motor(i), steps), the status report's A field: the same value, from a
// fraction reduced at setup, in 32-bit arithmetic for every step count it fits (all within
// the limits on the MK2), so a report costs no 64-bit division.
articula::Millideg step_angle(uint8_t i, int32_t steps);

// Once at start-up (and again when a test reboots the firmware): the configuration from
// EEPROM, or the built-in one.
void setup();

// Puts a configuration (read by config_read, or, in the host's eight-motor build, one with more
// motors than the image carries: firmware/sitl) in use, with its checksum; then
// firmware::configured().
void use(const articula::ConfiguredArm<kJoints>& next, uint16_t sum);

// Writes an image to EEPROM as `articula configure` leaves it there (the version, the image,
// its CRC): what setup() then reads. (Only the SITL calls it, for an arm configured before
// power-up; on the Nano the linker drops it.)
void store(const uint8_t* image);

// `$1xx=v` and `N text`: checked (config_check, config_check_name) and written to the
// staged image in EEPROM; nothing else changes.
articula::Status stage(uint16_t n, int32_t thousandths);
articula::Status stage_name(const char* s, uint8_t len);
// `$199=crc`: the staged image becomes the configuration when its checksum is crc
// (kConfigChecksum otherwise) and it describes an arm this firmware drives (kConfigInvalid
// otherwise); then it is in use, as after setup(). On an error nothing changes.
articula::Status commit(int32_t crc);

}  // namespace robot

#endif  // ARTICULA_FIRMWARE_ROBOT_H
