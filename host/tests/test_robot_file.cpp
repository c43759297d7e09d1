// Tests of the robot file loader (host/lib/robot_file.cpp), the shipped robots and the
// JSON schema (robots/robot.schema.json).
#include "mini_schema.h"
#include "robot_file.h"

#include "board.h"
#include "wiring.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

namespace {

using namespace articula;
using namespace articula::host;
using articula::test::MiniSchema;
using json = nlohmann::json;
namespace fs = std::filesystem;

const std::string kSource = ARTICULA_SOURCE_DIR;
const std::string kRobots = kSource + "/robots";
const double kPi = 3.14159265358979323846;

double rad(double deg) { return deg * kPi / 180.0; }

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A small robot shaped like the MK2 (three joints, a linked row, a coupling), valid as it
// is: each error test breaks one thing in it.
json base_robot() {
  return json::parse(R"({
    "name": "test arm",
    "dh": [
      {"a": 0,   "alpha": 0,  "d": 78, "theta": {"joint": "base", "min": -90, "max": 90}},
      {"a": 0,   "alpha": 90, "d": 0,  "theta": {"joint": "shoulder", "min": 36, "max": 130}},
      {"a": 135, "alpha": 0,  "d": 0,  "theta": {"joint": "elbow", "min": -173, "max": -21}},
      {"a": 147, "alpha": 0,  "d": 0,  "theta": {"linked": {"shoulder": -1, "elbow": -1}}}
    ],
    "motors": [
      {"name": "m0", "min": -90, "max": 90},
      {"name": "m1", "zero": 90, "min": 36, "max": 130},
      {"name": "m2", "min": -43, "max": 15}
    ],
    "coupling": [[1, 0, 0], [0, 1, 0], [0, -1, 1]],
    "home": {"base": 0, "shoulder": 90, "elbow": -90}
  })");
}

// A DH row whose theta (and optionally alpha) is a joint variable.
json joint_row(const std::string& theta_name, const std::string& alpha_name = "") {
  json row = {{"a", 10}, {"alpha", 0}, {"d", 0}, {"theta", {{"joint", theta_name}, {"min", -180}, {"max", 180}}}};
  if (!alpha_name.empty()) row["alpha"] = {{"joint", alpha_name}, {"min", -180}, {"max", 180}};
  return row;
}

// parse_robot(text, "bad.json") must throw a RobotFileError naming the file, the path
// and every word of the problem.
::testing::AssertionResult text_fails_with(const std::string& text, const std::string& path,
                                           const std::vector<std::string>& words) {
  try {
    parse_robot(text, "bad.json");
  } catch (const RobotFileError& e) {
    const std::string what = e.what();
    const std::string prefix = path.empty() ? "bad.json: " : "bad.json: " + path + ": ";
    if (e.file() != "bad.json" || e.json_path() != path || what.compare(0, prefix.size(), prefix) != 0 ||
        what != prefix + e.problem())
      return ::testing::AssertionFailure() << "wrong file or path: " << what << " (path " << e.json_path()
                                           << ", wanted " << path << ")";
    for (const std::string& w : words)
      if (e.problem().find(w) == std::string::npos)
        return ::testing::AssertionFailure() << "\"" << w << "\" not in: " << what;
    return ::testing::AssertionSuccess() << what;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "not a RobotFileError: " << e.what();
  }
  return ::testing::AssertionFailure() << "loaded without error";
}

::testing::AssertionResult fails_with(const json& doc, const std::string& path, const std::vector<std::string>& words) {
  return text_fails_with(doc.dump(2), path, words);
}

// ---------------------------------------------------------------- the shipped robots

TEST(ShippedRobots, Mk2PlusModel) {
  const Robot r = load_robot_file(kRobots + "/mk2plus.json");
  EXPECT_EQ(r.name, "MK2 Plus");
  EXPECT_EQ(r.source, kRobots + "/mk2plus.json");
  EXPECT_FALSE(r.description.empty());
  const HostModel& m = r.model;
  ASSERT_EQ(m.num_rows, 4);
  ASSERT_EQ(m.num_joints, 3);
  ASSERT_EQ(m.num_linked, 1);
  EXPECT_EQ(r.joint_names, (std::vector<std::string>{"base", "shoulder", "elbow"}));
  const double a[] = {0, 0, 135, 147}, alpha[] = {0, 90, 0, 0}, d[] = {78, 0, 0, 0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(m.rows[i].a, a[i]) << i;
    EXPECT_DOUBLE_EQ(m.rows[i].alpha, rad(alpha[i])) << i;
    EXPECT_EQ(m.rows[i].d, d[i]) << i;
    EXPECT_EQ(m.rows[i].theta, 0.0) << i;
  }
  const double lo[] = {-90, 36, -173}, hi[] = {90, 130, -21};
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(m.joints[j].row, j);
    EXPECT_EQ(m.joints[j].param, kParamTheta);
    EXPECT_DOUBLE_EQ(m.joints[j].lo, rad(lo[j]));
    EXPECT_DOUBLE_EQ(m.joints[j].hi, rad(hi[j]));
  }
  EXPECT_EQ(m.linked[0].row, 3);
  EXPECT_EQ(m.linked[0].param, kParamTheta);
  EXPECT_EQ(m.linked[0].offset, 0.0);
  EXPECT_EQ(m.linked[0].gain[0], 0.0);
  EXPECT_EQ(m.linked[0].gain[1], -1.0);
  EXPECT_EQ(m.linked[0].gain[2], -1.0);
  EXPECT_EQ(validate(m), kModelOk);
}

TEST(ShippedRobots, Mk2PlusMotorsAndCoupling) {
  const Robot r = load_robot_file(kRobots + "/mk2plus.json");
  ASSERT_TRUE(r.has_motors);
  const HostActuation& a = r.actuation;
  ASSERT_EQ(a.num_motors, 3);
  EXPECT_EQ(r.motor_names, (std::vector<std::string>{"base", "shoulder", "elbow"}));
  const int32_t num[] = {108, 47, 47}, zero[] = {0, 90000, 0}, mn[] = {-90000, 36000, -43000}, mx[] = {90000, 130000, 15000};
  for (int i = 0; i < 3; ++i) {
    const MotorSpec& s = a.motors[i];
    EXPECT_EQ(s.full_steps_per_rev, 200) << i;
    EXPECT_EQ(s.microsteps, 1) << i;
    EXPECT_EQ(s.direction, 1) << i;
    EXPECT_EQ(s.gear_num, num[i]) << i;
    EXPECT_EQ(s.gear_den, 19) << i;
    EXPECT_EQ(s.zero, zero[i]) << i;
    EXPECT_EQ(s.min, mn[i]) << i;
    EXPECT_EQ(s.max, mx[i]) << i;
    EXPECT_EQ(validate(s), kMotorOk) << i;
  }
  EXPECT_NEAR(degrees_per_step<double>(a.motors[0]), 0.3167, 5e-5);
  EXPECT_NEAR(degrees_per_step<double>(a.motors[1]), 0.7277, 5e-5);
  EXPECT_NEAR(degrees_per_step<double>(a.motors[2]), 0.7277, 5e-5);
  EXPECT_DOUBLE_EQ(degrees_per_step<double>(a.motors[0]), 360.0 * 19 / (200 * 108));

  const double C[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, -1, 1}};
  const double Cinv[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 1, 1}};  // forearm elevation = shoulder + elbow
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.coupling[i][k], C[i][k]) << i << k;
      EXPECT_NEAR(a.coupling_inv[i][k], Cinv[i][k], 1e-15) << i << k;
    }
}

TEST(ShippedRobots, Mk2PlusHomePose) {
  const Robot r = load_robot_file(kRobots + "/mk2plus.json");
  ASSERT_EQ(r.home.size(), 3u);
  EXPECT_DOUBLE_EQ(r.home[0], 0.0);
  EXPECT_DOUBLE_EQ(r.home[1], rad(90));
  EXPECT_DOUBLE_EQ(r.home[2], rad(-90));

  HostFrames f;
  forward_kinematics(f, r.model, r.home.data());
  const Vec3<double> elbow = f.T_base_frame[3].p, wrist = f.T_base_frame[4].p, tool = f.T_base_tool.p;
  EXPECT_NEAR(elbow.x, 0, 1e-9);
  EXPECT_NEAR(elbow.z, 78 + 135, 1e-9);
  EXPECT_NEAR(wrist.x, 147, 1e-9);
  EXPECT_NEAR(wrist.y, 0, 1e-9);
  EXPECT_NEAR(wrist.z, 213, 1e-9);
  EXPECT_NEAR(tool.x, 235, 1e-9);
  EXPECT_NEAR(tool.y, 0, 1e-9);
  EXPECT_NEAR(tool.z, 213, 1e-9);
  // Tool frame: x forward, z up (and so y to the left).
  const Mat3<double>& R = f.T_base_tool.R;
  const double want[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(R.m[i][k], want[i][k], 1e-12) << i << k;

  // The motors at home: base 0, upper arm 90 deg up, forearm level.
  double u[kMaxJoints];
  actuators_from_joints(u, r.actuation, r.home.data());
  EXPECT_NEAR(u[0], 0, 1e-12);
  EXPECT_NEAR(u[1], rad(90), 1e-12);
  EXPECT_NEAR(u[2], 0, 1e-12);
}

TEST(ShippedRobots, Mk2PlusStaysLevelAndYaws) {
  const Robot r = load_robot_file(kRobots + "/mk2plus.json");
  const double q[] = {rad(30), rad(60), rad(-100)};
  HostFrames f;
  forward_kinematics(f, r.model, q);
  // The tool's z stays vertical whatever the arm does (the parallelogram).
  EXPECT_NEAR(f.T_base_tool.R.m[2][2], 1.0, 1e-12);
  // Horizontal distance from the yaw axis, closed form.
  const double reach = 135 * std::cos(rad(60)) + 147 * std::cos(rad(-40)) + 88;
  const double height = 78 + 135 * std::sin(rad(60)) + 147 * std::sin(rad(-40));
  EXPECT_NEAR(f.T_base_tool.p.x, reach * std::cos(rad(30)), 1e-9);
  EXPECT_NEAR(f.T_base_tool.p.y, reach * std::sin(rad(30)), 1e-9);
  EXPECT_NEAR(f.T_base_tool.p.z, height, 1e-9);
}

TEST(ShippedRobots, Mk2PlusGeometryAndGripper) {
  const Robot r = load_robot_file(kRobots + "/mk2plus.json");
  ASSERT_EQ(r.links.size(), 4u);
  EXPECT_EQ(r.links[0].frame, 0);
  EXPECT_EQ(r.links[1].frame, 2);
  EXPECT_EQ(r.links[2].frame, 3);
  EXPECT_EQ(r.links[3].frame, 4);
  ASSERT_EQ(r.links[0].shapes.size(), 1u);
  EXPECT_EQ(r.links[0].shapes[0].type, Shape::Type::kCylinder);
  ASSERT_EQ(r.links[1].shapes.size(), 1u);
  const Shape& upper = r.links[1].shapes[0];
  EXPECT_EQ(upper.type, Shape::Type::kBox);
  EXPECT_EQ(upper.size[0], 135);
  EXPECT_EQ(upper.T_frame_shape.p.x, 67.5);
  EXPECT_EQ(upper.mass, 0.0);
  EXPECT_EQ(upper.density, 1240.0);
  ASSERT_TRUE(r.gripper.present);
  EXPECT_EQ(r.gripper.max_opening_mm, 40);
  EXPECT_EQ(r.gripper.finger_length_mm, 40);
  EXPECT_EQ(r.gripper.servo_open_deg, 90);
  EXPECT_EQ(r.gripper.servo_closed_deg, 150);
}

TEST(ShippedRobots, ThesisExample) {
  const Robot r = load_robot_file(kRobots + "/thesis-example.json");
  EXPECT_EQ(r.name, "Thesis example");
  EXPECT_FALSE(r.has_motors);
  EXPECT_EQ(r.actuation.num_motors, 0);
  EXPECT_FALSE(r.gripper.present);
  const HostModel& m = r.model;
  ASSERT_EQ(m.num_rows, 4);
  ASSERT_EQ(m.num_joints, 8);
  EXPECT_EQ(m.num_linked, 0);
  // Numbered by row, and within a row theta before alpha.
  EXPECT_EQ(r.joint_names, (std::vector<std::string>{"theta1", "alpha1", "theta2", "alpha2", "theta3", "alpha3",
                                                     "theta4", "alpha4"}));
  const double a[] = {0, 60, 30, 20}, d[] = {0, 7, -7, 0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(m.rows[i].a, a[i]);
    EXPECT_EQ(m.rows[i].d, d[i]);
    EXPECT_EQ(m.joints[2 * i].row, i);
    EXPECT_EQ(m.joints[2 * i].param, kParamTheta);
    EXPECT_EQ(m.joints[2 * i + 1].row, i);
    EXPECT_EQ(m.joints[2 * i + 1].param, kParamAlpha);
  }
  for (int j = 0; j < 8; ++j) {
    EXPECT_DOUBLE_EQ(m.joints[j].lo, -kPi);
    EXPECT_DOUBLE_EQ(m.joints[j].hi, kPi);
  }
  EXPECT_EQ(r.home, std::vector<double>(8, 0.0));

  Vec3<double> p = tool_position(m, r.home.data());
  EXPECT_NEAR(p.x, 110, 1e-12);
  EXPECT_NEAR(p.y, 0, 1e-12);
  EXPECT_NEAR(p.z, 0, 1e-12);
  // The thesis's Table 2 turns alpha on row 3 to 90 deg: the -7 mm of d3 now points along
  // -y2 rotated, i.e. +7 in y.
  std::vector<double> q(8, 0.0);
  q[5] = rad(90);
  p = tool_position(m, q.data());
  EXPECT_NEAR(p.x, 110, 1e-12);
  EXPECT_NEAR(p.y, 7, 1e-12);
  EXPECT_NEAR(p.z, 7, 1e-12);
}

TEST(ShippedRobots, EveryShippedRobotLoads) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kRobots)) {
    const std::string path = entry.path().string();
    if (entry.path().extension() != ".json" || entry.path().filename() == "robot.schema.json") continue;
    EXPECT_NO_THROW(load_robot_file(path)) << path;
    ++count;
  }
  EXPECT_GE(count, 2);
}

TEST(ShippedRobots, ReadmeExampleLoads) {
  const std::string readme = read_text(kRobots + "/README.md");
  const std::size_t start = readme.find("```json\n{");
  ASSERT_NE(start, std::string::npos);
  const std::size_t end = readme.find("```", start + 7);
  ASSERT_NE(end, std::string::npos);
  const Robot r = parse_robot(readme.substr(start + 7, end - start - 7), "README.md");
  EXPECT_EQ(r.model.num_joints, 2);
  EXPECT_EQ(r.actuation.motors[1].direction, -1);
  EXPECT_EQ(r.actuation.motors[1].min, -135000);  // from the joint: identity coupling
  EXPECT_NEAR(tool_position(r.model, r.home.data()).x, 180, 1e-12);
}

// ---------------------------------------------------------------- the schema


json load_schema() { return json::parse(read_text(kRobots + "/robot.schema.json")); }

std::set<std::string> keys_of(const json& obj) {
  std::set<std::string> out;
  for (const auto& item : obj.items()) out.insert(item.key());
  return out;
}

TEST(Schema, IsDraft2020JsonWithTheLoadersTopLevelFields) {
  json schema;
  ASSERT_NO_THROW(schema = load_schema());
  EXPECT_EQ(schema["$schema"], "https://json-schema.org/draft/2020-12/schema");
  const auto& fields = robot_file_fields().at("robot");
  EXPECT_EQ(keys_of(schema["properties"]), std::set<std::string>(fields.begin(), fields.end()));
  EXPECT_EQ(schema["additionalProperties"], false);
}

TEST(Schema, EveryObjectKindMatchesTheLoader) {
  const json schema = load_schema();
  // Every kind the loader reads has a $defs entry with the same fields, closed to others.
  for (const auto& [kind, fields] : robot_file_fields()) {
    if (kind == "robot") continue;
    ASSERT_TRUE(schema["$defs"].contains(kind)) << kind;
    const json& def = schema["$defs"][kind];
    EXPECT_EQ(keys_of(def["properties"]), std::set<std::string>(fields.begin(), fields.end())) << kind;
    EXPECT_EQ(def["additionalProperties"], false) << kind;
  }
  // And every object kind of the schema is one the loader knows.
  for (const auto& item : schema["$defs"].items()) {
    if (item.value().contains("properties")) {
      EXPECT_TRUE(robot_file_fields().count(item.key())) << item.key();
    }
  }
}

TEST(Schema, EveryShippedRobotValidates) {
  const json schema = load_schema();
  const MiniSchema validator(schema);
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kRobots)) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "robot.schema.json") continue;
    const json doc = json::parse(read_text(entry.path().string()));
    const std::vector<std::string> errors = validator.errors(doc);
    EXPECT_TRUE(errors.empty()) << entry.path() << ": " << (errors.empty() ? "" : errors[0]);
    EXPECT_EQ(doc.value("$schema", ""), "./robot.schema.json") << entry.path();
    ++count;
  }
  EXPECT_GE(count, 2);
}

// The schema and the loader agree: what one rejects the other rejects too, and the
// schema's validator is not vacuous.
TEST(Schema, RejectsWhatTheLoaderRejects) {
  const json schema = load_schema();
  const MiniSchema validator(schema);
  const json mk2 = json::parse(read_text(kRobots + "/mk2plus.json"));
  ASSERT_TRUE(validator.errors(mk2).empty());

  std::vector<std::pair<std::string, std::function<void(json&)>>> breakages = {
      {"unknown top-level field", [](json& j) { j["nmae"] = "x"; }},
      {"no name", [](json& j) { j.erase("name"); }},
      {"unknown row field", [](json& j) { j["dh"][0]["thta"] = 1; }},
      {"row without alpha", [](json& j) { j["dh"][0].erase("alpha"); }},
      {"negative length range", [](json& j) { j["dh"][2]["a"] = {{"value", 135}, {"min", -1}, {"max", 200}}; }},
      {"joint without max", [](json& j) { j["dh"][0]["theta"].erase("max"); }},
      {"parameter as text", [](json& j) { j["dh"][0]["d"] = "78"; }},
      {"linked as a list", [](json& j) { j["dh"][3]["theta"]["linked"] = json::array({-1, -1}); }},
      {"tool with 2 numbers", [](json& j) { j["tool"]["xyz"] = {1, 2}; }},
      {"an I/O pin without a mode", [](json& j) { j["io"] = json::parse(R"([{"name": "ready", "pin": "A5"}])"); }},
      {"an I/O pin of no mode known", [](json& j) { j["io"] = json::parse(R"([{"name": "ready", "pin": "A5", "mode": "pwm"}])"); }},
      {"an I/O pin on no header pin", [](json& j) { j["io"] = json::parse(R"([{"name": "ready", "pin": "D14", "mode": "input"}])"); }},
      {"motor field typo", [](json& j) { j["motors"][0]["gear_ratio"] = 1; }},
      {"motor direction 2", [](json& j) { j["motors"][0]["direction"] = 2; }},
      {"motor gear 0", [](json& j) { j["motors"][0]["gear"] = {0, 19}; }},
      {"microsteps 1.5", [](json& j) { j["motors"][0]["microsteps"] = 1.5; }},
      {"box with 2 sizes", [](json& j) { j["links"][1]["shapes"][0]["size"] = {1, 2}; }},
      {"zero size", [](json& j) { j["links"][1]["shapes"][0]["size"][0] = 0; }},
      {"mass and density", [](json& j) { j["links"][1]["shapes"][0]["mass"] = 1, j["links"][1]["shapes"][0]["density"] = 1; }},
      {"unknown shape type", [](json& j) { j["links"][1]["shapes"][0]["type"] = "cube"; }},
      {"mesh without file", [](json& j) { j["links"][1]["shapes"][0] = {{"type", "mesh"}}; }},
      {"mesh with size", [](json& j) { j["links"][1]["shapes"][0] = {{"type", "mesh"}, {"mesh", "a.stl"}, {"size", {1}}}; }},
      {"box with a mesh file", [](json& j) { j["links"][1]["shapes"][0]["mesh"] = "a.stl"; }},
      {"negative frame", [](json& j) { j["links"][0]["frame"] = -1; }},
      {"link without shapes", [](json& j) { j["links"][0].erase("shapes"); }},
      {"gripper servo 200", [](json& j) { j["gripper"]["servo_closed"] = 200; }},
      {"gripper missing field", [](json& j) { j["gripper"].erase("finger_length"); }},
      {"home as text", [](json& j) { j["home"]["base"] = "0"; }},
      {"coupling entry as text", [](json& j) { j["coupling"][0][0] = "1"; }},
      {"torque without pull_out", [](json& j) { j["motors"][0]["torque"] = {{"rotor_inertia", 1e-6}}; }},
      {"pull_out of one point", [](json& j) { j["motors"][0]["torque"]["pull_out"] = {{0, 0.4}}; }},
      {"pull_out point of 3", [](json& j) { j["motors"][0]["torque"]["pull_out"][1] = {200, 0.3, 1}; }},
      {"negative pull_out torque", [](json& j) { j["motors"][0]["torque"]["pull_out"][1][1] = -0.1; }},
      {"negative rotor inertia", [](json& j) { j["motors"][0]["torque"]["rotor_inertia"] = -1; }},
      {"torque field typo", [](json& j) { j["motors"][0]["torque"]["pullout"] = 1; }},
      {"unknown board", [](json& j) { j["board"] = "mega"; }},
      {"driver without kind", [](json& j) { j["motors"][0]["driver"] = json::object(); }},
      {"unknown driver kind", [](json& j) { j["motors"][0]["driver"]["kind"] = "tb6600"; }},
      {"driver field typo", [](json& j) { j["motors"][0]["driver"]["chp"] = "a4988"; }},
      {"servo pulse 2700", [](json& j) { j["motors"][0]["driver"] = {{"kind", "servo"}, {"pin", "D9"}, {"pulse", {500, 2700}},
                                                                      {"at", {{1000, 0}, {2000, 90}}}, {"speed", 60}}; }},
      {"unknown chip", [](json& j) { j["motors"][0]["driver"] = {{"kind", "step-dir"}, {"chip", "l6470"}}; }},
      {"17 rows", [](json& j) { for (int i = 0; i < 13; ++i) j["dh"].push_back({{"a", 1}, {"alpha", 0}, {"d", 0}, {"theta", 0}}); }},
  };
  for (auto& [what, breakage] : breakages) {
    json doc = mk2;
    breakage(doc);
    EXPECT_FALSE(validator.errors(doc).empty()) << "schema accepts: " << what;
    EXPECT_THROW(parse_robot(doc.dump(), "broken.json"), RobotFileError) << "loader accepts: " << what;
  }

  // Variants both accept.
  std::vector<std::pair<std::string, std::function<void(json&)>>> fine = {
      {"mesh shape", [](json& j) { j["links"][1]["shapes"][0] = {{"type", "mesh"}, {"mesh", "upper.stl"}, {"mass", 0.1}}; }},
      {"sphere and capsule", [](json& j) {
         j["links"][1]["shapes"].push_back({{"type", "sphere"}, {"size", {5}}});
         j["links"][1]["shapes"].push_back({{"type", "capsule"}, {"size", {5, 20}}, {"rpy", {0, 90, 0}}, {"density", 1000}});
       }},
      {"motor defaults", [](json& j) { j["motors"][0] = {{"name", "base"}, {"min", -90}, {"max", 90}}; }},
      {"direction -1", [](json& j) { j["motors"][0]["direction"] = -1; }},
      {"a CNC shield", [](json& j) {
         j["board"] = "nano-cnc-v4";
         for (auto& m : j["motors"]) m["driver"] = {{"kind", "step-dir"}, {"chip", "drv8825"}, {"enable", "D8"}}, m["microsteps"] = 16;
       }},
      {"no drive named", [](json& j) { j.erase("board"); for (auto& m : j["motors"]) m.erase("driver"); }},
      {"an I/O pin on the one pin the drive leaves free", [](json& j) {
         j["io"] = json::parse(R"([{"name": "ready", "pin": "A5", "mode": "input_pullup"}])"); }},
      {"a d joint", [](json& j) { j["dh"][0]["d"] = {{"joint", "lift"}, {"min", 0}, {"max", 100}}; j["home"]["lift"] = 0;
                                   j.erase("motors"); j.erase("coupling"); j.erase("board"); }},
      {"no optional parts", [](json& j) { for (const char* k : {"description", "tool", "board", "motors", "coupling", "home", "links", "gripper"}) {
                                          j.erase(k);
                                        }
                                      }},
  };
  for (auto& [what, change] : fine) {
    json doc = mk2;
    change(doc);
    const auto errors = validator.errors(doc);
    EXPECT_TRUE(errors.empty()) << "schema rejects: " << what << ": " << (errors.empty() ? "" : errors[0]);
    EXPECT_NO_THROW(parse_robot(doc.dump(), "fine.json")) << "loader rejects: " << what;
  }
}

// ---------------------------------------------------------------- finding and reading files

TEST(ResolveRobotPath, NamesAndPaths) {
  const char* saved = std::getenv("ARTICULA_ROBOTS");
  const std::string saved_value = saved ? saved : "";
  unsetenv("ARTICULA_ROBOTS");
  EXPECT_EQ(resolve_robot_path("mk2plus"), kRobots + "/mk2plus.json");
  EXPECT_TRUE(fs::exists(resolve_robot_path("mk2plus")));
  EXPECT_EQ(resolve_robot_path("robots/mk2plus.json"), "robots/mk2plus.json");
  EXPECT_EQ(resolve_robot_path("./mine"), "./mine");
  EXPECT_EQ(resolve_robot_path("mine.json"), "mine.json");
  setenv("ARTICULA_ROBOTS", "/opt/arms", 1);
  EXPECT_EQ(resolve_robot_path("mk2plus"), "/opt/arms/mk2plus.json");
  EXPECT_EQ(resolve_robot_path("mk2plus.json"), "mk2plus.json");
  setenv("ARTICULA_ROBOTS", "", 1);  // empty: as if unset
  EXPECT_EQ(resolve_robot_path("mk2plus"), kRobots + "/mk2plus.json");
  if (saved)
    setenv("ARTICULA_ROBOTS", saved_value.c_str(), 1);
  else
    unsetenv("ARTICULA_ROBOTS");
}

TEST(LoadRobotFile, FileNotFound) {
  try {
    load_robot_file("/nonexistent/arm.json");
    FAIL() << "no error";
  } catch (const RobotFileError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/arm.json: file not found");
    EXPECT_EQ(e.file(), "/nonexistent/arm.json");
    EXPECT_EQ(e.json_path(), "");
  }
}

TEST(LoadRobotFile, DirectoryIsNotAFile) {
  try {
    load_robot_file(kRobots);
    FAIL() << "no error";
  } catch (const RobotFileError& e) {
    EXPECT_EQ(e.file(), kRobots);
    EXPECT_NE(std::string(e.what()).find("directory"), std::string::npos) << e.what();
  }
}

TEST(LoadRobotFile, ErrorsNameTheFileAsGiven) {
  const fs::path dir = fs::temp_directory_path() / ("articula-robot-file-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "typo.json").string();
  {
    std::ofstream out(path);
    json doc = base_robot();
    doc["dh"][1]["theta"]["min"] = 140;
    out << doc.dump(2);
  }
  try {
    load_robot_file(path);
    FAIL() << "no error";
  } catch (const RobotFileError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": /dh/1/theta/min: limits inverted (min 140 > max 130)");
  }
  fs::remove_all(dir);
}

// ---------------------------------------------------------------- parsing, positive

TEST(ParseRobot, BaseRobotLoads) {
  const Robot r = parse_robot(base_robot().dump(), "ok.json");
  EXPECT_EQ(r.source, "ok.json");
  EXPECT_EQ(r.model.num_joints, 3);
  EXPECT_EQ(r.model.rows[0].d, 78);
  EXPECT_TRUE(r.links.empty());
  EXPECT_FALSE(r.gripper.present);
  // Identity tool when none is given.
  EXPECT_EQ(r.model.T_last_tool.p.x, 0);
  EXPECT_EQ(r.model.T_last_tool.R.m[0][0], 1);
}

TEST(ParseRobot, MotorDefaults) {
  const Robot r = parse_robot(base_robot().dump(), "ok.json");
  const MotorSpec& s = r.actuation.motors[0];
  EXPECT_EQ(s.full_steps_per_rev, 200);
  EXPECT_EQ(s.microsteps, 1);
  EXPECT_EQ(s.direction, 1);
  EXPECT_EQ(s.gear_num, 1);
  EXPECT_EQ(s.gear_den, 1);
  EXPECT_EQ(s.zero, 0);
}

TEST(ParseRobot, IntegralNumbersWrittenAsFloatsAreIntegers) {
  json doc = base_robot();
  doc["motors"][0]["steps_per_rev"] = 400.0;
  doc["motors"][0]["microsteps"] = 2;
  doc["motors"][0]["direction"] = -1;
  doc["motors"][0]["gear"] = {108, 19};
  const Robot r = parse_robot(doc.dump(), "ok.json");
  EXPECT_EQ(r.actuation.motors[0].full_steps_per_rev, 400);
  EXPECT_EQ(r.actuation.motors[0].microsteps, 2);
  EXPECT_EQ(r.actuation.motors[0].direction, -1);
  EXPECT_EQ(r.actuation.motors[0].gear_num, 108);
}

TEST(ParseRobot, MotorLimitsDefaultToTheJointsWithIdentityCoupling) {
  json doc = base_robot();
  doc.erase("coupling");
  doc["motors"] = {{{"name", "a"}}, {{"name", "b"}, {"zero", 36}}, {{"name", "c"}, {"zero", -90}}};
  const Robot r = parse_robot(doc.dump(), "ok.json");
  EXPECT_EQ(r.actuation.motors[0].min, -90000);
  EXPECT_EQ(r.actuation.motors[0].max, 90000);
  EXPECT_EQ(r.actuation.motors[1].min, 36000);
  EXPECT_EQ(r.actuation.motors[1].max, 130000);
  EXPECT_EQ(r.actuation.motors[2].min, -173000);
  EXPECT_EQ(r.actuation.motors[2].max, -21000);
  EXPECT_EQ(r.actuation.coupling[2][1], 0.0);
  EXPECT_EQ(r.actuation.coupling_inv[2][2], 1.0);
  // An identity matrix written out counts as identity too.
  doc["coupling"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_EQ(parse_robot(doc.dump(), "ok.json").actuation.motors[2].min, -173000);
}

TEST(ParseRobot, DefaultHomeIsZeroClampedIntoTheLimits) {
  json doc = base_robot();
  doc.erase("home");
  doc.erase("motors");
  doc.erase("coupling");
  const Robot r = parse_robot(doc.dump(), "ok.json");
  ASSERT_EQ(r.home.size(), 3u);
  EXPECT_EQ(r.home[0], 0.0);
  EXPECT_DOUBLE_EQ(r.home[1], rad(36));
  EXPECT_DOUBLE_EQ(r.home[2], rad(-21));
}

TEST(ParseRobot, UnitsOfJointsLinksAndTool) {
  json doc = {
      {"name", "units"},
      {"dh",
       {{{"a", 5}, {"alpha", 30}, {"d", {{"joint", "lift"}, {"min", -10}, {"max", 250}}}, {"theta", 45}},
        {{"a", 0},
         {"alpha", {{"joint", "twist"}, {"min", -90}, {"max", 90}}},
         {"d", {{"linked", {{"twist", 2}}}, {"offset", 3}}},                    // mm per deg
         {"theta", {{"linked", {{"lift", 0.5}, {"twist", -1}}}, {"offset", 10}}}}}},  // deg per mm, deg per deg
      {"tool", {{"xyz", {1, 2, 3}}, {"rpy", {10, 20, 30}}}},
      {"home", {{"lift", 100}, {"twist", 45}}},
  };
  const Robot r = parse_robot(doc.dump(), "ok.json");
  const HostModel& m = r.model;
  EXPECT_DOUBLE_EQ(m.rows[0].alpha, rad(30));
  EXPECT_DOUBLE_EQ(m.rows[0].theta, rad(45));
  EXPECT_EQ(m.rows[0].d, 0.0);  // a variable has no constant
  ASSERT_EQ(m.num_joints, 2);
  EXPECT_EQ(m.joints[0].param, kParamD);
  EXPECT_EQ(m.joints[0].lo, -10);  // mm: not converted
  EXPECT_EQ(m.joints[0].hi, 250);
  EXPECT_EQ(m.joints[1].param, kParamAlpha);
  EXPECT_DOUBLE_EQ(m.joints[1].hi, rad(90));
  EXPECT_EQ(r.home[0], 100.0);
  EXPECT_DOUBLE_EQ(r.home[1], rad(45));
  ASSERT_EQ(m.num_linked, 2);
  // d(2) = 3 mm + 2 mm/deg * twist: 93 mm at twist 45 deg.
  // theta(2) = 10 deg + 0.5 deg/mm * lift - twist: 10 + 50 - 45 = 15 deg.
  DhRow<double> table[kMaxRows];
  dh_table(table, m, r.home.data());
  EXPECT_NEAR(table[1].d, 93, 1e-12);
  EXPECT_NEAR(table[1].theta, rad(15), 1e-12);
  EXPECT_NEAR(table[0].d, 100, 1e-12);
  EXPECT_NEAR(table[1].alpha, rad(45), 1e-12);

  const Mat3<double> want = rpy_to_matrix(rad(10), rad(20), rad(30));
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(m.T_last_tool.R.m[i][k], want.m[i][k]);
  EXPECT_EQ(m.T_last_tool.p.z, 3);
}

TEST(ParseRobot, JointsAreNumberedRowByRowThetaDAlpha) {
  // Keys written in another order than the numbering, to show the order is the loader's.
  const std::string text = R"({"name": "order", "dh": [
    {"alpha": {"joint": "r1_alpha", "min": -1, "max": 1}, "d": {"joint": "r1_d", "min": 0, "max": 5},
     "theta": {"joint": "r1_theta", "min": -1, "max": 1}, "a": 0},
    {"a": 3, "d": {"joint": "r2_d", "min": 0, "max": 5}, "alpha": 0, "theta": 0}]})";
  const Robot r = parse_robot(text, "ok.json");
  EXPECT_EQ(r.joint_names, (std::vector<std::string>{"r1_theta", "r1_d", "r1_alpha", "r2_d"}));
  EXPECT_EQ(r.model.joints[1].param, kParamD);
  EXPECT_EQ(r.model.joints[2].param, kParamAlpha);
  EXPECT_EQ(r.model.joints[3].row, 1);
}

TEST(ParseRobot, LinkedGainsMayNameLaterJoints) {
  json doc = {{"name", "forward"},
              {"dh",
               {{{"a", 0}, {"alpha", 0}, {"d", 0}, {"theta", {{"linked", {{"late", 2}}}}}},
                {{"a", 10}, {"alpha", 0}, {"d", 0}, {"theta", {{"joint", "late"}, {"min", -10}, {"max", 10}}}}}}};
  const Robot r = parse_robot(doc.dump(), "ok.json");
  EXPECT_EQ(r.model.linked[0].row, 0);
  EXPECT_EQ(r.model.linked[0].gain[0], 2.0);
}

TEST(ParseRobot, ShapesAndGripper) {
  json doc = base_robot();
  doc["links"] = {{{"frame", 4},
                   {"shapes",
                    {{{"type", "sphere"}, {"size", {10}}, {"mass", 0.05}},
                     {{"type", "mesh"}, {"mesh", "meshes/claw.stl"}, {"xyz", {1, 2, 3}}, {"rpy", {0, 0, 90}}, {"density", 1000}}}}}};
  doc["gripper"] = {{"max_opening", 30}, {"finger_length", 25}, {"servo_open", 10}, {"servo_closed", 170}};
  const Robot r = parse_robot(doc.dump(), "ok.json");
  ASSERT_EQ(r.links.size(), 1u);
  EXPECT_EQ(r.links[0].frame, 4);
  ASSERT_EQ(r.links[0].shapes.size(), 2u);
  const Shape& ball = r.links[0].shapes[0];
  EXPECT_EQ(ball.type, Shape::Type::kSphere);
  EXPECT_EQ(ball.size[0], 10);
  EXPECT_EQ(ball.mass, 0.05);
  EXPECT_EQ(ball.density, 0.0);
  const Shape& claw = r.links[0].shapes[1];
  EXPECT_EQ(claw.type, Shape::Type::kMesh);
  EXPECT_EQ(claw.mesh, "meshes/claw.stl");
  EXPECT_EQ(claw.density, 1000.0);
  EXPECT_EQ(claw.T_frame_shape.p.y, 2);
  EXPECT_NEAR(claw.T_frame_shape.R.m[1][0], 1.0, 1e-15);  // yaw 90: x turns to y
  EXPECT_TRUE(r.gripper.present);
  EXPECT_EQ(r.gripper.max_opening_mm, 30);
  EXPECT_EQ(r.gripper.servo_closed_deg, 170);
}

// ---------------------------------------------------------------- errors, one each

TEST(RobotFileErrors, MessageFormat) {
  const RobotFileError with_path("a.json", "/dh/0", "bad");
  EXPECT_STREQ(with_path.what(), "a.json: /dh/0: bad");
  const RobotFileError without("a.json", "", "file not found");
  EXPECT_STREQ(without.what(), "a.json: file not found");
}

TEST(RobotFileErrors, JsonSyntaxErrorGivesLineAndColumn) {
  // Line 3, column 10 is the stray '}'.
  EXPECT_TRUE(text_fails_with("{\n  \"name\": \"x\",\n  \"dh\": [}\n", "", {"JSON syntax error", "line 3, column 10"}));
  EXPECT_TRUE(text_fails_with("{\"name\": \"x\", }", "", {"JSON syntax error", "line 1, column 15"}));
  EXPECT_TRUE(text_fails_with("", "", {"JSON syntax error", "line 1, column 1"}));
  // The lexer reads "tru}" whole and stops at the brace: that is where the error is.
  EXPECT_TRUE(text_fails_with("{\"name\": tru}", "", {"JSON syntax error", "line 1, column 13", "invalid literal"}));
}

TEST(RobotFileErrors, RootNotAnObject) {
  EXPECT_TRUE(text_fails_with("[1, 2]", "", {"expected an object, got an array"}));
}

TEST(RobotFileErrors, MissingRequiredField) {
  json doc = base_robot();
  doc.erase("name");
  EXPECT_TRUE(fails_with(doc, "/name", {"missing required field \"name\""}));
  doc = base_robot();
  doc["dh"][2].erase("a");
  EXPECT_TRUE(fails_with(doc, "/dh/2/a", {"missing required field \"a\""}));
  doc = base_robot();
  doc["dh"][1]["theta"].erase("max");
  EXPECT_TRUE(fails_with(doc, "/dh/1/theta/max", {"missing required field \"max\""}));
  doc = base_robot();
  doc.erase("dh");
  EXPECT_TRUE(fails_with(doc, "/dh", {"missing required field \"dh\""}));
}

TEST(RobotFileErrors, WrongType) {
  json doc = base_robot();
  doc["name"] = 5;
  EXPECT_TRUE(fails_with(doc, "/name", {"expected a string, got a number (5)"}));
  doc = base_robot();
  doc["dh"][2]["a"] = "135";
  EXPECT_TRUE(fails_with(doc, "/dh/2/a", {"expected a number, got a string (\"135\")"}));
  doc = base_robot();
  doc["dh"] = json::object();
  EXPECT_TRUE(fails_with(doc, "/dh", {"expected an array, got an object"}));
  doc = base_robot();
  doc["motors"][1] = true;
  EXPECT_TRUE(fails_with(doc, "/motors/1", {"expected an object, got a boolean (true)"}));
  doc = base_robot();
  doc["dh"][0]["theta"]["min"] = nullptr;
  EXPECT_TRUE(fails_with(doc, "/dh/0/theta/min", {"expected a number, got null"}));
}

TEST(RobotFileErrors, ParameterOfNoKnownKind) {
  json doc = base_robot();
  doc["dh"][0]["d"] = "78";
  EXPECT_TRUE(fails_with(doc, "/dh/0/d", {"expected a number, a joint variable", "linked parameter", "got a string"}));
  doc = base_robot();
  doc["dh"][0]["d"] = {{"value", 78}};
  EXPECT_TRUE(fails_with(doc, "/dh/0/d", {"neither \"joint\" nor \"linked\""}));
}

TEST(RobotFileErrors, WrongTypeForIntegers) {
  json doc = base_robot();
  doc["motors"][0]["steps_per_rev"] = 200.5;
  EXPECT_TRUE(fails_with(doc, "/motors/0/steps_per_rev", {"expected an integer, got 200.5"}));
  doc = base_robot();
  doc["motors"][0]["microsteps"] = 256;
  EXPECT_TRUE(fails_with(doc, "/motors/0/microsteps", {"256 is out of range (0..255)"}));
}

TEST(RobotFileErrors, UnknownField) {
  json doc = base_robot();
  doc["nmae"] = "x";
  EXPECT_TRUE(fails_with(doc, "/nmae", {"unknown field \"nmae\"", "expected one of: $schema, name"}));
  doc = base_robot();
  doc["dh"][1]["thta"] = 0;
  EXPECT_TRUE(fails_with(doc, "/dh/1/thta", {"unknown field \"thta\"", "a, alpha, d, theta"}));
  doc = base_robot();
  doc["dh"][1]["theta"]["mni"] = 0;
  EXPECT_TRUE(fails_with(doc, "/dh/1/theta/mni", {"unknown field \"mni\""}));
  doc = base_robot();
  doc["motors"][2]["gear_ratio"] = 3;
  EXPECT_TRUE(fails_with(doc, "/motors/2/gear_ratio", {"unknown field \"gear_ratio\""}));
  doc = base_robot();
  doc["dh"][3]["theta"]["joint"] = "x";  // a linked parameter cannot also be a joint
  EXPECT_TRUE(fails_with(doc, "/dh/3/theta/linked", {"unknown field \"linked\""}));
}

TEST(RobotFileErrors, DuplicateField) {
  const std::string text = R"({"name": "a", "dh": [{"a": 0, "alpha": 0, "d": 1, "theta": 0, "d": 2}]})";
  EXPECT_TRUE(text_fails_with(text, "/dh/0/d", {"duplicate field \"d\""}));
}

TEST(RobotFileErrors, NegativeLinkLengthRange) {
  // A length RoboSim's `l` may change is a length: never negative.
  json doc = base_robot();
  doc["dh"][2]["a"] = {{"value", 135}, {"min", -10}, {"max", 200}};
  EXPECT_TRUE(fails_with(doc, "/dh/2/a/min", {"negative length (-10 mm)"}));
}

TEST(RobotFileErrors, NonFiniteNumber) {
  const std::string text = R"({"name": "a", "dh": [{"a": 0, "alpha": 0, "d": 1e999, "theta": 0}]})";
  EXPECT_TRUE(text_fails_with(text, "/dh/0/d", {"not a finite number", "1e999"}));
  const std::string in_array = R"({"name": "a", "dh": [{"a": 0, "alpha": 0, "d": 0, "theta": 0}], "tool": {"xyz": [0, -1e400, 0]}})";
  EXPECT_TRUE(text_fails_with(in_array, "/tool/xyz/1", {"not a finite number"}));
}

TEST(RobotFileErrors, LimitsInverted) {
  json doc = base_robot();
  doc["dh"][1]["theta"]["min"] = 130;
  doc["dh"][1]["theta"]["max"] = 36;
  EXPECT_TRUE(fails_with(doc, "/dh/1/theta/min", {"limits inverted (min 130 > max 36)"}));
}

TEST(RobotFileErrors, UnknownJointInLinked) {
  json doc = base_robot();
  doc["dh"][3]["theta"]["linked"] = {{"shoulder", -1}, {"elbw", -1}};
  EXPECT_TRUE(fails_with(doc, "/dh/3/theta/linked/elbw", {"unknown joint name \"elbw\"", "base, shoulder, elbow"}));
}

TEST(RobotFileErrors, LinkedGainsNotAnObject) {
  json doc = base_robot();
  doc["dh"][3]["theta"]["linked"] = {-1, -1};
  EXPECT_TRUE(fails_with(doc, "/dh/3/theta/linked", {"expected an object", "got an array"}));
}

TEST(RobotFileErrors, UnknownJointInHome) {
  json doc = base_robot();
  doc["home"]["wrist"] = 0;
  EXPECT_TRUE(fails_with(doc, "/home/wrist", {"unknown joint name \"wrist\""}));
  doc = base_robot();
  doc["home"]["a/b~c"] = 0;  // JSON pointer escaping
  EXPECT_TRUE(fails_with(doc, "/home/a~1b~0c", {"unknown joint name \"a/b~c\""}));
}

TEST(RobotFileErrors, HomeMissingAJoint) {
  json doc = base_robot();
  doc["home"].erase("elbow");
  EXPECT_TRUE(fails_with(doc, "/home/elbow", {"missing required field \"elbow\"", "every joint"}));
}

TEST(RobotFileErrors, DuplicateJointName) {
  json doc = base_robot();
  doc["dh"][2]["theta"]["joint"] = "shoulder";
  EXPECT_TRUE(fails_with(doc, "/dh/2/theta/joint", {"duplicate joint name \"shoulder\"", "/dh/1/theta"}));
}

TEST(RobotFileErrors, EmptyJointName) {
  json doc = base_robot();
  doc["dh"][0]["theta"]["joint"] = "";
  EXPECT_TRUE(fails_with(doc, "/dh/0/theta/joint", {"must not be empty"}));
}

TEST(RobotFileErrors, CouplingWrongShape) {
  json doc = base_robot();
  doc["coupling"] = {{1, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(fails_with(doc, "/coupling", {"expected 3 rows (one per joint variable), got 2"}));
  doc = base_robot();
  doc["coupling"][1] = {0, 1};
  EXPECT_TRUE(fails_with(doc, "/coupling/1", {"expected 3 entries (one per motor), got 2"}));
  doc = base_robot();
  doc["coupling"][1] = 1;
  EXPECT_TRUE(fails_with(doc, "/coupling/1", {"expected an array, got a number"}));
}

TEST(RobotFileErrors, CouplingSingular) {
  json doc = base_robot();
  doc["coupling"] = {{1, 0, 0}, {0, 1, 1}, {0, 2, 2}};
  EXPECT_TRUE(fails_with(doc, "/coupling", {"singular"}));
}

TEST(RobotFileErrors, CouplingWithoutMotors) {
  json doc = base_robot();
  doc.erase("motors");
  EXPECT_TRUE(fails_with(doc, "/coupling", {"needs \"motors\""}));
}

TEST(RobotFileErrors, MotorCountNotJointCount) {
  json doc = base_robot();
  doc["motors"].erase(2);
  EXPECT_TRUE(fails_with(doc, "/motors", {"expected 3 motors (one per joint variable), got 2"}));
}

TEST(RobotFileErrors, DuplicateMotorName) {
  json doc = base_robot();
  doc["motors"][2]["name"] = "m0";
  EXPECT_TRUE(fails_with(doc, "/motors/2/name", {"duplicate motor name \"m0\"", "/motors/0/name"}));
}

TEST(RobotFileErrors, MotorLimitsRequiredWithACoupling) {
  json doc = base_robot();
  doc["motors"][2].erase("min");
  EXPECT_TRUE(fails_with(doc, "/motors/2/min", {"missing required field \"min\"", "unless the coupling is identity"}));
}

TEST(RobotFileErrors, TooManyRows) {
  json doc = {{"name", "long"}, {"dh", json::array()}};
  for (int i = 0; i < 17; ++i) doc["dh"].push_back({{"a", 1}, {"alpha", 0}, {"d", 0}, {"theta", 0}});
  EXPECT_TRUE(fails_with(doc, "/dh", {"17 rows", "at most 16"}));
  doc["dh"].erase(16);
  EXPECT_NO_THROW(parse_robot(doc.dump(), "ok.json"));  // 16 is fine
}

TEST(RobotFileErrors, NoRows) {
  json doc = {{"name", "empty"}, {"dh", json::array()}};
  EXPECT_TRUE(fails_with(doc, "/dh", {"at least one row"}));
}

TEST(RobotFileErrors, TooManyJointVariables) {
  json doc = {{"name", "many"}, {"dh", json::array()}};
  for (int i = 1; i <= 7; ++i) doc["dh"].push_back(joint_row("t" + std::to_string(i), "a" + std::to_string(i)));
  // 14 variables; the 13th is theta of row 7.
  EXPECT_TRUE(fails_with(doc, "/dh/6/theta", {"more than 12 joint variables", "at most 12"}));
  doc["dh"][6]["alpha"] = 0;
  doc["dh"][6]["theta"] = 0;
  EXPECT_NO_THROW(parse_robot(doc.dump(), "ok.json"));  // 12 is fine
}

TEST(RobotFileErrors, TooManyLinkedParameters) {
  json doc = {{"name", "links"}, {"dh", {joint_row("q")}}};
  const json link = {{"linked", {{"q", 1}}}};
  for (int i = 0; i < 6; ++i) doc["dh"].push_back({{"a", 1}, {"alpha", link}, {"d", link}, {"theta", link}});
  // Rows 1..6 hold 18 linked parameters; the 17th is row 6's d.
  EXPECT_TRUE(fails_with(doc, "/dh/6/d", {"more than 16 linked parameters", "at most 16"}));
}

TEST(RobotFileErrors, HomeOutsideLimits) {
  json doc = base_robot();
  doc["home"]["elbow"] = -200;
  EXPECT_TRUE(fails_with(doc, "/home/elbow", {"outside the joint limits (-200 not in -173..-21)"}));
}

TEST(RobotFileErrors, HomeOutsideMotorLimits) {
  json doc = base_robot();
  // Inside every joint's limits, but the forearm would point 109 deg up: beyond 15.
  doc["home"] = {{"base", 0}, {"shoulder", 130}, {"elbow", -21}};
  EXPECT_TRUE(fails_with(doc, "/home", {"motor \"m2\" at 109 deg", "outside its limits -43..15"}));
  // The default home (0 clamped: shoulder 36, elbow -21) puts the forearm at 15 deg.
  doc.erase("home");
  EXPECT_NO_THROW(parse_robot(doc.dump(), "ok.json"));
  doc["motors"][2]["max"] = 10;
  EXPECT_TRUE(fails_with(doc, "/home", {"motor \"m2\" at 15 deg", "no \"home\" given"}));
}

TEST(RobotFileErrors, MotorBadDirection) {
  json doc = base_robot();
  doc["motors"][0]["direction"] = 2;
  EXPECT_TRUE(fails_with(doc, "/motors/0/direction", {motor_error_text(kMotorBadDirection)}));
}

TEST(RobotFileErrors, MotorBadGear) {
  json doc = base_robot();
  doc["motors"][0]["gear"] = {0, 19};
  EXPECT_TRUE(fails_with(doc, "/motors/0/gear", {motor_error_text(kMotorBadGear), "[0, 19]"}));
  doc["motors"][0]["gear"] = {108};
  EXPECT_TRUE(fails_with(doc, "/motors/0/gear", {"2 integers", "got 1"}));
}

TEST(RobotFileErrors, MotorBadSteps) {
  json doc = base_robot();
  doc["motors"][1]["steps_per_rev"] = 0;
  EXPECT_TRUE(fails_with(doc, "/motors/1", {motor_error_text(kMotorBadSteps)}));
}

TEST(RobotFileErrors, MotorZeroOutsideLimits) {
  json doc = base_robot();
  doc["motors"][1]["zero"] = 0;  // shoulder motor limited to 36..130
  EXPECT_TRUE(fails_with(doc, "/motors/1", {motor_error_text(kMotorBadLimits), "min 36, max 130, zero 0"}));
}

TEST(RobotFileErrors, MotorLimitsInverted) {
  json doc = base_robot();
  doc["motors"][2]["min"] = 15;
  doc["motors"][2]["max"] = -43;
  EXPECT_TRUE(fails_with(doc, "/motors/2", {motor_error_text(kMotorBadLimits), "min 15, max -43"}));
}

TEST(RobotFileErrors, MotorTooFine) {
  json doc = base_robot();
  doc["motors"][0]["steps_per_rev"] = 60000;
  doc["motors"][0]["microsteps"] = 200;
  doc["motors"][0]["gear"] = {1000, 1};
  EXPECT_TRUE(fails_with(doc, "/motors/0", {motor_error_text(kMotorTooFine)}));
}

TEST(RobotFileErrors, MotorAngleBeyondAMillionDegrees) {
  json doc = base_robot();
  doc["motors"][0]["max"] = 2e6;
  EXPECT_TRUE(fails_with(doc, "/motors/0/max", {"beyond +-1,000,000 degrees"}));
}

TEST(RobotFileErrors, ModelRejectedByTheCore) {
  // Finite as written, infinite once 1e307 mm/deg becomes mm/rad: only the core's
  // validate(Model) sees it.
  json doc = {{"name", "overflow"},
              {"dh",
               {joint_row("q"), {{"a", 0}, {"alpha", 0}, {"d", {{"linked", {{"q", 1e307}}}}}, {"theta", 0}}}}};
  EXPECT_TRUE(fails_with(doc, "/dh", {"not usable", model_error_text(kModelNotFinite)}));
}

TEST(RobotFileErrors, ShapeSizes) {
  json doc = base_robot();
  doc["links"] = {{{"frame", 1}, {"shapes", {{{"type", "box"}, {"size", {10, 0, 10}}}}}}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/size/1", {"size must be > 0 (got 0)"}));
  doc["links"][0]["shapes"][0]["size"] = {10, 10};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/size", {"expected 3 numbers", "box", "got 2"}));
  doc["links"][0]["shapes"][0] = {{"type", "cylinder"}, {"size", {10, 20, 30}}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/size", {"expected 2 numbers", "radius, length", "got 3"}));
  doc["links"][0]["shapes"][0] = {{"type", "sphere"}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/size", {"missing required field \"size\""}));
}

TEST(RobotFileErrors, ShapeTypeMeshAndMass) {
  json doc = base_robot();
  doc["links"] = {{{"frame", 1}, {"shapes", {{{"type", "cube"}, {"size", {1, 1, 1}}}}}}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/type", {"unknown shape type \"cube\""}));
  doc["links"][0]["shapes"][0] = {{"type", "mesh"}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/mesh", {"missing required field \"mesh\""}));
  doc["links"][0]["shapes"][0] = {{"type", "mesh"}, {"mesh", "a.stl"}, {"size", {1}}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/size", {"a mesh shape has no size"}));
  doc["links"][0]["shapes"][0] = {{"type", "box"}, {"size", {1, 1, 1}}, {"mesh", "a.stl"}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/mesh", {"only a shape of type \"mesh\""}));
  doc["links"][0]["shapes"][0] = {{"type", "box"}, {"size", {1, 1, 1}}, {"mass", 1}, {"density", 1000}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/density", {"mass", "density", "not both"}));
  doc["links"][0]["shapes"][0] = {{"type", "box"}, {"size", {1, 1, 1}}, {"mass", -1}};
  EXPECT_TRUE(fails_with(doc, "/links/0/shapes/0/mass", {"mass must be > 0"}));
}

TEST(RobotFileErrors, LinkFrameDoesNotExist) {
  json doc = base_robot();
  doc["links"] = {{{"frame", 5}, {"shapes", json::array()}}};
  EXPECT_TRUE(fails_with(doc, "/links/0/frame", {"frame 5 does not exist", "0..4"}));
  doc["links"][0]["frame"] = 4;
  EXPECT_NO_THROW(parse_robot(doc.dump(), "ok.json"));
}

TEST(RobotFileErrors, Gripper) {
  json doc = base_robot();
  doc["gripper"] = {{"max_opening", 40}, {"finger_length", 40}, {"servo_open", 90}, {"servo_closed", 190}};
  EXPECT_TRUE(fails_with(doc, "/gripper/servo_closed", {"within 0..180", "190"}));
  doc["gripper"].erase("servo_closed");
  EXPECT_TRUE(fails_with(doc, "/gripper/servo_closed", {"missing required field"}));
  doc["gripper"]["servo_closed"] = 150;
  doc["gripper"]["max_opening"] = 0;
  EXPECT_TRUE(fails_with(doc, "/gripper/max_opening", {"must be > 0"}));
  doc["gripper"]["max_opening"] = 40;
  doc["gripper"]["finger_height"] = -2;
  EXPECT_TRUE(fails_with(doc, "/gripper/finger_height", {"must be > 0"}));
  doc["gripper"]["finger_height"] = 20;
  doc["gripper"]["finger_thickness"] = "8";
  EXPECT_TRUE(fails_with(doc, "/gripper/finger_thickness", {"expected a number"}));
}

TEST(ParseRobot, FingerSizeIsOptional) {
  json doc = base_robot();
  doc["gripper"] = {{"max_opening", 30}, {"finger_length", 25}, {"servo_open", 10}, {"servo_closed", 170}};
  const Robot defaults = parse_robot(doc.dump(), "ok.json");
  EXPECT_EQ(defaults.gripper.finger_thickness_mm, 8);
  EXPECT_EQ(defaults.gripper.finger_height_mm, 20);
  doc["gripper"]["finger_thickness"] = 5.5;
  doc["gripper"]["finger_height"] = 12;
  const Robot given = parse_robot(doc.dump(), "ok.json");
  EXPECT_EQ(given.gripper.finger_thickness_mm, 5.5);
  EXPECT_EQ(given.gripper.finger_height_mm, 12);
}

TEST(ParseRobot, MotorTorque) {
  json doc = base_robot();
  doc["motors"][1]["torque"] = {{"pull_out", {{0, 0.4}, {300, 0.35}, {1500, 0.1}}}, {"rotor_inertia", 5.4e-6}};
  const Robot r = parse_robot(doc.dump(), "torque.json");
  ASSERT_EQ(r.motor_torque.size(), 3u);
  EXPECT_FALSE(r.motor_torque[0].given());
  ASSERT_TRUE(r.motor_torque[1].given());
  ASSERT_EQ(r.motor_torque[1].pull_out.size(), 3u);
  EXPECT_EQ(r.motor_torque[1].pull_out[1][0], 300);
  EXPECT_EQ(r.motor_torque[1].pull_out[1][1], 0.35);
  EXPECT_EQ(r.motor_torque[1].rotor_inertia, 5.4e-6);
  // The MK2 ships datasheet-typical figures for every motor.
  const Robot mk2 = load_robot_file(kRobots + "/mk2plus.json");
  ASSERT_EQ(mk2.motor_torque.size(), 3u);
  for (const MotorTorque& t : mk2.motor_torque) {
    ASSERT_TRUE(t.given());
    EXPECT_EQ(t.pull_out[0][1], 0.40);
    EXPECT_GT(t.rotor_inertia, 0);
  }
}

TEST(RobotFileErrors, MotorTorque) {
  json doc = base_robot();
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}, {300, 0.35}}}, {"inertia", 1}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/inertia", {"unknown field \"inertia\"", "pull_out, rotor_inertia"}));
  doc["motors"][2]["torque"] = {{"rotor_inertia", 1e-6}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out", {"missing required field \"pull_out\""}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out", {"at least 2 points", "got 1"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}, {300}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out/1", {"[full steps/s, N*m]", "got 1 entries"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{10, 0.4}, {300, 0.3}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out/0/0", {"start at rate 0", "got 10"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}, {300, 0.3}, {300, 0.2}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out/2/0", {"strictly ascending", "300 after 300"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}, {300, -0.1}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out/1/1", {"torque must be >= 0", "-0.1"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0}, {300, 0.1}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out/0/1", {"holding torque must be > 0"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}, {"fast", 0.1}}}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/pull_out/1/0", {"expected a number, got a string"}));
  doc["motors"][2]["torque"] = {{"pull_out", {{0, 0.4}, {300, 0.1}}}, {"rotor_inertia", -1}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque/rotor_inertia", {"rotor inertia must be >= 0"}));
  doc["motors"][2]["torque"] = json::array();
  EXPECT_TRUE(fails_with(doc, "/motors/2/torque", {"expected an object, got an array"}));
}

TEST(RobotFileErrors, EmptyName) {
  json doc = base_robot();
  doc["name"] = "";
  EXPECT_TRUE(fails_with(doc, "/name", {"must not be empty"}));
}

// ---------------------------------------------------------------- the drive: board and drivers

// base_robot() on hobby servos: each motor's limits map into its pulse range.
json servo_robot() {
  json doc = base_robot();
  doc["motors"][1].erase("zero");
  doc["motors"][0]["driver"] = json::parse(R"({"kind": "servo", "pin": "D9", "at": [[1000, -45], [2000, 45]], "speed": 120})");
  doc["motors"][1]["driver"] = json::parse(R"({"kind": "servo", "pin": "D10", "at": [[1500, 90], [2500, 180]], "speed": 120})");
  doc["motors"][2]["driver"] =
      json::parse(R"({"kind": "servo", "pin": "D11", "pulse": [600, 2400], "at": [[1500, 0], [2400, 90]], "speed": 90, "accel": 300})");
  return doc;
}

// base_robot() on a CNC shield with STEP/DIR drivers.
json shield_robot(const std::string& chip, int microsteps) {
  json doc = base_robot();
  doc["board"] = "uno-cnc-v3";
  for (auto& m : doc["motors"]) {
    m["driver"] = {{"kind", "step-dir"}, {"chip", chip}};
    m["microsteps"] = microsteps;
  }
  return doc;
}

// The pin (by name) each wire of a motor uses, keyed by signal.
std::map<std::string, std::string> pins_of(const Wiring& w, int motor) {
  std::map<std::string, std::string> out;
  for (const Wire& x : w.wires)
    if (x.motor == motor) out[x.signal] = board::kHeaderPin[x.pin].pin;
  return out;
}
std::string pin_of(const Wiring& w, const std::string& part) {
  for (const Wire& x : w.wires)
    if (x.part == part) return board::kHeaderPin[x.pin].pin;
  return "";
}

TEST(Drive, WithoutADriverAMotorIsAnL298nOnTheNano) {
  const Robot r = parse_robot(base_robot().dump(), "t.json");
  EXPECT_FALSE(r.drive.given);
  EXPECT_EQ(r.drive.board, board::kBoardNano);
  ASSERT_EQ(r.drive.motors.size(), 3u);
  for (const MotorDriver& d : r.drive.motors) EXPECT_EQ(d.kind, kDriveL298n);
  const Wiring w = wire(r);
  EXPECT_EQ(pins_of(w, 0), (std::map<std::string, std::string>{{"IN1", "D4"}, {"IN2", "D5"}, {"IN3", "D6"}, {"IN4", "D7"}, {"switch", "D2"}}));
  EXPECT_EQ(pins_of(w, 1), (std::map<std::string, std::string>{{"IN1", "D8"}, {"IN2", "D9"}, {"IN3", "D10"}, {"IN4", "D11"}, {"switch", "D12"}}));
  EXPECT_EQ(pins_of(w, 2), (std::map<std::string, std::string>{{"IN1", "A0"}, {"IN2", "A1"}, {"IN3", "A2"}, {"IN4", "A3"}, {"switch", "A4"}}));
  EXPECT_EQ(pin_of(w, "USB serial"), "D0");
  // The shipped MK2 Plus names the same wiring, and its gripper is on D3.
  const Robot mk2 = load_robot_file(kRobots + "/mk2plus.json");
  EXPECT_TRUE(mk2.drive.given);
  EXPECT_EQ(mk2.drive.board, board::kBoardNano);
  EXPECT_EQ(pin_of(wire(mk2), "gripper servo"), "D3");
}

TEST(Drive, AFileThatNamesNoDriveIsNotWired) {
  // More motors than a Nano wires, at 16 microsteps: the host's firmware runs it all the same.
  json doc = base_robot();
  doc["motors"][0]["microsteps"] = 16;
  EXPECT_NO_THROW(parse_robot(doc.dump(), "t.json"));
  doc["board"] = "nano";
  EXPECT_TRUE(fails_with(doc, "/motors/0/microsteps", {"the L298N has no 16"}));
}

TEST(Drive, StepDirDriversInTheSocketsOfACncShield) {
  json doc = shield_robot("a4988", 8);
  doc["motors"][0]["driver"]["enable"] = "D8";
  doc["gripper"] = json::parse(R"({"max_opening": 40, "finger_length": 40, "servo_open": 90, "servo_closed": 150})");
  const Robot r = parse_robot(doc.dump(), "t.json");
  EXPECT_EQ(r.drive.board, board::kBoardUnoCncV3);
  EXPECT_EQ(r.actuation.motors[0].microsteps, 8);
  EXPECT_EQ(kStepDirChip[r.drive.motors[0].chip].step_high_ns, 1000);
  const Wiring w = wire(r);
  EXPECT_EQ(pins_of(w, 0), (std::map<std::string, std::string>{{"STEP", "D2"}, {"DIR", "D5"}, {"switch", "D9"}}));
  EXPECT_EQ(pins_of(w, 1), (std::map<std::string, std::string>{{"STEP", "D3"}, {"DIR", "D6"}, {"switch", "D10"}}));
  EXPECT_EQ(pins_of(w, 2), (std::map<std::string, std::string>{{"STEP", "D4"}, {"DIR", "D7"}, {"switch", "D11"}}));
  EXPECT_EQ(pin_of(w, "drivers"), "D8");
  EXPECT_EQ(pin_of(w, "gripper servo"), "A3");
  // Each chip's own modes: the DRV8825 has 1/32, the TMC2209 1/64.
  EXPECT_NO_THROW(parse_robot(shield_robot("drv8825", 32).dump(), "t.json"));
  EXPECT_NO_THROW(parse_robot(shield_robot("tmc2209", 64).dump(), "t.json"));
}

TEST(Drive, AServoJointsStepsAreThePulsesTicks) {
  const Robot r = parse_robot(servo_robot().dump(), "t.json");
  const MotorSpec& m = r.actuation.motors[0];
  // 1000 us for 90 deg: 2000 ticks, 8000 a turn; step 0 at the first point.
  EXPECT_EQ(detail::steps_num(m) / m.gear_den, 8000);
  EXPECT_EQ(m.direction, 1);
  EXPECT_EQ(m.zero, -45000);
  EXPECT_EQ(quantize(m, Millideg(45000)), 2000);  // 1000 us + 2000 ticks = 2000 us
  EXPECT_EQ(r.drive.motors[2].accel_deg_s2, 300);
  // A servo whose pulse falls as the angle rises steps the other way.
  json doc = servo_robot();
  doc["motors"][0]["driver"]["at"] = {{2000, -45}, {1000, 45}};
  EXPECT_EQ(parse_robot(doc.dump(), "t.json").actuation.motors[0].direction, -1);
  EXPECT_EQ(pins_of(wire(r), 1), (std::map<std::string, std::string>{{"signal", "D10"}}));
}

TEST(DriveErrors, TwoMotorsOnOnePin) {
  json doc = servo_robot();
  doc["motors"][1]["driver"]["pin"] = "D9";
  EXPECT_TRUE(fails_with(doc, "/motors/1/driver/pin", {"pin D9 of the Arduino Nano", "motor \"m0\"'s servo signal", "motor \"m1\"'s servo signal"}));
  doc = servo_robot();
  doc["gripper"] = json::parse(R"({"max_opening": 40, "finger_length": 40, "servo_open": 90, "servo_closed": 150})");
  doc["motors"][2]["driver"]["pin"] = "D3";
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/pin", {"pin D3", "the gripper servo signal", "motor \"m2\""}));
  doc["motors"][2]["driver"]["pin"] = "D1";
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/pin", {"pin D1", "USB serial TX"}));
  doc["motors"][2]["driver"]["pin"] = "A6";
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/pin", {"A6 is an analog input only"}));
  doc["board"] = "uno";
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/pin", {"the Arduino Uno has no A6"}));
  doc["motors"][2]["driver"]["pin"] = "D14";
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/pin", {"no pin \"D14\" on the Arduino Uno"}));
}

TEST(DriveErrors, StepDirOnABoardWithoutTheShield) {
  json doc = shield_robot("a4988", 8);
  doc["board"] = "nano";
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/kind", {"motor \"m0\"", "step-dir needs a CNC shield", "board \"nano\" has none"}));
  // and the other way: 4-wire drivers or servos on a shield.
  doc = base_robot();
  doc["board"] = "nano-cnc-v4";
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/kind", {"sockets of the Arduino Nano on a CNC Shield V4", "not an L298N"}));
  doc = servo_robot();
  doc["board"] = "uno-cnc-v3";
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/kind", {"a servo joint on the Arduino Uno on a CNC Shield V3"}));
  doc = shield_robot("a4988", 8);
  doc["motors"][1]["driver"]["enable"] = "D7";
  EXPECT_TRUE(fails_with(doc, "/motors/1/driver/enable", {"wires every driver's EN to D8, not D7"}));
}

TEST(DriveErrors, ServoPulsesOutside400To2600Us) {
  json doc = servo_robot();
  doc["motors"][0]["driver"]["pulse"] = {300, 2500};
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/pulse/0", {"within 400..2600 us", "got 300"}));
  doc["motors"][0]["driver"]["pulse"] = {500, 2700};
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/pulse/1", {"within 400..2600 us", "got 2700"}));
  doc["motors"][0]["driver"]["pulse"] = {500, 2500};
  doc["motors"][0]["driver"]["at"] = {{1000, -45}, {2800, 45}};
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/at/1/0", {"within 400..2600 us", "got 2800"}));
  // A limit whose angle needs a pulse beyond the range.
  doc = servo_robot();
  doc["motors"][0]["max"] = 95;
  EXPECT_TRUE(fails_with(doc, "/motors/0/max", {"95 deg needs a 2555.6 us pulse", "range 500..2500 us"}));
  doc = servo_robot();
  doc["motors"][0]["driver"]["pulse"] = {500, 2400};
  EXPECT_TRUE(fails_with(doc, "/motors/0/max", {"90 deg needs a 2500 us pulse", "range 500..2400 us"}));
  doc["motors"][0]["driver"]["at"] = {{1000, -45}, {2450, 45}};
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/at/1/0", {"within the pulse range 500..2400 us"}));
  doc = servo_robot();
  doc["motors"][0]["gear"] = {2, 1};
  EXPECT_TRUE(fails_with(doc, "/motors/0/gear", {"a servo motor takes no \"gear\"", "0.5 us ticks"}));
  doc = servo_robot();
  doc["motors"][0]["driver"].erase("speed");
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/speed", {"missing required field \"speed\""}));
}

TEST(DriveErrors, AMicrosteppingTheDriverDoesNotHave) {
  EXPECT_TRUE(fails_with(shield_robot("a4988", 32), "/motors/0/microsteps",
                         {"the A4988 has no 32 microsteps per full step", "it takes 1, 2, 4, 8, 16"}));
  EXPECT_TRUE(fails_with(shield_robot("tmc2209", 4), "/motors/0/microsteps", {"the TMC2209 has no 4", "8, 16, 32, 64"}));
  EXPECT_TRUE(fails_with(shield_robot("tmc2208", 1), "/motors/0/microsteps", {"the TMC2208 has no 1", "2, 4, 8, 16"}));
  json doc = base_robot();
  doc["board"] = "nano";
  doc["motors"][1]["microsteps"] = 4;
  EXPECT_TRUE(fails_with(doc, "/motors/1/microsteps", {"the L298N has no 4", "it takes 1, 2"}));
}

TEST(DriveErrors, BoardsKindsAndChips) {
  json doc = base_robot();
  doc["board"] = "mega";
  EXPECT_TRUE(fails_with(doc, "/board", {"unknown board \"mega\"", "nano, uno, nano-cnc-v4, uno-cnc-v3"}));
  doc = base_robot();
  doc["motors"][2]["driver"] = {{"kind", "uln2003"}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/kind", {"motor \"m2\" is driven by uln2003 but motor \"m0\" by l298n"}));
  doc["motors"][2]["driver"] = {{"kind", "tb6600"}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/kind", {"unknown driver \"tb6600\"", "l298n, uln2003, step-dir, servo"}));
  doc["motors"][2]["driver"] = {{"kind", "l298n"}, {"pin", "D9"}};
  EXPECT_TRUE(fails_with(doc, "/motors/2/driver/pin", {"a l298n driver takes no \"pin\""}));
  doc = shield_robot("a4988", 8);
  doc["motors"][0]["driver"]["chip"] = "l6470";
  EXPECT_TRUE(fails_with(doc, "/motors/0/driver/chip", {"unknown STEP/DIR chip \"l6470\"", "a4988, drv8825, tmc2208, tmc2209"}));
  doc = base_robot();
  doc.erase("motors");
  doc.erase("coupling");
  doc["board"] = "nano";
  EXPECT_TRUE(fails_with(doc, "/board", {"a board needs \"motors\""}));
}

}  // namespace

// ---------------------------------------------------------------- I/O pins

TEST(IoPins, NamedPinsOnFreeHeaderPinsAreWiredAfterTheDrive) {
  const json io = json::parse(R"([{"name": "ready", "pin": "D12", "mode": "output"},
                                  {"name": "go", "pin": "A0", "mode": "input_pullup"},
                                  {"name": "part-in", "pin": "A1", "mode": "input"}])");
  // The servo build leaves every pin its servos, the gripper's, the serial line and the LED do
  // not take: here D9..D11 are the joints' (the file's), D3 the gripper's.
  json servos = servo_robot();
  servos["io"] = io;
  const Robot sr = parse_robot(servos.dump(), "s.json");
  EXPECT_EQ(sr.io.size(), 3u);
  EXPECT_EQ(io_pins_free_text(sr), "D2, D4, D5, D6, D7, D8, D12, A0, A1, A2, A3, A4, A5");
  servos["io"][0]["pin"] = "D3";
  EXPECT_TRUE(fails_with(servos, "/io/0/pin", {"D3"}));
  json doc = json::parse(std::ifstream(kSource + "/robots/mk2plus-cnc.json"));
  doc["io"] = io;
  const Robot r = parse_robot(doc.dump(), "t.json");
  ASSERT_EQ(r.io.size(), 3u);
  EXPECT_EQ(r.io[0].name, "ready");
  EXPECT_EQ(r.io[0].mode, kIoOutput);
  EXPECT_FALSE(r.io[0].input());
  EXPECT_EQ(r.io[1].mode, kIoInputPullup);
  EXPECT_TRUE(r.io[2].input());
  EXPECT_STREQ(board::kHeaderPin[r.io[1].pin].pin, "A0");
  ASSERT_NE(r.io_pin("part-in"), nullptr);
  EXPECT_EQ(r.io_pin("nothing"), nullptr);
  const Wiring w = wire(r);
  EXPECT_EQ(pin_of(w, "I/O \"ready\""), "D12");
  EXPECT_EQ(pin_of(w, "I/O \"go\""), "A0");
}

TEST(IoPins, AStepperArmWithoutANamedBoardIsCheckedOnTheNano) {
  json doc = base_robot();  // three L298Ns: D2..D12 and A0..A4 are the drive's
  doc["io"] = json::parse(R"([{"name": "ready", "pin": "A5", "mode": "output"}])");
  EXPECT_EQ(parse_robot(doc.dump(), "t.json").io.size(), 1u);
  doc["io"][0]["pin"] = "D10";
  EXPECT_TRUE(fails_with(doc, "/io/0/pin", {"pin D10 of the Arduino Nano", "L298N #1 IN3", "I/O \"ready\" output"}));
}

TEST(IoPins, BadPinsAreRefusedByName) {
  json doc = servo_robot();
  doc["io"] = json::parse(R"([{"name": "ready", "pin": "D9", "mode": "output"}])");
  EXPECT_TRUE(fails_with(doc, "/io/0/pin", {"pin D9", "servo signal", "I/O \"ready\""}));
  doc["io"][0]["pin"] = "D0";
  EXPECT_TRUE(fails_with(doc, "/io/0/pin", {"USB serial RX"}));
  doc["io"][0]["pin"] = "D14";
  EXPECT_TRUE(fails_with(doc, "/io/0/pin", {"no pin \"D14\""}));
  doc["io"][0]["pin"] = "A6";
  EXPECT_TRUE(fails_with(doc, "/io/0/pin", {"analog input only"}));
  doc["io"][0]["pin"] = "D12";
  doc["io"][0]["mode"] = "pwm";
  EXPECT_TRUE(fails_with(doc, "/io/0/mode", {"unknown mode \"pwm\"", "output, input, input_pullup"}));
  doc["io"][0]["mode"] = "input";
  doc["io"][0]["name"] = "2fast";
  EXPECT_TRUE(fails_with(doc, "/io/0/name", {"starting with a letter", "\"2fast\""}));
  doc["io"][0]["name"] = "go";
  doc["io"].push_back(json::parse(R"({"name": "go", "pin": "A0", "mode": "output"})"));
  EXPECT_TRUE(fails_with(doc, "/io/1/name", {"duplicate I/O pin name \"go\""}));
  doc["io"][1]["name"] = "stop";
  doc["io"][1]["pin"] = "D12";
  EXPECT_TRUE(fails_with(doc, "/io/1/pin", {"pin D12", "I/O \"go\" input", "I/O \"stop\" output"}));
  doc["io"][1].erase("mode");
  EXPECT_TRUE(fails_with(doc, "/io/1/mode", {"missing required field \"mode\""}));
  doc["io"] = json::array();
  for (const char* pin : {"D4", "D5", "D6", "D7", "D8"})
    doc["io"].push_back({{"name", std::string("p") + pin}, {"pin", pin}, {"mode", "output"}});
  EXPECT_TRUE(fails_with(doc, "/io", {"at most 4 I/O pins (got 5)"}));
}

TEST(IoPins, ARobotWithoutMotorsHasNoBoardForThem) {
  json doc = base_robot();
  doc.erase("motors");
  doc.erase("coupling");
  doc["io"] = json::parse(R"([{"name": "ready", "pin": "D12", "mode": "output"}])");
  EXPECT_TRUE(fails_with(doc, "/io", {"no \"motors\""}));
}
