// firmware/src/robot.cpp - the robot configuration: EEPROM, the built-in default, staging.
#include "robot.h"

#include "hal.h"
#if defined(ARTICULA_CNC_SHIELD)
#include "builtin_config_cnc.h"  // the MK2 Plus on A4988s in a CNC shield's sockets
#elif defined(ARTICULA_SERVO_ARM)
#include "builtin_config_servo.h"  // the meArm: four SG90 servos
#else
#include "builtin_config.h"
#endif

using namespace articula;

namespace robot {

namespace {
// The configuration's state (robot.h), in the firmware's (state.h).
inline Ram& rb() { return ram(); }

const uint16_t kAddress = kEepromAddress;
const uint8_t kVersion = kEepromVersion;
const uint16_t kImageAt = kEepromImageAt;
const uint16_t kCrcAt = kEepromCrcAt;

// What a blank EEPROM gets: the MK2 (builtin_config.h, made by the host's nano_config; on a
// CNC shield builtin_config_cnc.h, the MK2 on STEP/DIR drivers; the servo build's
// builtin_config_servo.h, the meArm).
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

// The CRC of an image, read a piece at a time (the whole would take kConfigImageSize bytes of the stack);
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
// at power-up: 178 bytes take the EEPROM 0.6 s to write. (Ram::in_eeprom)

void ensure_in_eeprom() {
  if (rb().in_eeprom) return;
  image_crc(kBuiltInImage, true);
  rb().in_eeprom = true;
}


// Puts a configuration read by config_read in use.
void put_in_use(const ConfiguredArm<kJoints>& next, uint16_t sum) {
  Ram& r = rb();
  if (&next != &r.config) r.config = next;
  r.checksum = sum;
  for (uint8_t i = 0; i < kJoints; ++i) {
    const MotorSpec& m = r.config.actuation.motors[i];
    r.home_steps[i] = quantize_within_limits(m, r.config.home[i]);
  }
}
}  // namespace

// (Only the SITL calls it: on the Nano the linker drops it, and setup() and commit() keep their
// own inlined call.)
void use(const ConfiguredArm<kJoints>& next, uint16_t sum) { put_in_use(next, sum); }

void store(const uint8_t* image) {
  hal::eeprom_write(kImageAt, image, kConfigImageSize);
  seal(crc16(image, kConfigImageSize));
}

Millideg step_angle(uint8_t i, int32_t steps) { return steps_to_millideg(config().actuation.motors[i], steps); }

void setup() {
  // Read in place: nothing runs yet, and a copy would take ~250 bytes of the stack.
  uint16_t c = image_crc(kStaged, false);
  ConfiguredArm<kJoints>& arm = rb().config;
  rb().in_eeprom = sealed(c) && config_read(arm, kStaged, kDrives) == kConfigOk;
  if (!rb().in_eeprom) {
    c = image_crc(kBuiltInImage, false);
    config_read(arm, kBuiltInImage, kDrives);
  }
  put_in_use(arm, c);
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
  if (config_read(next, kStaged, kDrives) != kConfigOk) return kConfigInvalid;
  seal(c);
  put_in_use(next, c);
  return kOk;
}

}  // namespace robot
