// host/physics/cell_sim.cpp - see cell_sim.h.
#include "cell_sim.h"

#include <algorithm>
#include <optional>

#include "firmware_session.h"
#include "robot_view.h"
#include "wiring.h"

namespace articula::host {

namespace {

// The entry of the robot's io on header pin `pin` (-1: it names none there).
int io_on_pin(const Robot& robot, int pin) {
  for (size_t k = 0; k < robot.io.size(); ++k)
    if (robot.io[k].pin == pin) return int(k);
  return -1;
}

std::vector<ArmPlacement> placements(const Cell& cell) {
  std::vector<ArmPlacement> out;
  for (const CellArm& a : cell.arms) out.push_back({a.robot, a.name, a.T_world_base()});
  return out;
}

}  // namespace

CellSimulation::CellSimulation(const Cell& cell, const SimOptions& options)
    : cell_(cell),
      world_(placements(cell), cell.scene, options),
      device_level_(cell.devices.size(), 1),
      sensed_by_(cell.devices.size()),
      feeds_(cell.devices.size()) {
  wire();
  for (size_t k = 0; k < cell_.devices.size(); ++k)
    for (int o : cell_.devices[k].magazine) world_.stow_object(o);
  for (const CellWire& w : cell_.wires)
    if (w.to_device >= 0) feeds_[size_t(w.to_device)].wired = true;
  look_at_sensors(false);
  run_belts(false);
  for (size_t i = 0; i < cell_.arms.size(); ++i)
    if (!cell_.arms[i].program.statements.empty()) world_.driver(int(i)).feed_program(cell_.arms[i].program, 0);
}

// The level a wire carries at `tick`: its output's then, from that arm's log; an arm without
// firmware never drives its pin (its pull-up: high). A barrier's: its beam as the world was at
// its last step.
bool CellSimulation::wire_level(const CellWire& w, uint64_t tick) {
  if (w.from_device >= 0) return device_level_[size_t(w.from_device)] != 0;
  FirmwareSession* from = world_.driver(w.from_arm).firmware();
  return !from || from->output_level(cell_.arms[size_t(w.from_arm)].robot.io[size_t(w.from_pin)].pin, tick);
}

uint32_t CellSimulation::driven_inputs(int arm) const {
  uint32_t pins = 0;
  for (const CellWire& w : cell_.wires)
    if (w.to_arm == arm) pins |= uint32_t(1) << cell_.arms[size_t(arm)].robot.io[size_t(w.to_pin)].pin;
  return pins;
}

// Every arm that drives one of them is run up to `tick` (if it is not there yet: an arm in the
// middle of its own run, the one whose read led here, is past it), and the level is its
// output's then.
uint32_t CellSimulation::input_levels(int arm, uint64_t tick) {
  uint32_t levels = 0;
  for (const CellWire& w : cell_.wires) {
    if (w.to_arm != arm) continue;
    FirmwareSession* from = w.from_device >= 0 ? nullptr : world_.driver(w.from_arm).firmware();
    if (from && from->clock() < tick) from->run_to(tick);
    if (wire_level(w, tick)) levels |= uint32_t(1) << cell_.arms[size_t(arm)].robot.io[size_t(w.to_pin)].pin;
  }
  return levels;
}

// Each arm's inputs on a wire read input_levels at the tick its firmware reads them.
void CellSimulation::wire() {
  for (int i = 0; i < num_arms(); ++i) {
    FirmwareSession* fw = world_.driver(i).firmware();
    const uint32_t pins = driven_inputs(i);
    if (fw && pins)  // (a robot without motors has no firmware to read them)
      fw->drive_inputs(pins, [this, i](uint64_t tick) { return input_levels(i, tick); });
  }
}

void CellSimulation::device_event(int k, const std::string& by, const std::string& detail) {
  SimEvent e;
  e.kind = SimEvent::Kind::kDevice;
  e.t = time();
  e.a = cell_.devices[size_t(k)].name;
  e.b = by;
  e.detail = detail;
  world_.add_event(e);
}

// A belt with a wire to its input runs while the wire is low (a relay module's active-low
// input: an output at rest, high, leaves it standing); one without a wire runs.
void CellSimulation::run_belts(bool tell) {
  const uint64_t now = world_.now_tick();
  for (const CellWire& w : cell_.wires) {
    if (w.to_device < 0) continue;
    const size_t k = size_t(w.to_device);
    const CellDevice& d = cell_.devices[k];
    if (d.kind != CellDevice::Kind::kBelt) continue;
    const bool level = wire_level(w, now);
    if (level == (device_level_[k] != 0) && tell) continue;
    device_level_[k] = level;
    world_.set_belt(d.object, level ? 0 : world_.object(d.object).belt);
    if (tell) device_event(int(k), "", level ? "stands" : "runs");
  }
}

bool CellSimulation::belt_running(int k) const {
  for (const CellWire& w : cell_.wires)
    if (w.to_device == k) return !device_level(k);
  return true;
}

int CellSimulation::feeder_left(int k) const {
  return int(cell_.devices[size_t(k)].magazine.size() - feeds_[size_t(k)].next);
}

// A feeder puts out its next object at each fall of its input (high to low; with no wire, every
// every_s from t = 0), as soon as its outlet is clear.
void CellSimulation::run_feeders() {
  const uint64_t now = world_.now_tick();
  for (size_t k = 0; k < cell_.devices.size(); ++k) {
    const CellDevice& d = cell_.devices[k];
    if (d.kind != CellDevice::Kind::kFeeder) continue;
    Feed& f = feeds_[k];
    if (f.wired) {
      for (const CellWire& w : cell_.wires) {
        if (w.to_device != int(k)) continue;
        const bool level = wire_level(w, now);
        if (!level && device_level_[k]) ++f.owed;  // (a fall)
        device_level_[k] = level;
      }
    } else if (time() >= f.next_t - 1e-12) {
      ++f.owed;
      f.next_t += d.every_s;
    }
    if (f.owed == 0) continue;
    if (f.next >= d.magazine.size()) {
      f.owed = 0;
      if (!f.empty_told) device_event(int(k), "", "is empty");
      f.empty_told = true;
      continue;
    }
    const int obj = d.magazine[f.next];
    if (!world_.put_out(obj, d.at)) {
      if (!f.waiting_told) device_event(int(k), "", "waits: its outlet is taken");
      f.waiting_told = true;
      continue;
    }
    ++f.next;
    --f.owed;
    f.waiting_told = false;
    device_event(int(k), world_.object(obj).name, "puts one out");
  }
}

void CellSimulation::look_at_sensors(bool tell) {
  for (size_t k = 0; k < cell_.devices.size(); ++k) {
    const CellDevice& d = cell_.devices[k];
    if (d.kind != CellDevice::Kind::kBarrier && d.kind != CellDevice::Kind::kSwitch) continue;
    const bool beam = d.kind == CellDevice::Kind::kBarrier;
    const std::string by = beam ? world_.beam_blocker(d.from, d.to) : world_.box_presser(d.at, d.size);
    if (by == sensed_by_[k]) continue;
    const bool was_clear = sensed_by_[k].empty();
    sensed_by_[k] = by;
    device_level_[k] = by.empty();
    if (tell && (was_clear || by.empty()))  // (broken, or clear again: not one object for another)
      device_event(int(k), by, beam ? (by.empty() ? "the beam is clear" : "the beam is broken") : (by.empty() ? "is let go" : "is pressed"));
  }
}

void CellSimulation::step() {
  if (!cell_.devices.empty()) {
    run_belts(true);
    run_feeders();
  }
  world_.step();
  if (!cell_.devices.empty()) look_at_sensors(true);
  if (cell_.wires.empty()) return;
  const std::string now = stuck();
  if (!now.empty() && !stuck_) {
    deadlock_ = now;
    SimEvent e;
    e.kind = SimEvent::Kind::kDeadlock;
    e.t = time();
    e.detail = now;
    world_.add_event(e);
  }
  stuck_ = !now.empty();
}

void CellSimulation::run_until(double t) {
  while (time() < t - 1e-12) step();
}

// A deadlock: no arm moves or will send another line, and each one still busy waits for a
// level its input does not have now and that no arm will change before a wait runs out.
std::string CellSimulation::stuck() {
  struct Waiting {
    int pin, level;
    int from_arm = -1, from_io = -1;  // the wire's other end (-1: none)
    int io = -1;                      // its own pin's entry in its robot's io (-1: not named)
  };
  std::vector<std::optional<Waiting>> waits(static_cast<size_t>(num_arms()));
  bool any = false;
  const uint64_t now = world_.now_tick();
  for (int i = 0; i < num_arms(); ++i) {
    ArmDriver& d = world_.driver(i);
    if (!d.busy()) continue;
    FirmwareSession* fw = d.firmware();
    if (!fw) return "";
    const std::optional<FirmwareSession::InputWait> w = fw->waiting();
    if (!w) return "";
    Waiting x{w->pin, w->level};
    x.io = io_on_pin(cell_.arms[size_t(i)].robot, w->pin);
    bool high = true;  // (an input no wire drives reads its pull-up)
    for (const CellWire& c : cell_.wires)
      if (c.to_arm == i && c.to_pin == x.io) {
        if (c.from_device >= 0) return "";  // (the world may break or clear the beam yet)
        x.from_arm = c.from_arm;
        x.from_io = c.from_pin;
        high = wire_level(c, now);
      }
    if (high == (w->level != 0)) return "";  // (its next look ends it)
    waits[size_t(i)] = x;
    any = true;
  }
  if (!any) return "";
  std::string words;
  std::vector<bool> told(waits.size(), false);
  for (size_t i = 0; i < waits.size(); ++i) {
    if (!waits[i] || told[i]) continue;
    std::string chain;
    for (size_t a = i; !told[a];) {
      told[a] = true;
      const Waiting& w = *waits[a];
      const std::string level = w.level ? "high" : "low";
      chain += (chain.empty() ? cell_.arms[a].name + " waits for " : ", which waits for ");
      if (w.from_arm < 0) {
        const std::string pin = header_pin_name(w.pin);
        chain += (w.io >= 0 ? "its input `" + cell_.io_name(int(a), w.io) + "` (" + pin + ")" : "pin " + pin) +
                 " to go " + level + ", which no wire drives";
        break;
      }
      chain += "`" + cell_.io_name(w.from_arm, w.from_io) + "` from " + cell_.arms[size_t(w.from_arm)].name + " (" +
               level + ")";
      if (!waits[size_t(w.from_arm)]) {
        chain += cell_.arms[size_t(w.from_arm)].program.statements.empty() ? ", which runs no program"
                                                                           : ", which has ended its program";
        break;
      }
      a = size_t(w.from_arm);
    }
    words += (words.empty() ? "" : "; ") + chain;
  }
  return words;
}

double CellSimulation::program_end() const {
  double end = 0;
  for (int i = 0; i < world_.num_arms(); ++i) end = std::max(end, world_.driver(i).program_end());
  return end;
}

namespace {

// An arm's outputs set and inputs waited for, so far: kind ("output", "wait"), line, pin ("A0"),
// name (as the arm's io names it; "" for a pin it does not name), level, t and, for a wait,
// end_t and met (null while it waits; met: it read its level, false: it ran out).
nlohmann::json signals_json(const CellSimulation& sim, int arm) {
  nlohmann::json out = nlohmann::json::array();
  const Robot& robot = sim.cell().arms[size_t(arm)].robot;
  for (const ArmDriver::Signal& x : sim.driver(arm).signals()) {
    const int io = io_on_pin(robot, x.pin);
    const std::string name = io >= 0 ? robot.io[size_t(io)].name : "";
    const bool wait = x.kind == ArmDriver::Signal::kWait;
    nlohmann::json j = {{"kind", wait ? "wait" : "output"}, {"line", x.line},     {"pin", header_pin_name(x.pin)},
                        {"name", name},                     {"level", x.level}, {"t", double(x.tick) / kStepTickHz}};
    if (wait) {
      j["end_t"] = x.ended ? nlohmann::json(double(x.end_tick) / kStepTickHz) : nlohmann::json(nullptr);
      j["met"] = x.ended ? nlohmann::json(x.met) : nlohmann::json(nullptr);
    }
    out.push_back(j);
  }
  return out;
}

// The arm's I/O pins as its robot file (or the cell for it) names them, each with its header
// pin's number (as O and W write it) and, for an input on a wire, what drives it ("arm.pin" or
// "device.pin"; null: nothing) and whether that is a device (its level comes from the world).
nlohmann::json io_json(const Cell& cell, int arm) {
  nlohmann::json out = nlohmann::json::array();
  const Robot& robot = cell.arms[size_t(arm)].robot;
  for (size_t k = 0; k < robot.io.size(); ++k) {
    const IoPin& p = robot.io[k];
    nlohmann::json j = {{"name", p.name}, {"pin", header_pin_name(p.pin)}, {"number", p.pin}, {"mode", io_mode_id(p.mode)},
                        {"driven_by", nullptr}, {"by_device", false}};
    for (const CellWire& w : cell.wires) {
      if (w.to_arm != arm || w.to_pin != int(k)) continue;
      if (w.from_device >= 0) {
        const CellDevice& d = cell.devices[size_t(w.from_device)];
        j["driven_by"] = d.name + "." + d.pin();
        j["by_device"] = true;
      } else {
        j["driven_by"] = cell.arms[size_t(w.from_arm)].name + "." + cell.io_name(w.from_arm, w.from_pin);
      }
    }
    out.push_back(j);
  }
  return out;
}

}  // namespace

Prediction predict_in_cell(const Cell& cell, const std::string& name, bool path) {
  const int i = cell_arm_index(cell, name);
  const CellArm& arm = cell.arms[size_t(i)];
  if (!arm.robot.has_motors)
    throw PredictError("arm " + name + " (" + arm.robot.name + ") has no motors: there are no steps to predict");
  // The other arms run in the cell's simulation, whose world never steps: only their firmwares,
  // each run as far as a read of this arm's inputs (or of theirs) needs. This arm runs there
  // too, as the others' inputs read it, on the same firmware, program and inputs as here.
  SimOptions options;
  CellSimulation sim(cell, options);
  DrivenInputs inputs{sim.driven_inputs(i), [&sim, i](uint64_t tick) { return sim.input_levels(i, tick); }};
  return predict_program(arm.robot, arm.program, options.settings, SenderModel{}, path, inputs);
}

nlohmann::json cell_arms_json(const CellSimulation& sim) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < sim.num_arms(); ++i) {
    const ArmBody& b = sim.arm(i);
    const CellArm& a = sim.cell().arms[size_t(i)];
    const Robot& r = b.robot();
    std::vector<double> q;
    for (int j = 0; j < r.model.num_joints; ++j) q.push_back(joint_from_model(r, j, b.joints()[size_t(j)]));
    const Transform<double> T = a.T_world_base() * b.frames().T_base_tool;
    out.push_back({{"name", b.name()},
                   {"robot", r.name},
                   {"robot_ref", a.robot_ref},
                   {"base", {{"xyz", {a.xyz.x, a.xyz.y, a.xyz.z}}, {"yaw", a.yaw_deg}, {"footprint_mm", a.footprint_mm}}},
                   {"io", io_json(sim.cell(), i)},
                   {"program", a.program_ref},
                   {"program_end_s", sim.driver(i).program_end()},
                   {"line", b.current_line()},
                   {"joints", q},
                   {"tool_mm", {T.p.x, T.p.y, T.p.z}},
                   {"gripper_mm", b.gripper_opening_mm()},
                   {"counted_steps", b.counted_steps()},
                   {"lost_steps", b.lost_steps()},
                   {"signals", signals_json(sim, i)}});
  }
  return out;
}

nlohmann::json cell_state_json(const CellSimulation& sim) {
  const World& w = sim.world();
  nlohmann::json objects = nlohmann::json::array();
  for (int i = 0; i < w.num_objects(); ++i) {
    const Transform<double> T = w.object_pose(i);
    const int carrier = w.object_carrier(i);
    objects.push_back({{"name", w.object(i).name},
                       {"xyz_mm", {T.p.x, T.p.y, T.p.z}},
                       {"pose", transform_json(T)},
                       {"carried_by", carrier >= 0 ? nlohmann::json(w.body(carrier).name()) : nlohmann::json(nullptr)},
                       {"removed", w.object_removed(i)}});
  }
  nlohmann::json devices = nlohmann::json::array();
  for (size_t k = 0; k < sim.cell().devices.size(); ++k) {
    const CellDevice& d = sim.cell().devices[k];
    nlohmann::json j = {{"name", d.name}, {"kind", d.kind_name()}, {"pin", d.pin()}, {"level", sim.device_level(int(k))}};
    if (d.kind == CellDevice::Kind::kBelt) {
      j["object"] = w.object(d.object).name;
      j["running"] = sim.belt_running(int(k));
    } else if (d.kind == CellDevice::Kind::kFeeder) {
      nlohmann::json names = nlohmann::json::array();
      for (int o : d.magazine) names.push_back(w.object(o).name);
      j["objects"] = names;
      j["at_mm"] = {d.at.x, d.at.y, d.at.z};
      j["every_s"] = d.every_s;
      j["left"] = sim.feeder_left(int(k));
    } else if (d.kind == CellDevice::Kind::kSwitch) {
      j["at_mm"] = {d.at.x, d.at.y, d.at.z};
      j["size_mm"] = {d.size.x, d.size.y, d.size.z};
      const std::string& by = sim.sensed_by(int(k));
      j["pressed_by"] = by.empty() ? nlohmann::json(nullptr) : nlohmann::json(by);
    } else {
      j["from_mm"] = {d.from.x, d.from.y, d.from.z};
      j["to_mm"] = {d.to.x, d.to.y, d.to.z};
      const std::string& by = sim.sensed_by(int(k));
      j["broken_by"] = by.empty() ? nlohmann::json(nullptr) : nlohmann::json(by);
    }
    devices.push_back(j);
  }
  return {{"t", sim.time()}, {"arms", cell_arms_json(sim)}, {"objects", objects}, {"devices", devices}};
}

}  // namespace articula::host
