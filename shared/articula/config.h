// articula/config.h - the robot configuration a Nano holds in EEPROM: one firmware for any
// arm it can drive. docs/protocol.md ("Robot configuration") is the specification; this is
// its code, shared by the firmware (which stores, checks and reads it) and the host library
// (which makes it from a robot file, host/lib/nano_config.cpp, for the CLI, Python, the page,
// and the firmware's built-in image).
//
// The configuration is an image of kConfigImageSize bytes. Every number in it is a setting
// in GRBL's manner, `$<n>=<value>`, numbered here and nowhere else:
//
//   $1mk    motor m (0 to 2), field k:  0 full steps per turn   1 microsteps (1, 2, 4 .. 64;
//                                                               beyond 2 on STEP/DIR only)
//           2 direction (1 or -1)       3 gear numerator        4 gear denominator
//           5 zero, deg                 6 minimum, deg          7 maximum, deg
//           8 home, deg (the motor's angle at the home pose)
//   $130    motors, 1 to 3
//   $131    how they are driven (articula::DriveKind, drive.h): 0 L298N, 1 ULN2003, 2 STEP/DIR,
//           3 servo. A firmware build drives some of them (config_read's `drives`).
//   $13m    (m = 2 to 4) servo arms: motor m-2's pulse at step 0, us (its first calibration
//           point; a step is one of Timer1's 0.5 us ticks more, drive.h); 0 on steppers
//   $13m    (m = 5 to 7) servo arms: motor m-5's signal pin, the header's index (board.h:
//           D0..D13 are 0..13, A0..A5 14..19); 0 on steppers
//   $138    servo arms: the servos' top rate, ticks/s (the robot file's speed; it caps $0); 0: none
//   $139    servo arms: their acceleration, ticks/s^2 (the file's accel; it caps $1); 0: none
//   $14k    coupling C row-major (q = C u), k = 3 row + column: 3 decimals
//   $150    1: P's closed form applies (a yaw-pitch-pitch arm), 0: it does not
//   $151-6  P's geometry, mm: base height, shoulder offset, upper arm, forearm,
//           tool forward, tool up (articula::YppArm)
//   $160    servo angle with the gripper open, deg; $161 closed
//   N text  the robot's name for the I banner (1 to kMaxRobotName characters)
//   $199    commit: the CRC-16 of the image (config_checksum). The firmware checks the
//           staged image against it and that it describes an arm it can drive, then uses it
//           at once and at every power-up after. Until then the last committed one runs.
//
// Whole fields (steps, microsteps, direction, gear, motors, $150) take whole numbers; the
// others keep the protocol's thousandths exactly (millidegrees, micrometres).
#ifndef ARTICULA_CONFIG_H
#define ARTICULA_CONFIG_H

#include "actuation.h"
#include "drive.h"
#include "ik_ypp.h"
#include "protocol.h"

namespace articula {

static const uint8_t kMaxConfigMotors = 3;  // the Nano's pin map wires three
static const uint16_t kCommitSetting = 199;
static const uint16_t kConfigImageSize = 194;

// The bytes of a field of the image, and the values its setting takes (in the units it is
// stored in: whole numbers, or thousandths).
struct ConfigField {
  uint8_t offset, size;
  bool whole;
  int32_t lo, hi;
};

// Where setting n lives in the image; false when n is not a configuration setting.
inline bool config_field(uint16_t n, ConfigField& f) {
  static const uint8_t kMotorOffset[9] = {0, 2, 3, 4, 8, 12, 16, 20, 24};
  f.offset = 0;
  f.whole = true;
  f.size = 4;
  const int32_t big = kMaxAbsMillideg;
  if (n >= 100 && n <= 128 && n % 10 <= 8) {
    const uint8_t m = uint8_t((n - 100) / 10), k = uint8_t(n % 10);
    f.offset = uint8_t(1 + 28 * m + kMotorOffset[k]);
    f.size = k == 0 ? 2 : k <= 2 ? 1 : 4;
    f.lo = k == 2 ? -1 : 1;
    f.hi = k == 0 ? 10000 : k == 1 ? 64 : k == 2 ? 1 : 1000000L;
    if (k >= 5) {
      f.whole = false;
      f.lo = -big;
      f.hi = big;
    }
    return true;
  }
  if (n == 130 || n == 131) {
    f.offset = n == 130 ? 0 : 178;
    f.size = 1;
    f.lo = n == 130 ? 1 : 0;
    f.hi = n == 130 ? kMaxConfigMotors : kDriveKinds - 1;
    return true;
  }
  if (n >= 132 && n <= 139) {  // a servo arm's calibration, pins and rates
    static const uint8_t kOffset[8] = {179, 181, 183, 185, 186, 187, 188, 190};
    static const uint8_t kSize[8] = {2, 2, 2, 1, 1, 1, 2, 4};
    f.offset = kOffset[n - 132];
    f.size = kSize[n - 132];
    f.lo = 0;
    f.hi = n <= 134 ? int32_t(kServoPulseMaxUs) : n <= 137 ? 19 : n == 138 ? 4000 : 100000L;
    return true;
  }
  f.whole = false;
  f.lo = -big;
  f.hi = big;
  if (n >= 140 && n <= 148) {
    f.offset = uint8_t(85 + 4 * (n - 140));
  } else if (n == 150) {
    f.offset = 121;
    f.size = 1;
    f.whole = true;
    f.lo = 0;
    f.hi = 1;
  } else if (n >= 151 && n <= 156) {
    f.offset = uint8_t(122 + 4 * (n - 151));
  } else if (n == 160 || n == 161) {
    f.offset = uint8_t(146 + 4 * (n - 160));
    f.lo = 0;
    f.hi = 180000L;
  } else {
    return false;
  }
  return true;
}
static const uint8_t kConfigNameOffset = 154;  // kMaxRobotName bytes, NUL-padded

// Whether `$n=<value>` (value in thousandths, as parsed) may be staged: kSettingUnknown for
// no such setting, kValueOutOfRange for a value its field does not take (a direction of 0
// among them).
inline Status config_check(uint16_t n, int32_t thousandths) {
  ConfigField f;
  if (!config_field(n, f)) return kSettingUnknown;
  int32_t v = thousandths;
  if (f.whole) {
    if (v % 1000 != 0) return kValueOutOfRange;
    v /= 1000;
  }
  if (v < f.lo || v > f.hi || (n % 10 == 2 && n <= 128 && v == 0)) return kValueOutOfRange;
  if (n % 10 == 1 && n <= 128 && (v & (v - 1)) != 0) return kValueOutOfRange;  // microsteps: a power of two
  return kOk;
}

// The stored bytes of a checked value of field f (little-endian, f.size of them) into out[0..3].
inline void config_bytes(uint8_t* out, const ConfigField& f, int32_t thousandths) {
  uint32_t v = uint32_t(f.whole ? thousandths / 1000 : thousandths);
  for (uint8_t i = 0; i < 4; ++i, v >>= 8) out[i] = uint8_t(v);
}

// The value of setting n in an image, in its stored units (sign-extended where the field
// takes negative values). `image` is the bytes, or anything that gives them by index (the
// firmware reads its EEPROM so, without a copy of the image on its stack).
template <typename Bytes>
inline int32_t config_get(const Bytes& image, uint16_t n) {
  ConfigField f;
  if (!config_field(n, f)) return 0;
  uint32_t v = 0;
  for (uint8_t i = f.size; i > 0; --i) v = (v << 8) | image[f.offset + i - 1];
  if (f.lo < 0 && f.size < 4 && (v & (1UL << (8 * f.size - 1)))) v |= ~((1UL << (8 * f.size)) - 1);
  return int32_t(v);
}

// Stores setting n's value (thousandths, checked by config_check) into an image.
inline void config_put(uint8_t* image, uint16_t n, int32_t thousandths) {
  uint8_t b[4];
  ConfigField f;
  config_field(n, f);
  config_bytes(b, f, thousandths);
  for (uint8_t i = 0; i < f.size; ++i) image[f.offset + i] = b[i];
}

// The name of an `N` line: 1 to kMaxRobotName printable characters, none of them '|' or ']'
// (the banner's separators). kMissingArgument, kValueOutOfRange (too long), kBadCharacter.
inline Status config_check_name(const char* s, uint8_t len) {
  if (len == 0) return kMissingArgument;
  if (len > kMaxRobotName) return kValueOutOfRange;
  for (uint8_t i = 0; i < len; ++i)
    if (s[i] < 0x20 || s[i] > 0x7e || s[i] == '|' || s[i] == ']') return kBadCharacter;
  return kOk;
}

// The name's bytes as the image holds them (NUL-padded to kMaxRobotName).
inline void config_name_bytes(uint8_t* out, const char* s, uint8_t len) {
  for (uint8_t i = 0; i < kMaxRobotName; ++i) out[i] = i < len ? uint8_t(s[i]) : 0;
}

// CRC-16/CCITT-FALSE (polynomial 0x1021, MSB first, from 0xFFFF): the configuration's
// checksum (the I banner's K field and $199's value) and the settings image's.
// `crc` carries a checksum on over several pieces.
inline uint16_t crc16(const uint8_t* data, uint16_t size, uint16_t crc = 0xFFFF) {
  for (uint16_t i = 0; i < size; ++i) {
    crc ^= uint16_t(data[i]) << 8;
    for (uint8_t b = 0; b < 8; ++b) crc = (crc & 0x8000) ? uint16_t((crc << 1) ^ 0x1021) : uint16_t(crc << 1);
  }
  return crc;
}

inline uint16_t config_checksum(const uint8_t* image) { return crc16(image, kConfigImageSize); }

// What the firmware runs on: the configuration read into the core's structures.
template <int J>
struct ConfiguredArm {
  Actuation<float, J> actuation;  // coupling_inv unused (left zero)
  Millideg home[J];               // the home pose as motor angles
  YppArm<float> arm;              // P's closed form, when has_point
  bool has_point;
  float servo_open_deg, servo_closed_deg;
  char name[kMaxRobotName + 1];
  uint8_t drive;  // articula::DriveKind
  // A servo arm's ($132..$139): each motor's pulse at step 0 (us) and signal pin (board.h's
  // header index), the top rate and acceleration its servos take (0: no cap).
  uint16_t servo_zero_us[kMaxConfigMotors];
  uint8_t servo_pin[kMaxConfigMotors];
  uint16_t rate_cap;
  uint32_t accel_cap;
};

// Why an image is not a configuration the firmware can run (kConfigOk when it is).
enum ConfigError : uint8_t {
  kConfigOk = 0,
  kConfigBadValue,    // a field outside its range (a blank or foreign image)
  kConfigBadMotor,    // a motor's steps, gear or limits (articula::validate)
  kConfigBadHome,     // a home angle outside its motor's limits
  kConfigBadName,     // no name, or a character the banner cannot carry
  kConfigBadDrive,    // a drive kind this firmware build does not drive, or a servo arm's
                      // pulse (below kServoPulseMinUs) or pins (D0, D1, or one pin twice)
};

// Reads an image into `out` (J >= the image's motor count), checking every field as
// config_check does and every motor as validate() does. P applies when $150 says so, the
// arm has three motors, and the coupling is one the closed form knows (the identity or the
// MK2's parallelogram, ypp_limits_from_actuation). `drives` has bit k set for each
// DriveKind k the reader drives.
template <int J, typename Bytes>
inline ConfigError config_read(ConfiguredArm<J>& out, const Bytes& image, uint8_t drives = 0xFF) {
  for (uint16_t n = 100; n <= 161; ++n) {
    ConfigField f;
    if (!config_field(n, f)) continue;
    const int32_t v = config_get(image, n);
    if (v < f.lo || v > f.hi) return kConfigBadValue;
  }
  const uint8_t count = uint8_t(config_get(image, 130));
  if (count > J) return kConfigBadValue;
  out.drive = uint8_t(config_get(image, 131));
  if (!(drives & (1u << out.drive))) return kConfigBadDrive;
  Actuation<float, J>& a = out.actuation;
  a.num_motors = count;
  for (uint8_t i = 0; i < J; ++i) {
    MotorSpec& m = a.motors[i];
    const uint16_t b = uint16_t(100 + 10 * i);
    const bool used = i < count;
    m.full_steps_per_rev = used ? uint16_t(config_get(image, b)) : 200;
    m.microsteps = used ? uint8_t(config_get(image, b + 1)) : 1;
    m.direction = used ? int8_t(config_get(image, b + 2)) : 1;
    m.gear_num = used ? config_get(image, b + 3) : 1;
    m.gear_den = used ? config_get(image, b + 4) : 1;
    m.zero = used ? config_get(image, b + 5) : 0;
    m.min = used ? config_get(image, b + 6) : 0;
    m.max = used ? config_get(image, b + 7) : 0;
    out.home[i] = used ? config_get(image, b + 8) : 0;
    if (validate(m) != kMotorOk) return kConfigBadMotor;
    if (out.drive != kDriveStepDir && m.microsteps > 2) return kConfigBadDrive;  // coils: full or half steps
    if (out.home[i] < m.min || out.home[i] > m.max) return kConfigBadHome;
    for (uint8_t j = 0; j < J; ++j) {
      a.coupling[i][j] = i < 3 && j < 3 ? float(config_get(image, uint16_t(140 + 3 * i + j))) / 1000.0f : 0.0f;
      a.coupling_inv[i][j] = 0.0f;
    }
  }
  YppArm<float>& arm = out.arm;
  float* g[6] = {&arm.base_height, &arm.shoulder_offset, &arm.upper, &arm.fore, &arm.tool_forward, &arm.tool_up};
  for (uint8_t k = 0; k < 6; ++k) *g[k] = float(config_get(image, uint16_t(151 + k))) / 1000.0f;
  arm.parallelogram = false;
  out.has_point = config_get(image, 150) == 1 && arm.upper > 0.0f && arm.fore > 0.0f &&
                  ypp_limits_from_actuation(arm, a);
  for (uint8_t i = 0; i < kMaxConfigMotors; ++i) {
    out.servo_zero_us[i] = uint16_t(config_get(image, uint16_t(132 + i)));
    out.servo_pin[i] = uint8_t(config_get(image, uint16_t(135 + i)));
    if (out.drive != kDriveServo || i >= count) continue;
    if (out.servo_zero_us[i] < kServoPulseMinUs || out.servo_pin[i] < 2) return kConfigBadDrive;
    for (uint8_t j = 0; j < i; ++j)
      if (out.servo_pin[j] == out.servo_pin[i]) return kConfigBadDrive;
  }
  out.rate_cap = uint16_t(config_get(image, 138));
  out.accel_cap = uint32_t(config_get(image, 139));
  out.servo_open_deg = float(config_get(image, 160)) / 1000.0f;
  out.servo_closed_deg = float(config_get(image, 161)) / 1000.0f;
  uint8_t len = 0;
  for (uint8_t i = 0; i < kMaxRobotName; ++i) {
    out.name[i] = char(image[uint16_t(kConfigNameOffset + i)]);
    if (out.name[i] == '\0') break;
    ++len;
  }
  out.name[len] = '\0';
  if (config_check_name(out.name, len) != kOk) return kConfigBadName;
  return kConfigOk;
}

}  // namespace articula

#endif  // ARTICULA_CONFIG_H
