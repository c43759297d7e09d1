// firmware/src/board.h - every pin of the Nano, in this one table (GRBL's cpu_map.h idea).
// The firmware's registers come from it (pins.h); both emulated Nanos read the pins by it
// (simavr's in virtual-nano/simavr, the page's avr8js through the nano decoder module, virtual-nano/web/nano_parts.cpp).
// Plain C++11 with no AVR header, so the host compiles it too.
//
//   Nano pin  AVR pin  use
//   D0, D1    PD0,PD1  USB serial (RX, TX)
//   D2        PD2      endstop 0 (base), to GND when pressed
//   D3        PD3      gripper servo signal (pulses made in software from Timer1 COMPB)
//   D4..D7    PD4..7   motor 0 (base):     IN1..IN4 of L298N #0
//   D8..D11   PB0..3   motor 1 (shoulder): IN1..IN4 of L298N #1
//   D12       PB4      endstop 1 (shoulder)
//   D13       PB5      on-board LED
//   A0..A3    PC0..3   motor 2 (elbow):    IN1..IN4 of L298N #2
//   A4        PC4      endstop 2 (elbow)
//   A5        PC5      free
//   A6, A7    -        analog inputs only: free
//
// Each motor's four L298N inputs IN1..IN4 sit on four consecutive bits of ONE port, so a new
// coil pattern is one port write and the four pins change on the same clock cycle
// (digitalWrite would spread them over about 76 cycles, and a pin monitor would see three
// intermediate patterns): pattern bit 0 (IN1) goes to bit `shift`.
//
// No conflict with the timers: Timer0 (millis) drives no pin; Timer1's compare outputs OC1A
// (D9) and OC1B (D10) stay disconnected (COM1x = 0), so D9 and D10 are plain port bits; Timer2
// is unused (hal::init stops it, and the ADC). D11..D13 are also the ISP header's
// MOSI/MISO/SCK: unplug the L298N inputs before flashing through ISP (the USB bootloader does
// not touch them).
#ifndef ARTICULA_FIRMWARE_BOARD_H
#define ARTICULA_FIRMWARE_BOARD_H

namespace board {

// The ports, by index: 0 B, 1 C, 2 D.
enum Port { kPortB = 0, kPortC = 1, kPortD = 2 };
constexpr char kPortNames[3] = {'B', 'C', 'D'};
// Their registers' I/O addresses on the ATmega328P (PINx, DDRx, PORTx are three in a row).
constexpr int pin_io(int port) { return 0x03 + 3 * port; }
constexpr int ddr_io(int port) { return 0x04 + 3 * port; }
constexpr int port_io(int port) { return 0x05 + 3 * port; }

struct MotorPins {
  int port, shift;  // IN1..IN4 on bits shift..shift+3 of the port
  const char* pins;
};
constexpr int kWiredMotors = 3;
constexpr MotorPins kMotorPins[kWiredMotors] = {
    {kPortD, 4, "PD4..PD7 (D4..D7)"}, {kPortB, 0, "PB0..PB3 (D8..D11)"}, {kPortC, 0, "PC0..PC3 (A0..A3)"}};

struct Pin {
  int port, bit;
  const char* pin;
};
constexpr Pin kEndstopPins[kWiredMotors] = {{kPortD, 2, "PD2 (D2)"}, {kPortB, 4, "PB4 (D12)"}, {kPortC, 4, "PC4 (A4)"}};
constexpr Pin kServoPin = {kPortD, 3, "PD3 (D3)"};
constexpr Pin kLedPin = {kPortB, 5, "PB5 (D13)"};

constexpr unsigned long kSerialBaud = 115200UL;  // USART0 on D0/D1 (the USB bridge)

// ---- every board a robot file may name ("board"), and what each wires ----
//
// The Nano and the Uno carry the same ATmega328P with the same header names (D0..D13 on ports
// D and B, A0..A5 on port C); the Nano adds A6 and A7, inputs of the ADC only. On these bare
// boards the map above holds: three 4-wire stepper slots (an L298N or a ULN2003 each), the
// endstops, the gripper servo and the LED.
//
// The CNC shields (Protoneer's CNC Shield V3 on an Uno, the CNC Shield V4 on a Nano) route the
// pins GRBL's cpu_map uses for the ATmega328P, from their published pinouts:
//
//   Nano/Uno pin  AVR pin  shield label       use
//   D2, D3, D4    PD2..4   X/Y/Z STEP         the STEP input of the driver in socket X, Y, Z
//   D5, D6, D7    PD5..7   X/Y/Z DIR          its DIR input
//   D8            PB0      EN                 every driver's ENABLE (low: enabled)
//   D9, D10, D11  PB1..3   X-, Y-, Z- limit   endstops (V3.0 and V4 silkscreen; V3.1+ moved Z to D12)
//   A3            PC3      CoolEn             the gripper servo (present on every version)
//   D13           PB5      SpnDir             the on-board LED
//
// The socket order is the motor order: the first motor of the file in X, then Y, then Z. The
// fourth socket (A) clones an axis or takes D12/D13 by jumpers; the firmware does not use it.
enum BoardId { kBoardNano = 0, kBoardUno = 1, kBoardNanoCncV4 = 2, kBoardUnoCncV3 = 3 };
constexpr int kBoards = 4;
struct BoardInfo {
  const char* id;      // as a robot file names it
  const char* title;   // as a person reads it
  bool cnc_shield;     // STEP/DIR sockets (and no 4-wire slots)
  bool has_a6_a7;      // the Nano's two analog-only inputs
  long flash_bytes;    // the application's room: below the bootloader it ships with
};
constexpr BoardInfo kBoardInfo[kBoards] = {
    {"nano", "Arduino Nano", false, true, 30720L},  // the old 2 KB bootloader (new Nanos: Optiboot, 32,256)
    {"uno", "Arduino Uno", false, false, 32256L},   // Optiboot, 512 B
    {"nano-cnc-v4", "Arduino Nano on a CNC Shield V4", true, true, 30720L},
    {"uno-cnc-v3", "Arduino Uno on a CNC Shield V3", true, false, 32256L},
};

// The header's digital pins by name, D0..D13 then A0..A5 (index 14 + n for An).
constexpr int kHeaderPins = 20;
constexpr Pin kHeaderPin[kHeaderPins] = {
    {kPortD, 0, "D0"}, {kPortD, 1, "D1"}, {kPortD, 2, "D2"}, {kPortD, 3, "D3"},  {kPortD, 4, "D4"},
    {kPortD, 5, "D5"}, {kPortD, 6, "D6"}, {kPortD, 7, "D7"}, {kPortB, 0, "D8"},  {kPortB, 1, "D9"},
    {kPortB, 2, "D10"}, {kPortB, 3, "D11"}, {kPortB, 4, "D12"}, {kPortB, 5, "D13"}, {kPortC, 0, "A0"},
    {kPortC, 1, "A1"}, {kPortC, 2, "A2"}, {kPortC, 3, "A3"},  {kPortC, 4, "A4"},  {kPortC, 5, "A5"}};

// A header pin's index in kHeaderPin by its name ("D9", "A3"), or -1: for the host's tools (the
// robot file's loader, the virtual Nanos); the firmware takes indexes.
inline int header_index(const char* name) {
  for (int i = 0; i < kHeaderPins; ++i) {
    const char* a = name;
    const char* b = kHeaderPin[i].pin;
    while (*a && *a == *b) ++a, ++b;
    if (*a == *b) return i;
  }
  return -1;
}

// A CNC shield's sockets: a STEP/DIR driver module each.
struct Socket {
  const char* axis;
  Pin step, dir;
};
constexpr int kShieldSockets = 3;
constexpr Socket kShieldSocket[kShieldSockets] = {{"X", {kPortD, 2, "PD2 (D2)"}, {kPortD, 5, "PD5 (D5)"}},
                                                  {"Y", {kPortD, 3, "PD3 (D3)"}, {kPortD, 6, "PD6 (D6)"}},
                                                  {"Z", {kPortD, 4, "PD4 (D4)"}, {kPortD, 7, "PD7 (D7)"}}};
constexpr Pin kShieldEnable = {kPortB, 0, "PB0 (D8)"};
constexpr Pin kShieldEndstopPins[kShieldSockets] = {
    {kPortB, 1, "PB1 (D9)"}, {kPortB, 2, "PB2 (D10)"}, {kPortB, 3, "PB3 (D11)"}};
constexpr Pin kShieldServoPin = {kPortC, 3, "PC3 (A3)"};

// ---- the pins a program may use (protocol.h's O and W, the robot file's "io") ----
//
// A header pin's bit in a mask of header pins (bit n: kHeaderPin[n]).
constexpr unsigned long header_bit(const Pin& p) {
  return 1UL << (p.port == kPortD ? p.bit : p.port == kPortB ? 8 + p.bit : 14 + p.bit);
}
// What every build keeps: the serial line and the LED.
constexpr unsigned long kKeptAlways = header_bit(kHeaderPin[0]) | header_bit(kHeaderPin[1]) | header_bit(kLedPin);
// The 4-wire build: its three coil slots, their endstops and the gripper servo, used or not
// (the firmware drives the slots it has): A5 is left.
constexpr unsigned long kKeptByCoils =
    kKeptAlways | (0xFUL << 4) | (0xFUL << 8) | (0xFUL << 14) | header_bit(kEndstopPins[0]) |
    header_bit(kEndstopPins[1]) | header_bit(kEndstopPins[2]) | header_bit(kServoPin);
// The shield build: STEP, DIR, EN, the limit switches and the gripper: D12, A0..A2, A4, A5 are
// left (the shield's spindle, abort, hold, resume and I2C headers).
constexpr unsigned long kKeptByShield =
    kKeptAlways | header_bit(kShieldSocket[0].step) | header_bit(kShieldSocket[1].step) |
    header_bit(kShieldSocket[2].step) | header_bit(kShieldSocket[0].dir) | header_bit(kShieldSocket[1].dir) |
    header_bit(kShieldSocket[2].dir) | header_bit(kShieldEnable) | header_bit(kShieldEndstopPins[0]) |
    header_bit(kShieldEndstopPins[1]) | header_bit(kShieldEndstopPins[2]) | header_bit(kShieldServoPin);
// The servo build: the gripper's servo; its joints' servos take the pins its configuration
// names (robot::kept_pins, the host's io_pins_free add them).
constexpr unsigned long kKeptByServos = kKeptAlways | header_bit(kServoPin);
constexpr unsigned long kAllHeaderPins = (1UL << kHeaderPins) - 1;
// The pins a drive keeps, by its family: the firmware's check of O and W (robot::kept_pins) and
// the host's list of what they may use (wiring.h's io_pins_free).
constexpr unsigned long kept_by(bool step_dir, bool servos) {
  return step_dir ? kKeptByShield : servos ? kKeptByServos : kKeptByCoils;
}
static_assert(kKeptByCoils == 0xFFFFFUL - (1UL << 19), "the 4-wire build leaves A5 only");
static_assert(kKeptByShield == 0xFFFFFUL - (1UL << 12) - (7UL << 14) - (3UL << 18), "the shield leaves D12, A0..A2, A4, A5");

}  // namespace board

#endif  // ARTICULA_FIRMWARE_BOARD_H
