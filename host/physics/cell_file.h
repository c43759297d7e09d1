// host/physics/cell_file.h - a cell: several arms on one table, each with its robot file, where
// its base stands, its program, and the wires between their I/O pins, in one world of objects
// (format: cells/README.md, schema cells/cell.schema.json). One loader, for the CLI, Python and
// the web engine alike; a file it cannot use is refused by name and JSON path.
#ifndef ARTICULA_PHYSICS_CELL_FILE_H
#define ARTICULA_PHYSICS_CELL_FILE_H

#include <articula/transform.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "program.h"
#include "robot.h"
#include "scene.h"

namespace articula::host {

constexpr int kMaxCellArms = 8;

struct CellArm {
  std::string name;          // "left": how events, wires and programs name it
  std::string robot_ref;     // the robot as the file names it ("mk2plus", "robots/x.json")
  Robot robot;
  Vec3<double> xyz{0, 0, 0};  // where its base frame stands on the table, mm
  double yaw_deg = 0;         // and which way it faces (about the table's z)
  double footprint_mm = 0;    // the radius around its base frame its base part covers (base_footprint_mm)
  std::string program_ref;    // "" none, a file (as resolved), or the cell's JSON path of inline lines
  Program program;            // what it runs (empty: nothing)
  Transform<double> T_world_base() const;
};

// A device on the table that the cell's wires reach, with one pin each (cells/README.md):
//   - a belt ("run", an input): one of the scene's belts (SceneObject::belt), which runs at its
//     speed while its input is low and stands while it is high, as through a relay module's
//     active-low input (an output at rest, high, leaves it standing); with no wire to it, it runs;
//   - a light barrier ("beam", an output): an infrared beam between two points, its output high
//     while the beam is clear and low while one of the scene's objects breaks it, as a break-beam
//     module's on a pull-up input. The cell looks once a world step;
//   - a switch ("pressed", an output): a touch or limit switch's actuator, a box on the table;
//     its output low while a movable object or an arm's part is inside it (a switch closing to ground
//     on a pull-up input), high otherwise. Looked at once a world step, as a barrier;
//   - a feeder ("feed", an input): a magazine of the scene's movable objects, out of the world
//     until it puts them out, one at a time, at its outlet: at each fall of its input (high to
//     low), or with no wire to it every `every_s` seconds from t = 0; while something stands at
//     the outlet it waits.
struct CellDevice {
  enum class Kind { kBelt, kBarrier, kFeeder, kSwitch };
  std::string name;
  Kind kind = Kind::kBelt;
  int object = -1;                      // a belt: the scene object it runs
  Vec3<double> from{0, 0, 0}, to{0, 0, 0};  // a barrier: its beam's ends, mm, on the table
  std::vector<int> magazine;            // a feeder: its objects, in the order it puts them out
  Vec3<double> at{0, 0, 0};             // and where (each one's centre, mm); a switch: its box's centre
  Vec3<double> size{0, 0, 0};           // a switch: its box, mm
  double every_s = 5;                   // and how often with no wire to its input
  const char* pin() const {
    return kind == Kind::kBelt ? "run" : kind == Kind::kBarrier ? "beam" : kind == Kind::kSwitch ? "pressed" : "feed";
  }
  bool output() const { return kind == Kind::kBarrier || kind == Kind::kSwitch; }
  const char* kind_name() const {
    return kind == Kind::kBelt ? "belt" : kind == Kind::kBarrier ? "barrier" : kind == Kind::kSwitch ? "switch" : "feeder";
  }
};

// One wire as the cell carries it: an output (of an arm or a device) to an input of an arm or a
// device. The file's wires join pins into nets of one output each; the cell has a wire from
// that output to every input on its net.
struct CellWire {
  int from_arm = -1, from_pin = -1;  // the output (index into the arm's robot.io); -1: a device's
  int to_arm = -1, to_pin = -1;      // the input; -1: a device's
  int from_device = -1, to_device = -1;  // the device whose pin it is (-1: an arm's)
};

struct Cell {
  std::string name, description;
  std::string source;  // the file it was read from
  Scene scene;         // the table: ground and objects (its own or a scene file's)
  std::vector<CellArm> arms;
  std::vector<CellDevice> devices;
  std::vector<CellWire> wires;
  int arm_index(const std::string& name) const;
  int device_index(const std::string& name) const;
  // An arm's I/O pin's name (robot.io).
  const std::string& io_name(int arm, int pin) const { return arms[size_t(arm)].robot.io[size_t(pin)].name; }
};

// A cell file that cannot be used: "cells/x.json: /arms/1/base: ..." (the file and the JSON path).
class CellError : public std::runtime_error {
 public:
  CellError(const std::string& file, const std::string& json_path, const std::string& problem);
  const std::string& json_path() const { return json_path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string json_path_, problem_;
};

// Reads and checks a cell file; robots, scenes and programs it names by path are read relative
// to its folder, shipped ones by name. Throws CellError.
Cell load_cell_file(const std::string& path);
// The same from text; `name` stands for the file, `dir` for its folder.
Cell parse_cell(const std::string& json_text, const std::string& name, const std::string& dir);
// A cell given by name ("handover") is looked up in $ARTICULA_CELLS if set (and not empty),
// otherwise in the shipped cells/ folder; anything with a '/' or a '.' is a path.
std::string resolve_cell_path(const std::string& name_or_path);
// Whether a command line's argument names a cell rather than a robot: a shipped cell's name
// that is no shipped robot's, or a JSON file whose top level has "arms".
bool is_cell_reference(const std::string& name_or_path);
// The fields the loader accepts per object kind (keys of cells/cell.schema.json's $defs; "cell"
// is the top level): the schema test keeps the two together.
const std::map<std::string, std::vector<std::string>>& cell_file_fields();

// The radius (mm) around the base frame's origin, on the table, that the robot's base part
// (its frame-0 shapes, geometry.h) covers: two arms closer than the sum of theirs collide
// where they stand.
double base_footprint_mm(const Robot& robot);

// The index of the cell's arm called `arm`; std::invalid_argument naming the arms it has if
// there is none.
int cell_arm_index(const Cell& cell, const std::string& arm);
// The cell's arms' names, "a, b", for messages.
std::string cell_arm_names(const Cell& cell);
// A program for one of the cell's arms, from a file or text: the arm must exist (as
// cell_arm_index).
void set_cell_program(Cell& cell, const std::string& arm, const Program& program);

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_CELL_FILE_H
