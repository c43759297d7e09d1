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
#include "quantize.h"
#include "records_json.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

struct Line {
  std::string text;
  std::string where;  // "file:line" or "argument N"
};

int run_quantize(int argc, char** argv) {
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

  std::vector<std::string> texts;
  for (const Line& line : lines) texts.push_back(line.text);
  const std::vector<host::QuantizeRecord> records = host::quantize_lines(r, texts);
  const bool json = args.count("json") > 0;
  Table table({"line", "command", "reply", "motor", "commanded deg", "steps", "reached deg", "error deg", "tool x",
               "tool y", "tool z", "tool error mm"});
  const char* const kNotSimulated = "not simulated by quantize";
  int rejected = 0, not_simulated = 0;
  double worst_mm = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const host::QuantizeRecord& q = records[i];
    const Line& line = lines[i];
    if (!q.simulated) ++not_simulated;
    if (q.reply != kOk) ++rejected;
    if (q.moved()) worst_mm = std::max(worst_mm, q.tool_error_mm);
    if (json) {
      nlohmann::json j = host::quantize_record_json(r, q);
      j["where"] = line.where;
      if (!q.simulated) j["note"] = kNotSimulated;
      std::cout << j.dump() << '\n';
    } else {
      const bool moved = q.moved();
      const Vec3<double>& p = q.tool_quantized;
      table.add({line.where, line.text, q.reply == kOk ? "ok" : "error:" + std::to_string(int(q.reply)),
                 moved ? r.motor_names[size_t(q.motor)] : "", moved ? fmt(q.commanded_deg) : "",
                 moved ? std::to_string(q.steps) : "", moved ? fmt(q.reached_deg, 4) : "",
                 moved ? fmt(q.reached_deg - q.commanded_deg, 4) : "", fmt(p.x), fmt(p.y), fmt(p.z),
                 fmt(q.tool_error_mm, 3)});
      if (q.reply != kOk)
        std::cerr << line.where << ": '" << line.text << "': error:" << int(q.reply) << " " << status_text(q.reply)
                  << " (nothing moved)\n";
      if (!q.simulated)
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

int cmd_quantize(int argc, char** argv) { return run_quantize(argc, argv); }

}  // namespace articula::cli
