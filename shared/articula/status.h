// articula/status.h - the one table of protocol status codes.
//
// Every reply on the serial line is `ok` or `error:<code>` (a report's `W:<code>` field
// carries a code too); the firmware prints only the number, host tools print the text from
// this same table. Codes are never renumbered and never reused: a new condition gets the
// next free number (GRBL's rule).
// docs/protocol.md lists the same table; a test checks that the two agree.
#ifndef ARTICULA_STATUS_H
#define ARTICULA_STATUS_H

#include "platform.h"

namespace articula {

// X(code, name, text)
#define ARTICULA_STATUS_TABLE(X)                                                         \
  X(0, kOk, "ok")                                                                      \
  X(1, kEmptyLine, "empty line")                                                       \
  X(2, kUnknownCommand, "unknown command")                                             \
  X(3, kBadNumber, "bad number (expected digits with optional sign and decimal point)") \
  X(4, kMissingArgument, "missing argument")                                           \
  X(5, kExtraArgument, "too many arguments")                                           \
  X(6, kBadJoint, "no such joint")                                                     \
  X(7, kLineTooLong, "line too long")                                                  \
  X(8, kValueOutOfRange, "value out of range")                                         \
  X(9, kJointLimit, "target beyond a joint limit")                                     \
  X(10, kUnreachable, "target out of reach")                                           \
  X(11, kBadCharacter, "character not allowed (control or non-ASCII byte)")            \
  X(12, kNotHomed, "not homed: send H or Z first")                                     \
  X(13, kSettingUnknown, "no such setting")                                            \
  X(14, kSettingsReset, "settings reset to defaults")                                  \
  X(15, kStopped, "discarded by stop (!)")                                             \
  X(16, kNoClosedForm, "P and T need a yaw-pitch-pitch arm: this robot has no closed form") \
  X(17, kConfigChecksum, "robot configuration incomplete: its checksum differs")        \
  X(18, kConfigInvalid, "robot configuration unusable (a motor's steps, gear, limits or home)") \
  X(19, kLineNotFollowed, "the straight line passes where the arm must change its pose (a singularity)") \
  X(20, kPinUnavailable, "no such pin, or one the arm's drive uses (O, W: D0..D13 are 0..13, A0..A5 14..19)") \
  X(21, kInputTimeout, "an input did not read its level in time (W): what was queued after it was dropped")

enum Status : uint8_t {
#define ARTICULA_STATUS_ENUM(code, name, text) name = code,
  ARTICULA_STATUS_TABLE(ARTICULA_STATUS_ENUM)
#undef ARTICULA_STATUS_ENUM
};

// Number of codes in the table (codes are 0 .. kStatusCount - 1, without gaps).
static const uint8_t kStatusCount = 0
#define ARTICULA_STATUS_COUNT(code, name, text) +1
    ARTICULA_STATUS_TABLE(ARTICULA_STATUS_COUNT)
#undef ARTICULA_STATUS_COUNT
    ;

// The text of a status. For host tools: on the AVR these strings would sit in RAM, so
// the firmware prints numbers only and never calls this.
inline const char* status_text(uint8_t code) {
  switch (code) {
#define ARTICULA_STATUS_TEXT(code, name, text) \
  case code:                                   \
    return text;
    ARTICULA_STATUS_TABLE(ARTICULA_STATUS_TEXT)
#undef ARTICULA_STATUS_TEXT
  }
  return "unknown status";
}

// The identifier of a status without its k prefix ("JointLimit"), for docs and logs.
inline const char* status_name(uint8_t code) {
  switch (code) {
#define ARTICULA_STATUS_NAME(code, name, text) \
  case code:                                   \
    return &(#name)[1];
    ARTICULA_STATUS_TABLE(ARTICULA_STATUS_NAME)
#undef ARTICULA_STATUS_NAME
  }
  return "Unknown";
}

}  // namespace articula

#endif  // ARTICULA_STATUS_H
