// articula quantize ROBOT LINE...: runs protocol lines (docs/protocol.md) through the same
// codec and step quantization the firmware uses, and shows what whole motor steps make of
// each move: the steps, the angle they really give, and the tool position error in mm.
#include <articula/protocol.h>

#include <cmath>
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

struct Line {
  std::string text;
  std::string where;  // "file:line" or "argument N"
};

int run(int argc, char** argv) {
  cxxopts::Options opts("articula quantize",
                        "Shows what whole motor steps make of protocol moves: for each line, the steps, the angle "
                        "reached and the tool position error it leaves.");
  opts.custom_help("ROBOT [LINE...] [--file PROGRAM] [--json]");
  opts.add_options()("file", "read protocol lines from a file ('-' for standard input)", cxxopts::value<std::string>())(
      "json", "one JSON line per protocol line")("h,help", "this help")(
      "robot", "robot file or shipped robot name", cxxopts::value<std::string>())(
      "lines", "protocol lines, e.g. \"L 0 10\"", cxxopts::value<std::vector<std::string>>());
  opts.parse_positional({"robot", "lines"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "The arm starts with every motor at step 0 (its zero angle). Each `L <joint> <deg>` turns one\n"
                 "motor's joint by a relative angle; the commanded angle is kept exactly and quantized once,\n"
                 "nearest step, ties away from zero (shared/articula/actuation.h). A rejected line moves nothing.\n"
                 "Only L and S are simulated; the other commands (M, P, G, H, Z, I, $) are parsed and checked\n"
                 "like the firmware does, then reported as not simulated by quantize (they move nothing and\n"
                 "do not count as rejected).\n";
    return 0;
  }
  if (!args.count("robot")) throw UsageError("no robot given");
  const host::Robot r = host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>()));
  if (!r.has_motors) throw UsageError(r.name + " has no motors in " + r.source + ": nothing to quantize");

  std::vector<Line> lines;
  if (args.count("lines")) {
    int i = 0;
    for (const auto& s : args["lines"].as<std::vector<std::string>>()) lines.push_back({s, "argument " + std::to_string(++i)});
  }
  if (args.count("file")) {
    const std::string path = args["file"].as<std::string>();
    std::ifstream file;
    std::istream* in = &std::cin;
    if (path != "-") {
      file.open(path);
      if (!file) throw UsageError("cannot read " + path);
      in = &file;
    }
    std::string s;
    for (int n = 1; std::getline(*in, s); ++n) lines.push_back({s, (path == "-" ? "stdin" : path) + ":" + std::to_string(n)});
  }
  if (lines.empty()) throw UsageError("no protocol lines given (arguments or --file)");

  const int n = r.actuation.num_motors;
  MotorState<host::kMaxJoints> state;
  reset(state, r.actuation);
  const bool json = args.count("json") > 0;
  Table table({"line", "command", "reply", "motor", "commanded deg", "steps", "reached deg", "error deg", "tool x",
               "tool y", "tool z", "tool error mm"});
  const char* const kNotSimulated = "not simulated by quantize";
  int rejected = 0, not_simulated = 0;
  double worst_mm = 0;
  for (const Line& line : lines) {
    Command cmd;
    Status st = line.text.size() > 255 ? kLineTooLong
                                       : parse_line(cmd, line.text.data(), uint8_t(line.text.size()), uint8_t(n));
    int motor = -1;
    if (st == kOk && cmd.type == kCmdRotate) {
      motor = cmd.arg[0];
      st = move_relative(state, r.actuation, uint8_t(motor), cmd.arg[1]);
    }
    // A valid line quantize has no model for (M, P, G, H, Z, I, $): accepted, nothing moves.
    const bool simulated = st != kOk || cmd.type == kCmdNone || cmd.type == kCmdRotate || cmd.type == kCmdGripper;
    if (!simulated) ++not_simulated;
    // Ideal: the exact commanded angles; quantized: the steps.
    std::vector<double> u(n), q_ideal(n), q_real(n);
    for (int k = 0; k < n; ++k) u[k] = deg_to_rad(state.commanded[k] / 1000.0);
    joints_from_actuators(q_ideal.data(), r.actuation, u.data());
    joints_from_steps(q_real.data(), r.actuation, state.steps);
    const Vec3<double> p_ideal = tool_position(r.model, q_ideal.data());
    const Vec3<double> p_real = tool_position(r.model, q_real.data());
    const double err_mm = norm(p_real - p_ideal);
    if (st != kOk) ++rejected;
    if (motor >= 0 && st == kOk) worst_mm = std::max(worst_mm, err_mm);
    const std::string reply = st == kOk ? "ok" : "error:" + std::to_string(int(st)) + " " + status_text(st);
    const bool moved = st == kOk && motor >= 0;
    const double cmd_deg = moved ? state.commanded[motor] / 1000.0 : 0;
    const double real_deg = moved ? steps_to_degrees<double>(r.actuation.motors[motor], state.steps[motor]) : 0;
    if (json) {
      nlohmann::json j = {{"where", line.where}, {"line", line.text}, {"reply", st == kOk ? "ok" : "error"},
                          {"code", int(st)}};
      if (st != kOk) j["error"] = status_text(st);
      if (!simulated) j["note"] = kNotSimulated;
      if (moved) {
        j["motor"] = r.motor_names[motor];
        j["commanded_deg"] = cmd_deg;
        j["steps"] = state.steps[motor];
        j["reached_deg"] = real_deg;
        j["error_deg"] = real_deg - cmd_deg;
      }
      j["all_steps"] = std::vector<int32_t>(state.steps, state.steps + n);
      j["tool_ideal_mm"] = {p_ideal.x, p_ideal.y, p_ideal.z};
      j["tool_quantized_mm"] = {p_real.x, p_real.y, p_real.z};
      j["tool_error_mm"] = err_mm;
      std::cout << j.dump() << '\n';
    } else {
      table.add({line.where, line.text, st == kOk ? "ok" : "error:" + std::to_string(int(st)),
                 moved ? r.motor_names[motor] : "", moved ? fmt(cmd_deg) : "", moved ? std::to_string(state.steps[motor]) : "",
                 moved ? fmt(real_deg, 4) : "", moved ? fmt(real_deg - cmd_deg, 4) : "", fmt(p_real.x), fmt(p_real.y),
                 fmt(p_real.z), fmt(err_mm, 3)});
      if (st != kOk) std::cerr << line.where << ": '" << line.text << "': " << reply << " (nothing moved)\n";
      if (!simulated)
        std::cerr << line.where << ": '" << line.text << "': ok, " << kNotSimulated << " (nothing moved)\n";
    }
  }
  if (!json) {
    std::cout << r.name << ": " << lines.size() << " lines, " << rejected << " rejected";
    if (not_simulated) std::cout << ", " << not_simulated << " not simulated";
    std::cout << '\n' << table.str();
    std::cout << "worst tool position error from whole steps: " << fmt(worst_mm, 3) << " mm\n";
  }
  return rejected ? 1 : 0;
}

}  // namespace

int cmd_quantize(int argc, char** argv) { return run(argc, argv); }

}  // namespace articula::cli
