// articula info ROBOT: the DH table as in thesis Tables 1 and 2, the joint variables and
// their limits, the motors and their resolution, and the reach.
#include <cmath>
#include <cxxopts.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "cli_util.h"
#include "commands.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

const char* param_name(uint8_t p) { return p == kParamTheta ? "theta" : (p == kParamD ? "d" : "alpha"); }

// The cell of one DH parameter: its constant, the joint's name, or the linked formula.
// Only theta, d and alpha can vary; a(i-1) is always a constant (length_cell).
std::string param_cell(const host::Robot& r, int row, uint8_t param, double constant, bool angle) {
  for (int j = 0; j < r.model.num_joints; ++j)
    if (r.model.joints[j].row == row && r.model.joints[j].param == param) return r.joint_names[j];
  for (int k = 0; k < r.model.num_linked; ++k) {
    const auto& l = r.model.linked[k];
    if (l.row != row || l.param != param) continue;
    std::string s;
    for (int j = 0; j < r.model.num_joints; ++j) {
      if (l.gain[j] == 0) continue;
      const double g = l.gain[j];
      s += s.empty() ? (g < 0 ? "-" : "") : (g < 0 ? " - " : " + ");
      if (std::fabs(g) != 1) s += fmt(std::fabs(g), 3) + "*";
      s += r.joint_names[j];
    }
    if (l.offset != 0) s += (l.offset < 0 ? " - " : " + ") + fmt(std::fabs(angle ? rad_to_deg(l.offset) : l.offset), 3);
    return s.empty() ? "0" : s;
  }
  return fmt(angle ? rad_to_deg(constant) : constant, 3);
}

// Words re-flowed into lines of at most `width` characters.
std::string wrap(const std::string& text, size_t width) {
  std::istringstream words(text);
  std::string word, line, out;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + '\n';
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  return line.empty() ? out : out + line + '\n';
}

std::string length_cell(double a) { return fmt(a, 3); }

struct Reach {
  double horizontal = 0, highest = -1e300, lowest = 1e300;
  int poses = 0;
};

// Sampled over in-limit poses: the limits' corners and random poses inside them.
Reach sample_reach(const host::Robot& r) {
  Reach out;
  const int n = r.model.num_joints;
  std::mt19937 rng(1);
  std::vector<double> q(n);
  auto visit = [&]() {
    const Vec3<double> p = tool_position(r.model, q.data());
    out.horizontal = std::max(out.horizontal, std::hypot(p.x, p.y));
    out.highest = std::max(out.highest, p.z);
    out.lowest = std::min(out.lowest, p.z);
    ++out.poses;
  };
  if (n <= 10)
    for (int corner = 0; corner < (1 << n); ++corner) {
      for (int j = 0; j < n; ++j) q[j] = (corner >> j) & 1 ? r.model.joints[j].hi : r.model.joints[j].lo;
      visit();
    }
  for (int i = 0; i < 20000; ++i) {
    for (int j = 0; j < n; ++j)
      q[j] = std::uniform_real_distribution<double>(r.model.joints[j].lo, r.model.joints[j].hi)(rng);
    visit();
  }
  return out;
}

int run_info(int argc, char** argv) {
  cxxopts::Options opts("articula info", "Shows a robot: its DH table, joint variables, limits, motors and reach.");
  const std::optional<OneRobot> one = one_robot_command(opts, argc, argv, "mk2plus");
  if (!one) return 0;
  const host::Robot& r = one->robot;
  const auto& m = r.model;
  const Reach reach = sample_reach(r);

  if (one->json) {
    nlohmann::json j;
    j["name"] = r.name;
    j["file"] = r.source;
    for (int i = 0; i < m.num_rows; ++i)
      j["dh"].push_back({{"row", i + 1},
                         {"a", length_cell(m.rows[i].a)},
                         {"alpha", param_cell(r, i, kParamAlpha, m.rows[i].alpha, true)},
                         {"d", param_cell(r, i, kParamD, m.rows[i].d, false)},
                         {"theta", param_cell(r, i, kParamTheta, m.rows[i].theta, true)}});
    for (int k = 0; k < m.num_joints; ++k)
      j["joints"].push_back({{"name", r.joint_names[k]},
                             {"row", m.joints[k].row + 1},
                             {"parameter", param_name(m.joints[k].param)},
                             {"unit", joint_unit(r, k)},
                             {"min", joint_from_model(r, k, m.joints[k].lo)},
                             {"max", joint_from_model(r, k, m.joints[k].hi)},
                             {"home", joint_from_model(r, k, r.home[k])}});
    if (r.has_motors)
      for (int k = 0; k < r.actuation.num_motors; ++k) {
        const MotorSpec& ms = r.actuation.motors[k];
        j["motors"].push_back({{"name", r.motor_names[k]},
                               {"steps_per_rev", ms.full_steps_per_rev},
                               {"microsteps", ms.microsteps},
                               {"gear", {ms.gear_num, ms.gear_den}},
                               {"direction", ms.direction},
                               {"zero", ms.zero / 1000.0},
                               {"min", ms.min / 1000.0},
                               {"max", ms.max / 1000.0},
                               {"deg_per_step", degrees_per_step<double>(ms)},
                               {"min_steps", min_steps(ms)},
                               {"max_steps", max_steps(ms)}});
      }
    j["reach"] = {{"horizontal_mm", reach.horizontal},
                  {"highest_mm", reach.highest},
                  {"lowest_mm", reach.lowest},
                  {"sampled_poses", reach.poses}};
    std::cout << j.dump(2) << '\n';
    return 0;
  }

  std::cout << r.name << "  (" << r.source << ")\n";
  if (!r.description.empty()) std::cout << wrap(r.description, 90);
  std::cout << "\nDH table (modified DH, Craig): row i holds a(i-1), alpha(i-1), d(i), theta(i)\n";
  Table dh({"row", "a(i-1) mm", "alpha(i-1) deg", "d(i) mm", "theta(i) deg"});
  for (int i = 0; i < m.num_rows; ++i)
    dh.add({std::to_string(i + 1), length_cell(m.rows[i].a),
            param_cell(r, i, kParamAlpha, m.rows[i].alpha, true), param_cell(r, i, kParamD, m.rows[i].d, false),
            param_cell(r, i, kParamTheta, m.rows[i].theta, true)});
  std::cout << dh.str();
  const Vec3<double> rpy = matrix_to_rpy(m.T_last_tool.R);
  std::cout << "tool after row " << int(m.num_rows) << ": xyz (" << fmt(m.T_last_tool.p.x) << ", "
            << fmt(m.T_last_tool.p.y) << ", " << fmt(m.T_last_tool.p.z) << ") mm, rpy (" << fmt(rad_to_deg(rpy.x))
            << ", " << fmt(rad_to_deg(rpy.y)) << ", " << fmt(rad_to_deg(rpy.z)) << ") deg\n";

  std::cout << "\nJoint variables\n";
  Table jt({"#", "name", "parameter", "min", "max", "home", "unit"});
  for (int k = 0; k < m.num_joints; ++k)
    jt.add({std::to_string(k), r.joint_names[k],
            std::string(param_name(m.joints[k].param)) + std::to_string(m.joints[k].row + 1),
            fmt(joint_from_model(r, k, m.joints[k].lo)), fmt(joint_from_model(r, k, m.joints[k].hi)),
            fmt(joint_from_model(r, k, r.home[k])), joint_unit(r, k)});
  std::cout << jt.str();

  if (r.has_motors) {
    std::cout << "\nMotors (angles at the gear's output; step 0 is the zero angle)\n";
    Table mt({"#", "name", "steps/rev", "microsteps", "gear", "dir", "zero deg", "min deg", "max deg", "deg/step",
              "steps"});
    for (int k = 0; k < r.actuation.num_motors; ++k) {
      const MotorSpec& ms = r.actuation.motors[k];
      mt.add({std::to_string(k), r.motor_names[k], std::to_string(ms.full_steps_per_rev),
              std::to_string(ms.microsteps), std::to_string(ms.gear_num) + "/" + std::to_string(ms.gear_den),
              ms.direction > 0 ? "+1" : "-1", fmt(ms.zero / 1000.0), fmt(ms.min / 1000.0), fmt(ms.max / 1000.0),
              fmt(degrees_per_step<double>(ms), 4),
              std::to_string(min_steps(ms)) + ".." + std::to_string(max_steps(ms))});
    }
    std::cout << mt.str();
    bool identity = true;
    for (int a = 0; a < m.num_joints; ++a)
      for (int b = 0; b < m.num_joints; ++b) identity = identity && r.actuation.coupling[a][b] == (a == b ? 1 : 0);
    if (!identity) {
      std::cout << "coupling, joint = C * motor angle:\n";
      for (int a = 0; a < m.num_joints; ++a) {
        std::cout << "  " << r.joint_names[a] << " =";
        bool first = true;
        for (int b = 0; b < m.num_joints; ++b) {
          const double c = r.actuation.coupling[a][b];
          if (c == 0) continue;
          std::cout << (first ? (c < 0 ? " -" : " ") : (c < 0 ? " - " : " + "));
          if (std::fabs(c) != 1) std::cout << fmt(std::fabs(c)) << "*";
          std::cout << r.motor_names[b];
          first = false;
        }
        std::cout << '\n';
      }
    }
  } else {
    std::cout << "\nNo motors: a kinematic model only.\n";
  }
  std::cout << "\nReach within the limits (" << reach.poses << " poses sampled): " << fmt(reach.horizontal, 1)
            << " mm horizontally, tool height " << fmt(reach.lowest, 1) << " .. " << fmt(reach.highest, 1)
            << " mm\n";
  return 0;
}

}  // namespace

int cmd_info(int argc, char** argv) { return run_info(argc, argv); }

}  // namespace articula::cli
