// host/lib/wiring.cpp - an arm's wires from board.h's pin table (wiring.h).
#include "wiring.h"

#include <nlohmann/json.hpp>

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

nlohmann::json wiring_json(const Robot& robot) {
  const board::BoardInfo& info = board::kBoardInfo[robot.drive.board];
  nlohmann::json out = {{"board", info.id}, {"board_title", info.title}, {"given", robot.drive.given},
                        {"firmware", firmware_build(robot)}, {"wires", nlohmann::json::array()}};
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
