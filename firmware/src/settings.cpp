// firmware/src/settings.cpp - the settings table, EEPROM image and validation.
#include "settings.h"

#include <string.h>

#include "hal.h"
#include "robot.h"

namespace settings {

// Defaults for an L298N driving a NEMA17 at 12 V in full steps. The rate limits keep the
// step interrupt (about 100 us for three motors) well inside the interval.
const Range kRanges[kCount] = {
    {1, 4000, 600},                     // $0 max rate, steps/s
    {1, 100000, 2000},                  // $1 acceleration, steps/s^2
    {0, 60000, 2000},                   // $2 coil release, ms (0: never)
    {0, (1u << robot::kJoints) - 1, 0},  // $3 endstop mask (bits of motors beyond count(): check())
    {1, 4000, 200},                     // $4 homing rate, steps/s
    {0, 10000, 300},                    // $5 gripper settle, ms
};

uint32_t value[kCount];

namespace {
uint8_t g_warning;

void save() {
  uint8_t image[kImageSize];
  image[0] = kVersion;
  memcpy(image + 1, value, 4 * kCount);  // both targets are little-endian
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
    memcpy(value, image + 1, 4 * kCount);
    for (uint8_t i = 0; i < kCount; ++i) good = good && value[i] >= kRanges[i].min && value[i] <= kRanges[i].max;
  }
  g_warning = 0;
  if (!good) {
    for (uint8_t i = 0; i < kCount; ++i) value[i] = kRanges[i].fallback;
    save();
    g_warning = articula::kSettingsReset;
  }
}

articula::Status check(int32_t n, int32_t thousandths) {
  if (n < 0 || n >= kCount) return articula::kSettingUnknown;
  if (thousandths < 0 || thousandths % 1000 != 0) return articula::kValueOutOfRange;
  const uint32_t v = uint32_t(thousandths / 1000);
  if (v < kRanges[n].min || v > kRanges[n].max) return articula::kValueOutOfRange;
  if (n == kEndstops && (v >> robot::count()) != 0) return articula::kValueOutOfRange;
  return articula::kOk;
}

articula::Status set(int32_t n, int32_t thousandths) {
  const articula::Status s = check(n, thousandths);
  if (s != articula::kOk) return s;
  value[n] = uint32_t(thousandths / 1000);
  save();
  return articula::kOk;
}

uint8_t take_warning() {
  // The main loop (info line) and the status report (an interrupt) both take it: once.
  const uint8_t s = hal::interrupts_off();
  const uint8_t w = g_warning;
  g_warning = 0;
  hal::interrupts_restore(s);
  return w;
}

}  // namespace settings
