// firmware/src/settings.h - the $n settings (articula/settings.h numbers them and gives
// their ranges), kept in EEPROM behind a version byte and a CRC-16. docs/protocol.md
// ("Settings") lists them.
#ifndef ARTICULA_FIRMWARE_SETTINGS_H
#define ARTICULA_FIRMWARE_SETTINGS_H

#include <articula/config.h>
#include <articula/settings.h>
#include "ram.h"

namespace settings {

// The names the firmware uses for the shared numbers.
enum Id : uint8_t {
  kMaxRate = articula::kSetMaxRate,
  kAccel = articula::kSetAccel,
  kReleaseMs = articula::kSetReleaseMs,
  kEndstops = articula::kSetEndstops,
  kHomingRate = articula::kSetHomingRate,
  kSettleMs = articula::kSetSettleMs,
  kJunction = articula::kSetJunction,
  kChord = articula::kSetChord,
  kCount = articula::kSettingCount,
};

// EEPROM image: [0] kVersion, [1 .. 4 kCount] the values (uint32, little-endian), then the
// CRC-16/CCITT-FALSE (articula::crc16) of all the bytes before it, low byte first. Version 2
// (eight settings) lives after the robot configuration (robot.h); version 1's six at 0 are
// not read: an arm updated to it starts from the defaults, with the SettingsReset warning.
static const uint8_t kVersion = 2;
static const uint16_t kAddress = 256;
static const uint16_t kImageSize = 1 + 4 * kCount + 2;

// The settings' state (state.h holds it; only settings.cpp writes it).
struct Ram {
  uint32_t value[kCount];
  uint8_t warning;  // take_warning()'s
};
ARTICULA_FIRMWARE_RAM(Ram, ram)


// The current values (whole numbers in the units above), kCount of them.
inline uint32_t* value() { return ram().value; }

// Reads the EEPROM; a blank or corrupt image (version or CRC wrong) loads the defaults,
// writes them back, and raises the SettingsReset warning.
void load();

// $n=v: n a setting number, v in thousandths (as parsed). Unknown n: kSettingUnknown; v not
// a whole number within the setting's range: kValueOutOfRange.
articula::Status check(int32_t n, int32_t thousandths);
// check(), and on kOk the value is stored and saved to EEPROM (else nothing changes).
articula::Status set(int32_t n, int32_t thousandths);

// kSettingsReset once after load() fell back to the defaults, then 0: for the W field of
// the next status or info report.
uint8_t take_warning();
// A status code for the next report to say once (a W that ran out of time: kInputTimeout).
void warn(uint8_t code);

}  // namespace settings

#endif  // ARTICULA_FIRMWARE_SETTINGS_H
