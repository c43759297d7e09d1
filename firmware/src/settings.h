// firmware/src/settings.h - the $n settings: a table of numbers with their ranges, kept in
// EEPROM behind a version byte and a CRC-16. docs/protocol.md ("Settings") lists them.
#ifndef ARTICULA_FIRMWARE_SETTINGS_H
#define ARTICULA_FIRMWARE_SETTINGS_H

#include <articula/config.h>

namespace settings {

// Setting numbers: $0 .. $5. Never renumbered (hosts and saved listings use them).
enum Id : uint8_t {
  kMaxRate = 0,     // top step rate of a move's dominant motor, steps/s
  kAccel = 1,       // acceleration of the dominant motor, steps/s^2
  kReleaseMs = 2,   // coils switched off after this long at rest, ms; 0 never
  kEndstops = 3,    // bit i: motor i has a homing switch at its minimum
  kHomingRate = 4,  // step rate while seeking a switch, steps/s
  kSettleMs = 5,    // pause after each gripper action for the servo to get there, ms
  kCount = 6,
};

// EEPROM image: [0] kVersion, [1 .. 4 kCount] the values (uint32, little-endian), then the
// CRC-16/CCITT-FALSE (articula::crc16) of all the bytes before it, low byte first.
static const uint8_t kVersion = 1;
static const uint16_t kAddress = 0;
static const uint16_t kImageSize = 1 + 4 * kCount + 2;

struct Range {
  uint32_t min, max, fallback;  // fallback: the default
};
extern const Range kRanges[kCount];

// The current values (whole numbers in the units above).
extern uint32_t value[kCount];

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

}  // namespace settings

#endif  // ARTICULA_FIRMWARE_SETTINGS_H
