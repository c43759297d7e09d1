// firmware/src/settings.cpp - the settings table, EEPROM image and validation.
#include "settings.h"

#include <string.h>

#include "hal.h"
#include "robot.h"

namespace settings {

namespace {
// The settings' state (settings.h), in the firmware's (state.h).
inline Ram& sr() { return ram(); }

void save() {
  uint8_t image[kImageSize];
  image[0] = kVersion;
  memcpy(image + 1, sr().value, 4 * kCount);  // both targets are little-endian
  const uint16_t crc = articula::crc16(image, kImageSize - 2);
  image[kImageSize - 2] = uint8_t(crc);
  image[kImageSize - 1] = uint8_t(crc >> 8);
  hal::eeprom_write(kAddress, image, kImageSize);
}
}  // namespace

void load() {
  uint8_t image[kImageSize];
  hal::eeprom_read(kAddress, image, kImageSize);
  const uint16_t crc = articula::crc16(image, kImageSize - 2);
  bool good = image[0] == kVersion && image[kImageSize - 2] == uint8_t(crc) && image[kImageSize - 1] == uint8_t(crc >> 8);
  if (good) {
    memcpy(sr().value, image + 1, 4 * kCount);
    for (uint8_t i = 0; i < kCount; ++i) {
      const articula::SettingRange r = articula::setting_range(i, robot::kJoints);
      good = good && sr().value[i] >= r.min && sr().value[i] <= r.max;
    }
  }
  sr().warning = 0;
  if (!good) {
    for (uint8_t i = 0; i < kCount; ++i) sr().value[i] = articula::setting_range(i, robot::kJoints).fallback;
    save();
    sr().warning = articula::kSettingsReset;
  }
}

articula::Status check(int32_t n, int32_t thousandths) {
  // $3: only the bits of the motors the configuration uses.
  return articula::check_setting(n, thousandths, robot::count());
}

articula::Status set(int32_t n, int32_t thousandths) {
  const articula::Status s = check(n, thousandths);
  if (s != articula::kOk) return s;
  sr().value[n] = uint32_t(thousandths / 1000);
  save();
  return articula::kOk;
}

void warn(uint8_t code) { sr().warning = code; }

uint8_t take_warning() {
  // The main loop (info line) and the status report (an interrupt) both take it: once.
  const uint8_t s = hal::interrupts_off();
  const uint8_t w = sr().warning;
  sr().warning = 0;
  hal::interrupts_restore(s);
  return w;
}

}  // namespace settings
