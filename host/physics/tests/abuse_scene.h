// host/physics/tests/abuse_scene.h - the abuse test's world: every shipped robot, a scene of
// objects all round it within its reach, and random commands (seeded) across its whole range.
// test_abuse.cpp checks what the physics does with them; bench/bench_physics.cpp times them.
#ifndef ARTICULA_PHYSICS_ABUSE_SCENE_H
#define ARTICULA_PHYSICS_ABUSE_SCENE_H

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "program.h"
#include "robot_file.h"
#include "sim.h"

namespace articula::host::abuse {

// Every robot file in robots/, sorted by name.
inline std::vector<std::string> shipped_robot_files(const std::string& source_dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(source_dir + "/robots"))
    if (e.path().extension() == ".json" && e.path().filename() != "robot.schema.json") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

inline double reach_mm(const Robot& r) {
  double reach = std::fabs(r.model.T_last_tool.p.x) + std::fabs(r.model.T_last_tool.p.y) + std::fabs(r.model.T_last_tool.p.z);
  for (int i = 0; i < r.model.num_rows; ++i) reach += std::fabs(r.model.rows[i].a) + std::fabs(r.model.rows[i].d);
  return reach;
}

// Objects all round the arm within its reach: cubes, a ball, a can, a static pillar and table.
inline Scene busy_scene(double reach) {
  Scene s;
  const double r = 0.55 * reach, size = std::clamp(0.12 * reach, 20.0, 80.0);
  for (int k = 0; k < 6; ++k) {
    SceneObject o;
    o.name = "thing " + std::to_string(k);
    const double a = k * M_PI / 3;
    o.xyz = make_vec3(r * std::cos(a), r * std::sin(a), size / 2);
    o.movable = k < 4;
    o.mass = 0.05 + 0.05 * k;
    o.type = k == 1 ? SceneObject::Type::kSphere : k == 2 ? SceneObject::Type::kCylinder : SceneObject::Type::kBox;
    o.size = {size, size, size};
    if (k == 1) o.size = {size / 2, 0, 0};
    if (k == 2) o.size = {size / 2, size, 0};
    if (k == 4) o.size = {size, size, 3 * size}, o.xyz.z = 1.5 * size;  // a pillar
    if (k == 5) o.size = {2 * size, 2 * size, size};                   // a low table
    s.objects.push_back(o);
  }
  SceneObject stack = s.objects[0];  // a cube on another
  stack.name = "stacked";
  stack.xyz.z += stack.size[2];
  s.objects.push_back(stack);
  return s;
}

inline std::string random_program(const Robot& r, std::mt19937& rng, int commands) {
  std::ostringstream p;
  std::uniform_real_distribution<double> u(0, 1);
  if (r.has_motors) {
    for (int c = 0; c < commands; ++c) {
      if (u(rng) < 0.2) {
        p << "G " << int(u(rng) * 100) << "\n";
        continue;
      }
      p << "M";
      for (int m = 0; m < r.actuation.num_motors; ++m) {
        const MotorSpec& ms = r.actuation.motors[m];
        p << " " << (ms.min + u(rng) * (ms.max - ms.min)) / 1000.0;
      }
      p << "\n";
    }
  } else {
    for (int c = 0; c < commands; ++c) {
      if (r.gripper.present && u(rng) < 0.2) {
        p << "h\n" << 0.5 * u(rng) << "\n";
        continue;
      }
      p << "m\n";
      for (int j = 0; j < r.model.num_joints; ++j) {
        const JointSpec<double>& js = r.model.joints[j];
        const double v = js.lo + u(rng) * (js.hi - js.lo);
        p << (js.param == kParamD ? v : v * 180 / M_PI) << "\n";
      }
    }
  }
  return p.str();
}

// Faster and harder than the defaults: 180 deg/s, 900 steps/s, 4,000 steps/s^2.
inline SimOptions options() {
  SimOptions o;
  o.joints.speed_deg = 180;
  o.joints.speed_mm = 300;
  o.settings.value[ControllerSettings::kMaxRate] = 900;  // faster than the default 600
  o.settings.value[ControllerSettings::kAccel] = 4000;
  return o;
}

// The robot's random program (25 commands), parsed.
inline Program random_commands(const Robot& r, std::mt19937& rng) {
  const std::string text = random_program(r, rng, 25);
  return r.has_motors ? parse_protocol_program(text, "abuse.arm", r) : parse_robosim(text, "abuse.robosim", r);
}

// The seed of the whole run: every robot in turn takes its program from one generator.
constexpr unsigned kSeed = 20240505;

}  // namespace articula::host::abuse

#endif  // ARTICULA_PHYSICS_ABUSE_SCENE_H
