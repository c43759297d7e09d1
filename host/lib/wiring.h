// host/lib/wiring.h - every wire of an arm: which board pin goes to which driver input, switch
// or servo, from the robot's drive (robot.h's Drive) and the board's one pin table
// (firmware/src/board.h). The robot file's loader asks it whether the board can give the
// wiring the file asks for; the studio's Wiring view and the docs draw from it.
#ifndef ARTICULA_HOST_WIRING_H
#define ARTICULA_HOST_WIRING_H

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robot.h"

namespace articula::host {

// One board pin and what it is wired to.
struct Wire {
  int pin = 0;         // index into board::kHeaderPin (D0..D13, A0..A5)
  std::string signal;  // the input or output at the other end: "IN1", "STEP", "DIR", "EN", "signal", "switch", "RX", ...
  std::string part;    // what that end belongs to: "L298N #1", "socket X (A4988)", "servo", "endstop", "USB serial"
  int motor = -1;      // the motor it serves (file order), or -1 (the board's own: serial, LED, gripper, EN)
};

struct Wiring {
  int board = 0;  // index into board::kBoardInfo
  std::vector<Wire> wires;  // the board's own (serial, LED, gripper), then each motor's
};

// A drive the board cannot give. `motor` is the motor at fault (-1: the board, the gripper or an
// I/O pin), `field` the part of its driver ("kind", "pin", "enable"; empty: the motor as a
// whole), `io` the I/O pin at fault (-1: none).
class WiringError : public std::runtime_error {
 public:
  WiringError(int motor, std::string field, const std::string& problem, int io = -1)
      : std::runtime_error(problem), motor(motor), field(std::move(field)), io(io) {}
  int motor;
  std::string field;
  int io;
};

// The arm's wiring. Throws WiringError when a motor's driver does not fit the board (STEP/DIR
// without a CNC shield, an L298N on one, more steppers than slots, drivers of different kinds in
// one arm) or when two things would share a pin (an I/O pin on one the drive uses among them).
Wiring wire(const Robot& robot);

// The firmware build that drives the robot's motors: "articula-nano" (L298N, ULN2003; a robot
// whose file names no drive), "articula-cnc" (STEP/DIR drivers in a CNC shield),
// "articula-servo" (hobby servos on the board's pins). firmware/avr.cmake makes each.
const char* firmware_build(const Robot& robot);

// The header pins the robot's firmware build lets O and W use (protocol.h), bit n for header pin
// n (board.h's kHeaderPin): those its drive keeps not (board.h's kKeptBy* masks; a servo arm's
// joints' signal pins too).
uint32_t io_pins_free(const Robot& robot);
// Their names, "A5" or "D12, A0, A1, A2, A4, A5"; "none" when there are none.
std::string io_pins_free_text(const Robot& robot);

// The wiring as data, for the CLI (`articula wiring`), Python (`Robot.wiring()`) and the page:
// {"board": id, "board_title", "given" (the file names its drive), "firmware" (firmware_build),
// "supply" (supply_notes), "io_pins" ([{"pin": 19, "name": "A5"}]: io_pins_free, for O and W),
// "header_pins" (every header pin's name by its index: "D0" .. "A5"),
// "wires": [{"pin": "D4",
// "signal": "IN1", "part": "L298N #0", "motor": "base" or null}]}; for an arm the board cannot
// wire (a file that names no drive and has more motors than slots), "wires" is empty and
// "error" says why.
nlohmann::json wiring_json(const Robot& robot);

// What the wires alone do not say, a sentence each: the supply the drive needs and its common
// ground (servos: 5 V and their stall current, not the Nano's pin; L298N, ULN2003, the CNC
// shield's motor supply), and on a CNC shield each driver's microstep jumpers for the file's
// microsteps and its current limit. wiring_json's "supply".
std::vector<std::string> supply_notes(const Robot& robot);
// A 9 g hobby servo's stall current, A (the SG90's datasheet: about 0.65 A at 5 V).
constexpr double kServoStallAmps = 0.65;

// A header pin's name by its index ("D12", "A0"; "pin 20" past the header's last).
std::string header_pin_name(int pin);

// The index of a header pin's name ("D9", "A3") on `board`, or -1 with the reason in `why`
// (no such pin, an analog-only input).
int header_pin(int board, const std::string& name, std::string& why);

// The board's id, or -1.
int board_by_id(const std::string& id);

// "nano, uno, nano-cnc-v4, uno-cnc-v3": for messages.
std::string board_ids();

}  // namespace articula::host

#endif  // ARTICULA_HOST_WIRING_H
