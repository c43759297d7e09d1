// articula/settings.h - the controller's settings, `$0` to `$7`: their numbers, ranges and
// defaults, here and nowhere else. The firmware stores and checks them (firmware/src/
// settings.cpp), the host's prediction applies them (host/lib/predict.cpp), and the fuzz
// and the page ask the host library for them. docs/protocol.md ("Settings") describes them.
#ifndef ARTICULA_SETTINGS_H
#define ARTICULA_SETTINGS_H

#include "platform.h"
#include "status.h"

namespace articula {

// Setting numbers. Never renumbered (hosts and saved listings use them).
enum SettingId : uint8_t {
  kSetMaxRate = 0,     // top step rate of a move's dominant motor, steps/s
  kSetAccel = 1,       // acceleration of the dominant motor, steps/s^2
  kSetReleaseMs = 2,   // coils switched off after this long at rest, ms; 0 never
  kSetEndstops = 3,    // bit i: motor i has a homing switch at its minimum
  kSetHomingRate = 4,  // step rate while seeking a switch, steps/s
  kSetSettleMs = 5,    // pause after each gripper action for the servo to get there, ms
  kSetJunction = 6,    // junction deviation, hundredths of a step (planner.h); 0: every move
                       // starts and ends at rest
  kSetChord = 7,       // a straight line's chord tolerance: its segments stay this close to
                       // the line, micrometres
  kSettingCount = 8,
};

struct SettingRange {
  uint32_t min, max, fallback;  // fallback: the default
};

// Defaults for an L298N driving a NEMA17 at 12 V in full steps. The rate limits keep the
// step interrupt (about 100 us for three motors) well inside the interval. The junction
// default, half a step, lets a motor's rate jump by sqrt(8 a d) = 89 steps/s at the default
// acceleration: about what every start from rest asks already (the first step ends at
// 2 / c0 = 63 steps/s) and far below a NEMA17's pull-in rate. The chord default, 0.1 mm, is
// a tenth of the MK2's finest step at the tool. In flash on the Nano (ARTICULA_IN_FLASH).
static const SettingRange kSettingTable[kSettingCount] ARTICULA_IN_FLASH = {
    {1, 4000, 600},    // $0 kSetMaxRate
    {1, 100000, 2000}, // $1 kSetAccel
    {0, 60000, 2000},  // $2 kSetReleaseMs
    {0, 0, 0},         // $3 kSetEndstops: its maximum is the motors' bits (setting_range)
    {1, 4000, 200},    // $4 kSetHomingRate
    {0, 10000, 300},   // $5 kSetSettleMs
    {0, 10000, 50},    // $6 kSetJunction
    {10, 10000, 100},  // $7 kSetChord
};

inline SettingRange setting_range(uint8_t n, uint8_t motors) {
  if (n >= kSettingCount) {
    const SettingRange none = {0, 0, 0};
    return none;
  }
  SettingRange r = from_flash(kSettingTable[n]);
  if (n == kSetEndstops) r.max = motors >= 31 ? 0x7FFFFFFFUL : (1UL << motors) - 1;
  return r;
}

// `$n=v` as the firmware checks it: n a setting number, v in thousandths (as parsed), a
// whole number within the setting's range ($3: the bits of the arm's motors).
inline Status check_setting(int32_t n, int32_t thousandths, uint8_t motors) {
  if (n < 0 || n >= kSettingCount) return kSettingUnknown;
  if (thousandths < 0 || thousandths % 1000 != 0) return kValueOutOfRange;
  const uint32_t v = uint32_t(thousandths / 1000);
  const SettingRange r = setting_range(uint8_t(n), motors);
  if (v < r.min || v > r.max) return kValueOutOfRange;
  return kOk;
}

}  // namespace articula

#endif  // ARTICULA_SETTINGS_H
