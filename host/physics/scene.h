// host/physics/scene.h - what the arm works in: the ground, static and movable objects, gravity
// (format: scenes/README.md). Lengths mm and angles deg in the file, as everywhere; the
// loader keeps them so, sim.cpp converts to SI at the engine's door.
#ifndef ARTICULA_PHYSICS_SCENE_H
#define ARTICULA_PHYSICS_SCENE_H

#include <articula/transform.h>
#include <nlohmann/json_fwd.hpp>

#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace articula::host {

struct SceneObject {
  enum class Type { kBox, kCylinder, kSphere };
  std::string name;
  Type type = Type::kBox;
  std::array<double, 3> size{};  // box: x y z; cylinder: radius, length (axis along z); sphere: radius (mm)
  Vec3<double> xyz{0, 0, 0};     // centre, mm, world frame (the robot's base frame)
  Vec3<double> rpy_deg{0, 0, 0};  // fixed X-Y-Z, deg
  bool movable = false;
  double mass = 0;     // kg, movable objects; 0 = from density
  double density = 0;  // kg/m^3 when mass is 0
  double friction = 0.8;  // Coulomb coefficient mu
  // A static box as a conveyor belt: its top face moves at this speed (mm/s, negative: the
  // other way) along the box's own x axis, and carries what lies on it. 0: not a belt.
  double belt = 0;

  double volume_m3() const;
  Mat3<double> rotation() const;  // from rpy_deg, the one place it is turned into a matrix
  double mass_kg() const { return mass > 0 ? mass : density * volume_m3(); }
};

// The most objects a scene file may hold.
constexpr size_t kMaxSceneObjects = 500;

struct Scene {
  std::string name;
  std::string description;
  std::string source;  // file it was read from ("" for a scene built in code)
  Vec3<double> gravity{0, 0, -9.81};  // m/s^2
  bool ground = true;                 // the plane z = 0
  double ground_friction = 0.8;
  // Beyond this box (mm) a dynamic body is taken out of the world (an event says so).
  Vec3<double> world_min{-3000, -3000, -1000}, world_max{3000, 3000, 3000};
  std::vector<SceneObject> objects;
  // The shipped robots its objects are placed for (file names without .json: "mearm"); empty:
  // any arm. The studio offers a scene first to the arms it is sized for.
  std::vector<std::string> sized_for;
};

// A scene file that cannot be used: "scenes/x.json: /objects/0/size/1: must be > 0 (got 0)".
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, const std::string& json_path, const std::string& problem);
  const std::string& json_path() const { return json_path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string json_path_, problem_;
};

// Two objects of the scene that stand inside one another at the start (deeper than 0.5 mm; at
// least one of them movable: static ones may meet, as a table's walls do), or a movable one sunk
// into the ground: in words, with the later one's index (-1: none). The objects `left_out` (a
// feeder's magazine) are not in the world yet. parse_scene and load_scene_file refuse such a
// scene; a cell's loader asks once it knows its feeders.
struct SceneOverlap {
  int object = -1;
  std::string problem;
};
SceneOverlap first_overlap(const Scene& scene, const std::vector<int>& left_out = {});

Scene load_scene_file(const std::string& path);
Scene parse_scene(const std::string& json_text, const std::string& name);
// A scene written inside another file (a cell's "scene"): its paths are the object's own.
Scene scene_from_json(const nlohmann::json& j, const std::string& name);
// A scene given by name ("grasp-and-lift") is looked up in $ARTICULA_SCENES if set (and not
// empty), otherwise in the shipped scenes/ folder as it was when the tools were built.
std::string resolve_scene_path(const std::string& name_or_path);
// The fields the loader accepts per object kind (keys of scenes/scene.schema.json's $defs;
// "scene" is the top level): the schema test keeps the two together.
const std::map<std::string, std::vector<std::string>>& scene_file_fields();

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_SCENE_H
