// articula ik ROBOT --target x,y,z[,roll,pitch,yaw]: joint values for a tool target, the
// solve's status and its remaining error. --targets FILE solves a batch, one JSON line each.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "ik.h"
#include "records_json.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

host::IkTarget make_target(const std::vector<double>& v, const std::string& what) {
  if (v.size() != 3 && v.size() != 6)
    throw UsageError(what + ": x,y,z (mm) or x,y,z,roll,pitch,yaw (mm, deg) expected, " + std::to_string(v.size()) +
                     " numbers given");
  host::IkTarget t = host::IkTarget::at(make_vec3(v[0], v[1], v[2]));
  if (v.size() == 6) {
    t.has_rotation = true;
    t.rotation = rpy_to_matrix(deg_to_rad(v[3]), deg_to_rad(v[4]), deg_to_rad(v[5]));
  }
  return t;
}

// A progress bar on stderr for long batches (only when stderr is a terminal or asked).
void ik_progress(size_t done, size_t total) {
  const int width = 40;
  const int filled = int(width * done / std::max<size_t>(total, 1));
  std::cerr << "\r[" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done << "/" << total
            << (done == total ? "\n" : "") << std::flush;
}

int run_ik(int argc, char** argv) {
  cxxopts::Options opts("articula ik", "Inverse kinematics: joint values that put the tool at a target.");
  opts.custom_help("ROBOT (--target x,y,z[,roll,pitch,yaw] | --targets FILE) [--from q] [--solver NAME] [--json]");
  opts.add_options()("target", "tool position in mm, optionally roll,pitch,yaw in deg (fixed X-Y-Z)",
                     cxxopts::value<std::string>())(
      "targets", "a file with one target a line (same fields, comma-separated); prints one JSON line each",
      cxxopts::value<std::string>())("from", "start pose, joint values in deg/mm (default: home)",
                                     cxxopts::value<std::string>())(
      "solver", "auto (default), lm, jt (the thesis's Jacobian transpose) or closed", cxxopts::value<std::string>())(
      "weights", "IK weight per joint variable (0 freezes a joint)", cxxopts::value<std::string>())(
      "progress", "show a progress bar for --targets even when stderr is not a terminal")(
      "json", "print one JSON document")("h,help", "this help")("robot", "robot file or name",
                                                                cxxopts::value<std::string>());
  opts.parse_positional({"robot"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "Statuses: reached (within 0.01 mm, 1e-4 rad), unreachable (the arm stretches toward the target;\n"
                 "the error says how far it stays), limited (a joint or motor limit holds it back), budget (the\n"
                 "iteration budget ran out). Exit code 0 when every target is reached, 1 otherwise. docs/ik.md.\n";
    return 0;
  }
  if (!args.count("robot")) throw UsageError("no robot given");
  if (args.count("target") == args.count("targets")) throw UsageError("give either --target or --targets");
  const host::Robot r = host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>()));
  const int n = r.model.num_joints;
  std::vector<double> start = r.home;
  if (args.count("from")) {
    const std::vector<double> v = parse_number_list(args["from"].as<std::string>(), "--from");
    if (int(v.size()) != n)
      throw UsageError("--from: " + r.name + " has " + std::to_string(n) + " joint variables, " +
                       std::to_string(v.size()) + " values given");
    for (int k = 0; k < n; ++k) start[k] = joint_to_model(r, k, v[k]);
  }
  host::IkOptions options;
  if (args.count("solver") && !host::parse_ik_method(args["solver"].as<std::string>(), options.method))
    throw UsageError("--solver: '" + args["solver"].as<std::string>() + "' is not auto, lm, jt or closed");
  if (args.count("weights")) options.weights = parse_number_list(args["weights"].as<std::string>(), "--weights");
  host::InverseKinematics ik(r);

  auto solve = [&](const host::IkTarget& t, const std::vector<double>& from) {
    try {
      return ik.solve(t, from, options);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  };

  if (args.count("target")) {
    const host::IkTarget t = make_target(parse_number_list(args["target"].as<std::string>(), "--target"), "--target");
    const host::IkResult res = solve(t, start);
    if (args.count("json")) {
      std::cout << host::ik_result_json(r, res).dump(2) << '\n';
      return res.reached() ? 0 : 1;
    }
    std::cout << r.name << ": " << host::ik_status_name(res.status) << " (" << host::ik_method_name(res.method)
              << ", " << res.iterations << " iterations)\n";
    Table table({"joint", "value", "unit"});
    for (int k = 0; k < n; ++k)
      table.add({r.joint_names[k], fmt(joint_from_model(r, k, res.q[k])), joint_unit(r, k)});
    std::cout << table.str() << "tool at (" << fmt(res.tool.p.x) << ", " << fmt(res.tool.p.y) << ", " << fmt(res.tool.p.z)
              << ") mm, position error " << fmt(res.position_error_mm, 4) << " mm";
    if (t.has_rotation)
      std::cout << ", orientation error " << fmt(rad_to_deg(res.orientation_error_rad), 4) << " deg";
    std::cout << '\n';
    return res.reached() ? 0 : 1;
  }

  const std::string path = args["targets"].as<std::string>();
  std::ifstream f(path);
  if (!f) throw UsageError("cannot read " + path);
  std::vector<std::pair<int, host::IkTarget>> targets;
  std::string line;
  for (int no = 1; std::getline(f, line); ++no) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = path + ":" + std::to_string(no);
    targets.push_back({no, make_target(parse_number_list(line, where), where)});
  }
  const bool show = targets.size() >= 100 && (args.count("progress") || isatty(2));
  int reached = 0;
  for (size_t i = 0; i < targets.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const host::IkResult res = solve(targets[i].second, start);
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json j = host::ik_result_json(r, res);
    j["line"] = targets[i].first;
    j["solve_us"] = us;
    std::cout << j.dump() << '\n';
    reached += res.reached();
    if (show && (i % 50 == 49 || i + 1 == targets.size())) ik_progress(i + 1, targets.size());
  }
  std::cerr << reached << " of " << targets.size() << " targets reached\n";
  return reached == int(targets.size()) ? 0 : 1;
}

}  // namespace

int cmd_ik(int argc, char** argv) { return run_ik(argc, argv); }

}  // namespace articula::cli
