// articula fk ROBOT --q v1,v2,...: every frame and the tool pose.
#include <cxxopts.hpp>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

nlohmann::json pose_json(const Transform<double>& T) {
  const Vec3<double> rpy = matrix_to_rpy(T.R);
  nlohmann::json R = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) R.push_back({T.R.m[i][0], T.R.m[i][1], T.R.m[i][2]});
  return {{"position", {T.p.x, T.p.y, T.p.z}},
          {"rotation", R},
          {"rpy", {rad_to_deg(rpy.x), rad_to_deg(rpy.y), rad_to_deg(rpy.z)}}};
}

int run_fk(int argc, char** argv) {
  cxxopts::Options opts("articula fk", "Forward kinematics: every DH frame and the tool pose for given joint values.");
  opts.custom_help("ROBOT [--q v1,v2,...] [--json]");
  opts.add_options()("q", "(--q) joint values in model order, deg (mm for d variables); default: the home pose",
                     cxxopts::value<std::string>())("json", "print one JSON document")("h,help", "this help")(
      "robot", "robot file or shipped robot name", cxxopts::value<std::string>());
  opts.parse_positional({"robot"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "Roll/pitch/yaw are fixed X-Y-Z angles: R = Rz(yaw) * Ry(pitch) * Rx(roll).\n"
                 "Joint limits are not enforced here; values outside them are reported.\n";
    return 0;
  }
  if (!args.count("robot")) throw UsageError("no robot given");
  const host::Robot r = host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>()));
  const int n = r.model.num_joints;
  std::vector<double> q = r.home;
  if (args.count("q")) {
    const std::vector<double> v = parse_number_list(args["q"].as<std::string>(), "--q");
    if (int(v.size()) != n)
      throw UsageError("--q: " + r.name + " has " + std::to_string(n) + " joint variables, " +
                       std::to_string(v.size()) + " values given");
    for (int k = 0; k < n; ++k) q[k] = joint_to_model(r, k, v[k]);
  }
  std::vector<std::string> outside;
  for (int k = 0; k < n; ++k)
    if (q[k] < r.model.joints[k].lo || q[k] > r.model.joints[k].hi) outside.push_back(r.joint_names[k]);

  host::HostFrames f;
  forward_kinematics(f, r.model, q.data());

  if (args.count("json")) {
    nlohmann::json j;
    j["robot"] = r.name;
    for (int k = 0; k < n; ++k) j["q"].push_back(joint_from_model(r, k, q[k]));
    j["outside_limits"] = outside;
    for (int i = 0; i < f.count; ++i) j["frames"].push_back(pose_json(f.T_base_frame[i]));
    j["tool"] = pose_json(f.T_base_tool);
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::cout << r.name << " at q = (";
  for (int k = 0; k < n; ++k) std::cout << (k ? ", " : "") << fmt(joint_from_model(r, k, q[k]));
  std::cout << ")\n";
  for (const auto& name : outside) std::cout << "note: " << name << " is outside its limits\n";
  Table t({"frame", "x mm", "y mm", "z mm", "roll deg", "pitch deg", "yaw deg"});
  auto add = [&](const std::string& name, const Transform<double>& T) {
    const Vec3<double> rpy = matrix_to_rpy(T.R);
    t.add({name, fmt(T.p.x), fmt(T.p.y), fmt(T.p.z), fmt(rad_to_deg(rpy.x)), fmt(rad_to_deg(rpy.y)),
           fmt(rad_to_deg(rpy.z))});
  };
  for (int i = 0; i < f.count; ++i) add(i == 0 ? "base" : std::to_string(i), f.T_base_frame[i]);
  add("tool", f.T_base_tool);
  std::cout << t.str() << "tool rotation matrix:\n";
  for (int i = 0; i < 3; ++i)
    std::cout << "  [" << fmt(f.T_base_tool.R.m[i][0], 6) << ", " << fmt(f.T_base_tool.R.m[i][1], 6) << ", "
              << fmt(f.T_base_tool.R.m[i][2], 6) << "]\n";
  return 0;
}

}  // namespace

int cmd_fk(int argc, char** argv) { return run_fk(argc, argv); }

}  // namespace articula::cli
