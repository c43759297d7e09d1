// firmware/src/robot.cpp - the robot configuration: EEPROM, the built-in default, staging.
#include "robot.h"

#include "hal.h"
#include "builtin_config.h"

using namespace articula;

namespace robot {

ConfiguredArm<kJoints> config;
uint16_t checksum;
int32_t home_steps[kJoints];

namespace {
const uint16_t kAddress = kEepromAddress;
const uint8_t kVersion = kEepromVersion;
const uint16_t kImageAt = kAddress + 1;
const uint16_t kCrcAt = kImageAt + kConfigImageSize;

// step_angle(): angle = zero + direction * round(steps * den / num), num/den = steps per
// millidegree in lowest terms (3/950 on the MK2's base, 47/34200 on its arm motors); `most`
// is the largest |steps| for which 2 |steps| den + num fits a uint32 (0: none, use
// steps_to_millideg). The last angle is kept: a report at rest, or of a motor that did not
// move, computes nothing.
struct StepScale {
  uint32_t num, den, most;
  int32_t last_steps;
  Millideg last_angle;
};
StepScale g_scale[kJoints];

void setup_scale(StepScale& k, const MotorSpec& m) {
  k.num = k.den = k.most = 0;
  k.last_steps = 0;
  k.last_angle = m.zero;
  const int64_t den64 = detail::steps_den(m);  // steps_num is below 2^31 (validate)
  if (den64 > 0x7FFFFFFFLL) return;
  uint32_t num = uint32_t(detail::steps_num(m)), den = uint32_t(den64);
  uint32_t a = num, b = den;  // gcd
  while (b != 0) {
    const uint32_t t = a % b;
    a = b;
    b = t;
  }
  num /= a;
  den /= a;
  k.num = num;
  k.den = den;
  k.most = min_of(uint32_t((0xFFFFFFFFUL - num) / (2 * den)), uint32_t(0x7FFFFFFFUL));
}

// What a blank EEPROM gets: the MK2 (builtin_config.h, made by the host's nano_config).
const uint8_t kBuiltIn[kConfigImageSize] ARTICULA_IN_FLASH = ARTICULA_BUILTIN_CONFIG;

// An image's bytes one at a time (config_read takes them so, and one reader type keeps one
// copy of it in flash): the staged one in EEPROM, or the built-in one in flash.
struct Image {
  bool built_in;
  uint8_t operator[](uint16_t i) const;
};
const Image kStaged = {false}, kBuiltInImage = {true};

// Writes the version and the checksum that make the staged image the configuration.
void seal(uint16_t c) {
  const uint8_t head[1] = {kVersion}, sum[2] = {uint8_t(c), uint8_t(c >> 8)};
  hal::eeprom_write(kCrcAt, sum, 2);
  hal::eeprom_write(kAddress, head, 1);
}

// Whether the EEPROM holds a whole configuration (version and CRC right).
bool sealed(uint16_t c) {
  uint8_t head[1], crc[2];
  hal::eeprom_read(kAddress, head, 1);
  hal::eeprom_read(kCrcAt, crc, 2);
  return head[0] == kVersion && crc[0] == uint8_t(c) && crc[1] == uint8_t(c >> 8);
}

uint8_t Image::operator[](uint16_t i) const {
  uint8_t b;
  if (built_in)
    hal::flash_read(&b, kBuiltIn + i, 1);
  else
    hal::eeprom_read(uint16_t(kImageAt + i), &b, 1);
  return b;
}

// The CRC of an image, read a piece at a time (the whole would take 178 bytes of the stack);
// with `copy`, each piece written to the EEPROM's image too, then sealed (the built-in one).
uint16_t image_crc(const Image& image, bool copy) {
  uint8_t bytes[16];
  uint16_t crc = 0xFFFF;
  for (uint16_t at = 0; at < kConfigImageSize; at = uint16_t(at + sizeof bytes)) {
    const uint16_t n = min_of(uint16_t(sizeof bytes), uint16_t(kConfigImageSize - at));
    for (uint16_t i = 0; i < n; ++i) bytes[i] = image[uint16_t(at + i)];
    if (copy) hal::eeprom_write(uint16_t(kImageAt + at), bytes, n);
    crc = crc16(bytes, n, crc);
  }
  if (copy) seal(crc);
  return crc;
}

// Whether the EEPROM holds the configuration in use. Not after a blank (or corrupt) one: the
// built-in image goes there before the first value is staged (as the settings' defaults are
// written back), so that staged values change the configuration in use and nothing else. Not
// at power-up: 178 bytes take the EEPROM 0.6 s to write.
bool g_in_eeprom;

void ensure_in_eeprom() {
  if (g_in_eeprom) return;
  image_crc(kBuiltInImage, true);
  g_in_eeprom = true;
}

// Puts a configuration read by config_read in use.
void use(const ConfiguredArm<kJoints>& next, uint16_t sum) {
  if (&next != &config) config = next;
  checksum = sum;
  for (uint8_t i = 0; i < kJoints; ++i) {
    const MotorSpec& m = config.actuation.motors[i];
    setup_scale(g_scale[i], m);
    home_steps[i] = quantize_within_limits(m, config.home[i]);
  }
}
}  // namespace

Millideg step_angle(uint8_t i, int32_t steps) {
  StepScale& k = g_scale[i];
  if (steps == k.last_steps) return k.last_angle;
  const MotorSpec& m = config.actuation.motors[i];
  const uint32_t mag = steps < 0 ? 0u - uint32_t(steps) : uint32_t(steps);
  Millideg a;
  if (mag > k.most) {  // (also when k.most is 0)
    a = steps_to_millideg(m, steps);
  } else {
    // round(mag den / num), a half away from zero, as detail::div_round_half_away.
    const uint32_t q = (2 * mag * k.den + k.num) / (2 * k.num);
    a = (steps < 0) != (m.direction < 0) ? m.zero - Millideg(q) : m.zero + Millideg(q);
  }
  // Called from the status report only (one at a time): the cache needs no lock.
  k.last_steps = steps;
  k.last_angle = a;
  return a;
}

void setup() {
  // Read in place: nothing runs yet, and a copy would take ~250 bytes of the stack.
  uint16_t c = image_crc(kStaged, false);
  g_in_eeprom = sealed(c) && config_read(config, kStaged) == kConfigOk;
  if (!g_in_eeprom) {
    c = image_crc(kBuiltInImage, false);
    config_read(config, kBuiltInImage);
  }
  use(config, c);
}

Status stage(uint16_t n, int32_t thousandths) {
  const Status s = config_check(n, thousandths);
  if (s != kOk) return s;
  ensure_in_eeprom();
  ConfigField f;
  config_field(n, f);
  uint8_t b[4];
  config_bytes(b, f, thousandths);
  hal::eeprom_write(uint16_t(kImageAt + f.offset), b, f.size);
  return kOk;
}

Status stage_name(const char* s, uint8_t len) {
  const Status st = config_check_name(s, len);
  if (st != kOk) return st;
  ensure_in_eeprom();
  uint8_t b[kMaxRobotName];
  config_name_bytes(b, s, len);
  hal::eeprom_write(kImageAt + kConfigNameOffset, b, kMaxRobotName);
  return kOk;
}

Status commit(int32_t crc) {
  ensure_in_eeprom();
  const uint16_t c = image_crc(kStaged, false);
  if (crc != int32_t(c)) return kConfigChecksum;
  ConfiguredArm<kJoints> next;
  if (config_read(next, kStaged) != kConfigOk) return kConfigInvalid;
  seal(c);
  use(next, c);
  return kOk;
}

}  // namespace robot
