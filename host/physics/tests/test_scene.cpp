// Tests host/physics/scene.h: the scene loader (scenes/README.md) and its schema.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "scene.h"

using namespace articula;
using namespace articula::host;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "s.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, ShippedScenesLoad) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(ARTICULA_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "scene.schema.json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene s = load_scene_file(entry.path().string());
    EXPECT_FALSE(s.name.empty());
    EXPECT_FALSE(s.objects.empty());
    ++n;
  }
  EXPECT_GE(n, 2);
}

TEST(Scene, ReadsEveryField) {
  const Scene s = parse_scene(R"({"gravity": [0, 0, -1.62], "ground": {"friction": 0.3},
      "world_box": {"min": [-1, -2, -3], "max": [4, 5, 6]},
      "objects": [{"name": "c", "type": "cylinder", "size": [3, 50], "xyz": [1, 2, 3], "rpy": [0, 90, 0],
                   "movable": true, "density": 1000, "friction": 0.4},
                  {"type": "sphere", "size": [2], "xyz": [-1, -2, -3]}]})",
                              "s.json");
  EXPECT_DOUBLE_EQ(s.gravity.z, -1.62);
  EXPECT_TRUE(s.ground);
  EXPECT_DOUBLE_EQ(s.ground_friction, 0.3);
  EXPECT_DOUBLE_EQ(s.world_max.y, 5);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].type, SceneObject::Type::kCylinder);
  EXPECT_NEAR(s.objects[0].mass_kg(), 1000 * M_PI * 0.003 * 0.003 * 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(s.objects[0].rpy_deg.y, 90);
  EXPECT_FALSE(s.objects[1].movable);
  EXPECT_EQ(s.objects[1].name, "object 1");
  EXPECT_FALSE(parse_scene(R"({"ground": false})", "s.json").ground);
  EXPECT_EQ(parse_scene(R"({"sized_for": ["mearm", "mk2plus"]})", "s.json").sized_for,
            (std::vector<std::string>{"mearm", "mk2plus"}));
}

// Every shipped scene names the shipped robots it is placed for (the studio's menu offers it
// to them first), and each one is a shipped robot.
TEST(Scene, ShippedScenesSayWhichArmsTheyArePlacedFor) {
  for (const auto& entry : std::filesystem::directory_iterator(std::string(ARTICULA_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "scene.schema.json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene s = load_scene_file(entry.path().string());
    EXPECT_FALSE(s.sized_for.empty());
    for (const std::string& r : s.sized_for)
      EXPECT_TRUE(std::filesystem::exists(std::string(ARTICULA_SOURCE_DIR) + "/robots/" + r + ".json")) << r;
  }
}

TEST(Scene, ErrorsNameTheJsonPointer) {
  EXPECT_EQ(error_of(R"({"objects": [{"type": "box", "size": [10, 0, 10]}]})"),
            "s.json: /objects/0/size/1: must be > 0 (got 0)");
  EXPECT_EQ(error_of(R"({"objcts": []})").substr(0, 25), "s.json: /objcts: unknown ");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "box", "size": [1, 1, 1]}, {"type": "cone", "size": [1]}]})"),
            "s.json: /objects/1/type: unknown type \"cone\" (box, cylinder or sphere)");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "sphere", "size": [1, 2]}]})"),
            "s.json: /objects/0/size: a sphere takes 1 size number [radius]");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "sphere", "size": [1], "mass": 1}]})"),
            "s.json: /objects/0/mass: a static object has no mass (set \"movable\": true)");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "sphere", "size": [1], "movable": true, "mass": 1, "density": 2}]})"),
            "s.json: /objects/0/density: give mass or density, not both");
  EXPECT_EQ(error_of(R"({"objects": [{"name": "a", "type": "sphere", "size": [1]}, {"name": "a", "type": "sphere", "size": [1]}]})"),
            "s.json: /objects/1/name: duplicate name \"a\"");
  EXPECT_EQ(error_of(R"({"ground": {"friction": -1}})"), "s.json: /ground/friction: must be >= 0 (got -1)");
  EXPECT_EQ(error_of(R"({"sized_for": "mearm"})"), "s.json: /sized_for: must be an array of robot names");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "box", "size": [1, 1, 1], "xyz": [9000, 0, 0]}]})"),
            "s.json: /objects/0/xyz: outside the world box");
  EXPECT_EQ(error_of("{\n  \"ground\": tru\n}"), "s.json: not valid JSON at line 2, column 16");
  std::string many = R"({"objects": [)";
  for (int i = 0; i < 501; ++i) many += std::string(i ? "," : "") + R"({"name": "c)" + std::to_string(i) + R"(", "type": "sphere", "size": [1]})";
  EXPECT_EQ(error_of(many + "]}"), "s.json: /objects: a scene holds at most 500 objects (got 501)");
  // a belt: a static box, at most 1000 mm/s either way, a finite number
  EXPECT_EQ(error_of(R"({"objects": [{"type": "box", "size": [30, 30, 30], "movable": true, "belt": 50}]})"),
            "s.json: /objects/0/belt: a belt is a static box (its top face moves)");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "sphere", "size": [1], "belt": 50}]})"),
            "s.json: /objects/0/belt: a belt is a static box (its top face moves)");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "box", "size": [1, 1, 1], "belt": -2000}]})"),
            "s.json: /objects/0/belt: a belt runs at most 1000 mm/s either way (got -2000)");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "box", "size": [1, 1, 1], "belt": "fast"}]})"),
            "s.json: /objects/0/belt: must be a number");
  EXPECT_THROW(load_scene_file("/nonexistent/scene.json"), SceneError);
}

// Every object kind of the schema allows exactly the fields the loader reads.
TEST(Scene, SchemaMatchesTheLoader) {
  std::ifstream f(std::string(ARTICULA_SOURCE_DIR) + "/scenes/scene.schema.json");
  const nlohmann::json schema = nlohmann::json::parse(f);
  for (const auto& [kind, fields] : scene_file_fields()) {
    SCOPED_TRACE(kind);
    const nlohmann::json& def = kind == "scene" ? schema : schema["$defs"][kind];
    ASSERT_TRUE(def.contains("properties"));
    std::set<std::string> in_schema, in_loader(fields.begin(), fields.end());
    for (const auto& p : def["properties"].items()) in_schema.insert(p.key());
    EXPECT_EQ(in_schema, in_loader);
    EXPECT_EQ(def["additionalProperties"], false);
  }
}

}  // namespace

// Objects inside one another at the start (a movable one among them), or a movable one sunk into
// the ground, are refused by name and place: ODE would throw them apart at the first step.
TEST(Scene, ObjectsInsideOneAnotherAtTheStartAreRefused) {
  auto error = [](const std::string& text) {
    try {
      parse_scene(text, "s.json");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(R"({"objects": [{"name": "a", "type": "box", "size": [40, 40, 40], "xyz": [0, 0, 20], "movable": true},
                                 {"name": "b", "type": "box", "size": [40, 40, 40], "xyz": [30, 0, 20], "movable": true}]})"),
            "s.json: /objects/1: \"b\" stands 10.0 mm inside \"a\" (/objects/0) at the start: move one of them");
  EXPECT_EQ(error(R"({"objects": [{"name": "a", "type": "sphere", "size": [10], "xyz": [0, 0, 4], "movable": true}]})"),
            "s.json: /objects/0: \"a\" is sunk 6.0 mm into the ground at the start: raise it (its lowest point at z = 0 or above)");
  // touching is fine (a block on another, on the ground); static ones may meet (a bin's walls)
  EXPECT_EQ(error(R"({"objects": [{"name": "a", "type": "box", "size": [40, 40, 40], "xyz": [0, 0, 20], "movable": true},
                                 {"name": "b", "type": "box", "size": [40, 40, 40], "xyz": [0, 0, 60], "movable": true},
                                 {"name": "w1", "type": "box", "size": [100, 8, 50], "xyz": [200, 0, 25]},
                                 {"name": "w2", "type": "box", "size": [8, 100, 50], "xyz": [200, 0, 25]}]})"),
            "");
  EXPECT_EQ(error(R"({"ground": false, "objects": [{"name": "a", "type": "sphere", "size": [10], "xyz": [0, 0, -40], "movable": true}]})"), "");
}
