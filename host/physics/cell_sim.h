// host/physics/cell_sim.h - a cell (cell_file.h) in one world (world.h): every arm on its own
// firmware (a virtual Nano each) or kinematic model, where the cell file puts it, running its
// program from t = 0, all of them and the objects on one clock.
//
// The cell's wires carry each output's level to the inputs on its net at the tick it changes.
// An arm's firmware reads its inputs only at its own ticks (a W's first look and then once a
// millisecond, a status report): at each read the arms that drive it are first run up to that
// tick (never past it), so every read sees every change made before it, whichever arm the
// world steps first. Each arm's program goes line by line as the arm comes to rest, never
// ahead of the clock, since a W's end depends on the other arms.
#ifndef ARTICULA_PHYSICS_CELL_SIM_H
#define ARTICULA_PHYSICS_CELL_SIM_H

#include <nlohmann/json.hpp>

#include "arm_body.h"
#include "arm_driver.h"
#include "cell_file.h"
#include "world.h"

namespace articula::host {

class CellSimulation {
 public:
  // The cell's arms (named as in the file) and objects; each arm's program loaded at t = 0.
  // Throws std::invalid_argument for what cannot be simulated (world.h).
  CellSimulation(const Cell& cell, const SimOptions& options = {});

  const Cell& cell() const { return cell_; }
  World& world() { return world_; }
  const World& world() const { return world_; }
  int num_arms() const { return world_.num_arms(); }
  const ArmBody& arm(int i) const { return world_.body(i); }
  const ArmDriver& driver(int i) const { return world_.driver(i); }

  void step();
  void run_until(double t);
  double time() const { return world_.time(); }
  // The last arm's program end, and extra_time after it (while an arm's program still runs,
  // where its clock is: each line goes as the arm comes to rest, not ahead).
  double program_end() const;
  double end_time() const { return program_end() + world_.options().extra_time; }
  bool done() const { return time() >= end_time() - 1e-12 && !world_.busy(); }
  // The last deadlock, told in words: every arm still busy waits (W) for an input that no arm
  // will change, until a wait runs out (W:21; then that arm's program goes on): "a waits for
  // `ready` from b (low), which waits for `done` from a (low)"; "" if there was none. Each one
  // is also a kDeadlock event when it begins.
  const std::string& deadlock() const { return deadlock_; }

  // Arm `arm`'s inputs that wires drive (a bit per header pin), and their levels at its tick
  // `tick`: each driving arm's firmware is first run up to that tick (predict_in_cell's, and
  // each firmware's own reads).
  uint32_t driven_inputs(int arm) const;
  uint32_t input_levels(int arm, uint64_t tick);

  // Device k's pin's level now (cell_file.h: a belt's input, a barrier's or a switch's output),
  // and what a sensor senses: what breaks a barrier's beam or presses a switch ("" none).
  bool device_level(int k) const { return device_level_[size_t(k)] != 0; }
  bool belt_running(int k) const;
  const std::string& sensed_by(int k) const { return sensed_by_[size_t(k)]; }
  // How many objects feeder k still holds.
  int feeder_left(int k) const;

 private:
  void wire();
  bool wire_level(const CellWire& w, uint64_t tick);
  // The belts' inputs at the world's tick (run or stand); the barriers and switches as the
  // world is: each change an event (kDevice) when `tell`.
  void run_belts(bool tell);
  void run_feeders();
  void look_at_sensors(bool tell);
  void device_event(int k, const std::string& by, const std::string& detail);
  std::string stuck();  // the deadlock now in words, or ""

  Cell cell_;
  World world_;
  std::vector<uint8_t> device_level_;  // each device's pin, as device_level()
  std::vector<std::string> sensed_by_;
  struct Feed {
    size_t next = 0;     // its magazine's next object
    int owed = 0;        // puts-out asked for and not yet made (the outlet was taken)
    double next_t = 0;   // with no wire: the next one's time
    bool wired = false;  // a wire reaches its input
    bool waiting_told = false, empty_told = false;
  };
  std::vector<Feed> feeds_;  // per device (a feeder's)
  std::string deadlock_;
  bool stuck_ = false;  // in a deadlock now
};

// What arm `arm` of the cell will do with its program, step-exact, in the cell: predict.h's
// Prediction (each line sent once the arm is at rest, from t = 0, as in the cell), with its
// inputs driven through the wires by the other arms' firmwares running their programs beside
// it, so each W ends at the tick the other arm's output changed. Throws std::invalid_argument
// for an arm the cell lacks, PredictError for one without motors.
Prediction predict_in_cell(const Cell& cell, const std::string& arm, bool path = false);

// Each arm as it ends (or is now): name, robot, robot_ref (as the cell file names it), base (xyz, yaw, footprint_mm: where it stands),
// io (each pin: name, pin "A0", number 14, mode, driven_by "arm.pin" / "device.pin" or null, by_device),
// program, program_end_s, line, joints (deg or mm),
// tool_mm (in the world), gripper_mm, counted_steps, lost_steps, signals (each output it set and
// input it waited for: kind "output" or "wait", line, pin, name, level, t, and a wait's end_t);
// `articula sim CELL --json`.
nlohmann::json cell_arms_json(const CellSimulation& sim);
// The cell now: t, arms (cell_arms_json), objects (name, xyz_mm, pose: 16 numbers, row-major,
// carried_by: the arm's name or null, removed), devices (name, kind, pin, level: its pin's now;
// a belt's object and running, a barrier's from_mm, to_mm and broken_by: an object's name or
// null, a switch's at_mm, size_mm and pressed_by, a feeder's objects, at_mm, every_s and left); `articula sim CELL --json`, Python's
// Cell.state, the web engine's.
nlohmann::json cell_state_json(const CellSimulation& sim);

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_CELL_SIM_H
