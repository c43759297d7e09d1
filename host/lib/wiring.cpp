// host/lib/wiring.cpp - an arm's wires from board.h's pin table (wiring.h).
#include "wiring.h"

#include <nlohmann/json.hpp>

#include <cstdio>

#include <articula/settings.h>

#include "board.h"

namespace articula::host {

namespace {

std::string quoted_name(const std::string& s) { return "\"" + s + "\""; }

// The header index of a Pin of board.h's tables (they name port and bit).
int header_of(const board::Pin& p) {
  for (int i = 0; i < board::kHeaderPins; ++i)
    if (board::kHeaderPin[i].port == p.port && board::kHeaderPin[i].bit == p.bit) return i;
  return -1;
}

bool is_stepper(DriveKind k) { return k != kDriveServo; }

}  // namespace

const char* io_mode_id(IoMode m) {
  switch (m) {
    case kIoOutput: return "output";
    case kIoInput: return "input";
    case kIoInputPullup: return "input_pullup";
  }
  return "?";
}

int board_by_id(const std::string& id) {
  for (int b = 0; b < board::kBoards; ++b)
    if (id == board::kBoardInfo[b].id) return b;
  return -1;
}

std::string board_ids() {
  std::string out;
  for (int b = 0; b < board::kBoards; ++b) out += std::string(b ? ", " : "") + board::kBoardInfo[b].id;
  return out;
}

int header_pin(int board_index, const std::string& name, std::string& why) {
  const board::BoardInfo& b = board::kBoardInfo[board_index];
  const int i = board::header_index(name.c_str());
  if (i >= 0) return i;
  if (name == "A6" || name == "A7")
    why = b.has_a6_a7 ? name + " is an analog input only: it cannot send a pulse"
                      : std::string("the ") + b.title + " has no " + name;
  else
    why = "no pin " + quoted_name(name) + " on the " + b.title + " (its pins are D0..D13 and A0..A5)";
  return -1;
}

Wiring wire(const Robot& robot) {
  Wiring w;
  w.board = robot.drive.board;
  const board::BoardInfo& info = board::kBoardInfo[w.board];
  const std::string board_name = std::string("board ") + quoted_name(info.id);
  const auto& motors = robot.drive.motors;
  const auto name = [&](std::size_t m) { return "motor " + quoted_name(robot.motor_names[m]); };

  // Every motor of an arm is driven one way: one firmware configuration drives one kind (STEP/DIR
  // drivers of different chips excepted: only their timing differs).
  for (std::size_t m = 1; m < motors.size(); ++m)
    if (motors[m].kind != motors[0].kind)
      throw WiringError(int(m), "kind",
                        name(m) + " is driven by " + kDriveKindInfo[motors[m].kind].id + " but " + name(0) + " by " +
                            kDriveKindInfo[motors[0].kind].id + ": the firmware drives every motor of an arm the same way");

  // What each pin is already wired to, to refuse a second use with both named.
  std::vector<int> owner(board::kHeaderPins, -1);
  const auto add = [&](int pin, const std::string& signal, const std::string& part, int motor,
                       const std::string& field, int io = -1) {
    if (owner[std::size_t(pin)] >= 0) {
      const Wire& first = w.wires[std::size_t(owner[std::size_t(pin)])];
      const std::string user = motor >= 0 ? name(std::size_t(motor)) + "'s " + part + " " + signal : part + " " + signal;
      const std::string other = first.motor >= 0 ? name(std::size_t(first.motor)) + "'s " + first.part + " " + first.signal
                                                  : "the " + first.part + " " + first.signal;
      throw WiringError(motor, field,
                        "pin " + std::string(board::kHeaderPin[pin].pin) + " of the " + info.title + " would carry both " +
                            other + " and " + user,
                        io);
    }
    owner[std::size_t(pin)] = int(w.wires.size());
    w.wires.push_back(Wire{pin, signal, part, motor});
  };

  // The board's own first: a motor that asks for one of these pins is the one at fault.
  add(0, "RX", "USB serial", -1, "");
  add(1, "TX", "USB serial", -1, "");
  add(header_of(board::kLedPin), "LED", "on-board", -1, "");
  if (robot.gripper.present)
    add(header_of(info.cnc_shield ? board::kShieldServoPin : board::kServoPin), "signal", "gripper servo", -1, "");

  int steppers = 0;
  bool enable_wired = false;
  for (std::size_t m = 0; m < motors.size(); ++m) {
    const MotorDriver& d = motors[m];
    const char* kind = kDriveKindInfo[d.kind].id;
    if (d.kind == kDriveStepDir && !info.cnc_shield)
      throw WiringError(int(m), "kind",
                        name(m) + ": step-dir needs a CNC shield's sockets, and " + board_name +
                            " has none (name \"nano-cnc-v4\" or \"uno-cnc-v3\")");
    if ((d.kind == kDriveL298n || d.kind == kDriveUln2003) && info.cnc_shield)
      throw WiringError(int(m), "kind",
                        name(m) + ": the sockets of the " + info.title + " take STEP/DIR driver modules, not an " +
                            kDriveKindInfo[d.kind].title + " (name board \"nano\" or \"uno\" for " + kind + ")");
    if (d.kind == kDriveServo && info.cnc_shield)
      throw WiringError(int(m), "kind",
                        name(m) + ": a servo joint on the " + info.title +
                            ": the firmware drives a shield's sockets only (name board \"nano\" or \"uno\" for a servo arm)");
    if (is_stepper(d.kind)) {
      const int slots = info.cnc_shield ? board::kShieldSockets : board::kWiredMotors;
      if (steppers == slots)
        throw WiringError(int(m), "", name(m) + " would be stepper " + std::to_string(steppers + 1) + ", and the " +
                                          info.title + " wires " + std::to_string(slots));
      const int slot = steppers++;
      if (info.cnc_shield) {
        const board::Socket& s = board::kShieldSocket[slot];
        const std::string part = std::string("socket ") + s.axis + " (" + kStepDirChip[d.chip].title + ")";
        add(header_of(s.step), "STEP", part, int(m), "");
        add(header_of(s.dir), "DIR", part, int(m), "");
        add(header_of(board::kShieldEndstopPins[slot]), "switch", std::string(s.axis) + "- endstop", int(m), "");
      } else {
        const board::MotorPins& p = board::kMotorPins[slot];
        const std::string part = std::string(kDriveKindInfo[d.kind].title) + " #" + std::to_string(slot);
        for (int k = 0; k < 4; ++k)
          add(header_of(board::Pin{p.port, p.shift + k, ""}), "IN" + std::to_string(k + 1), part, int(m), "");
        add(header_of(board::kEndstopPins[slot]), "switch", "endstop", int(m), "");
      }
      if (info.cnc_shield && !enable_wired) {
        enable_wired = true;
        add(header_of(board::kShieldEnable), "EN", "drivers", -1, "");
      }
    } else {
      add(d.pin, "signal", "servo", int(m), "pin");
    }
  }
  // The I/O pins the file names last: one on a pin the drive uses is the one at fault.
  for (std::size_t k = 0; k < robot.io.size(); ++k) {
    const IoPin& p = robot.io[k];
    add(p.pin, io_mode_id(p.mode), "I/O " + quoted_name(p.name), -1, "pin", int(k));
  }
  return w;
}

uint32_t io_pins_free(const Robot& robot) {
  const DriveKind kind = arm_drive(robot);
  uint32_t free = uint32_t(board::kAllHeaderPins & ~board::kept_by(kind == kDriveStepDir, kind == kDriveServo));
  if (kind == kDriveServo)  // (and its joints' servos, on the pins its file names)
    for (const MotorDriver& m : robot.drive.motors)
      if (m.pin >= 0) free &= ~(uint32_t(1) << m.pin);
  return free;
}

std::string io_pins_free_text(const Robot& robot) {
  std::string out;
  const uint32_t free = io_pins_free(robot);
  for (int i = 0; i < board::kHeaderPins; ++i)
    if (free & (uint32_t(1) << i)) out += (out.empty() ? "" : ", ") + std::string(board::kHeaderPin[i].pin);
  return out.empty() ? "none" : out;
}

const char* firmware_build(const Robot& robot) {
  const DriveKind kind = arm_drive(robot);
  return kind == kDriveStepDir ? "articula-cnc" : kind == kDriveServo ? "articula-servo" : "articula-nano";
}

namespace {
// The jumpers under a STEP/DIR module for a microstep mode (standalone: no serial interface),
// as its datasheet's table has them; "" when the chip has no such mode.
std::string microstep_jumpers(const StepDirChip& chip, int microsteps) {
  struct Mode {
    const char* chip;
    int microsteps;
    const char* on;
  };
  static const Mode kModes[] = {
      {"a4988", 1, "none"},           {"a4988", 2, "MS1"},           {"a4988", 4, "MS2"},
      {"a4988", 8, "MS1 and MS2"},    {"a4988", 16, "MS1, MS2 and MS3"},
      {"drv8825", 1, "none"},         {"drv8825", 2, "M0"},          {"drv8825", 4, "M1"},
      {"drv8825", 8, "M0 and M1"},    {"drv8825", 16, "M2"},         {"drv8825", 32, "M0 and M2"},
      {"tmc2208", 2, "MS1"},          {"tmc2208", 4, "MS2"},         {"tmc2208", 8, "none"},
      {"tmc2208", 16, "MS1 and MS2"}, {"tmc2209", 8, "none"},        {"tmc2209", 16, "MS1 and MS2"},
      {"tmc2209", 32, "MS1"},         {"tmc2209", 64, "MS2"},
  };
  for (const Mode& m : kModes)
    if (std::string(m.chip) == chip.id && m.microsteps == microsteps) return m.on;
  return "";
}
}  // namespace

std::vector<std::string> supply_notes(const Robot& robot) {
  std::vector<std::string> out;
  if (!robot.has_motors || robot.drive.motors.empty()) return out;
  const DriveKind kind = robot.drive.motors.front().kind;
  const int n = int(robot.drive.motors.size());
  if (kind == kDriveServo) {
    const int servos = n + (robot.gripper.present ? 1 : 0);
    char amps[16];
    std::snprintf(amps, sizeof amps, "%.1f", servos * kServoStallAmps);
    out.push_back("The servos' + to a 5 V supply that gives " + std::string(amps) + " A: each of the " +
                  std::to_string(servos) + " servos (the gripper's too) draws up to about 0.65 A when it stalls; "
                  "not the Nano's 5 V pin, which gives USB's 0.5 A and resets the Nano when the servos pull it down.");
    out.push_back("The servos' - to that supply's GND, and that GND to one of the Nano's GND pins: one common ground, "
                  "or the signals mean nothing to the servos.");
  } else if (kind == kDriveStepDir) {
    out.push_back("The shield's motor supply: 12 to 24 V to its power terminal (never through USB); its GND is the "
                  "Nano's through the shield.");
    std::vector<bool> said(size_t(n), false);  // the motors of one chip and mode in one sentence
    for (int i = 0; i < n; ++i) {
      if (said[size_t(i)]) continue;
      const int chip_id = robot.drive.motors[size_t(i)].chip, micro = robot.actuation.motors[i].microsteps;
      std::vector<std::string> names;
      for (int k = i; k < n; ++k)
        if (robot.drive.motors[size_t(k)].chip == chip_id && robot.actuation.motors[k].microsteps == micro)
          said[size_t(k)] = true, names.push_back(robot.motor_names[size_t(k)]);
      std::string list;
      for (size_t k = 0; k < names.size(); ++k)
        list += (k == 0 ? "" : k + 1 == names.size() ? " and " : ", ") + names[k];
      const StepDirChip& chip = kStepDirChip[chip_id];
      const std::string on = microstep_jumpers(chip, micro);
      const bool one = names.size() == 1;
      out.push_back(std::string(one ? "The " : "Each ") + chip.title + " (" + list + (one ? " motor" : " motors") + "): 1/" +
                    std::to_string(micro) + " step, its microstep jumpers on: " +
                    (on.empty() ? "(a mode the chip lacks)" : on) +
                    "; its current limit set with its potentiometer to the motor's rated current before the first move.");
    }
    // microsteps ask for more steps a second than the firmware's default top rate gives (issue 55, 5)
    int finest = 0;
    for (int i = 1; i < n; ++i)
      if (robot.actuation.motors[i].microsteps > robot.actuation.motors[finest].microsteps) finest = i;
    const MotorSpec& m = robot.actuation.motors[finest];
    const SettingRange rate = setting_range(kSetMaxRate, uint8_t(n));
    if (m.microsteps > 2) {
      const long turn = long(m.full_steps_per_rev) * m.microsteps;
      char text[320];
      std::snprintf(text, sizeof text,
                    "At 1/%d step a motor turn is %ld steps: at the firmware's default top rate ($0, %lu steps/s) a turn "
                    "takes %.1f s. Once the arm is connected, send $0=%lu (the most the firmware takes: a turn in %.1f s); "
                    "the Nano keeps it in its EEPROM.",
                    int(m.microsteps), turn, (unsigned long)rate.fallback, double(turn) / rate.fallback,
                    (unsigned long)rate.max, double(turn) / rate.max);
      out.push_back(text);
    }
  } else if (kind == kDriveUln2003) {
    out.push_back("The ULN2003 boards' + and - to a 5 V supply (each 28BYJ-48 draws about 0.25 A), its GND joined to "
                  "the Nano's GND.");
  } else {
    out.push_back("Each L298N's +12V and GND to the motors' supply (12 V for NEMA17s), that GND joined to the Nano's "
                  "GND; keep the board's 5 V jumper on at 12 V or less.");
  }
  return out;
}

nlohmann::json wiring_json(const Robot& robot) {
  const board::BoardInfo& info = board::kBoardInfo[robot.drive.board];
  nlohmann::json out = {{"board", info.id}, {"board_title", info.title}, {"given", robot.drive.given},
                        {"firmware", firmware_build(robot)}, {"wires", nlohmann::json::array()},
                        {"supply", supply_notes(robot)}, {"io_pins", nlohmann::json::array()}};
  const uint32_t free = io_pins_free(robot);
  out["header_pins"] = nlohmann::json::array();
  for (int i = 0; i < board::kHeaderPins; ++i) {
    out["header_pins"].push_back(board::kHeaderPin[i].pin);
    if (free & (uint32_t(1) << i)) out["io_pins"].push_back({{"pin", i}, {"name", board::kHeaderPin[i].pin}});
  }
  if (!robot.has_motors) {
    out["error"] = "the robot has no motors: nothing to wire";
    return out;
  }
  try {
    for (const Wire& w : wire(robot).wires)
      out["wires"].push_back({{"pin", board::kHeaderPin[w.pin].pin},
                              {"signal", w.signal},
                              {"part", w.part},
                              {"motor", w.motor >= 0 ? nlohmann::json(robot.motor_names[std::size_t(w.motor)]) : nullptr}});
  } catch (const WiringError& e) {
    out["error"] = e.what();
  }
  return out;
}

std::string header_pin_name(int pin) {
  if (pin < 0 || pin >= int(board::kHeaderPins)) return "pin " + std::to_string(pin);
  return board::kHeaderPin[pin].pin;
}

}  // namespace articula::host
