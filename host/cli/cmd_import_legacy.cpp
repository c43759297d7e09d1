// articula import-legacy FILE: the original system's robot text file (thesis appendix C)
// as a robot file; what does not map is listed on stderr.
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli_util.h"
#include "commands.h"
#include "legacy.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

int run_import_legacy(int argc, char** argv) {
  cxxopts::Options opts("articula import-legacy",
                        "Converts a robot file of the original system (thesis appendix C) into a robot file "
                        "(robots/README.md), keeping what maps and listing what does not.");
  opts.custom_help("FILE [--scale MM] [-o OUT.json]");
  opts.add_options()("scale", "millimetres per unit of the old file (the thesis's MK2 model: 25.75)",
                     cxxopts::value<double>()->default_value("10"))(
      "o,output", "write the robot file here (default: standard output)", cxxopts::value<std::string>())(
      "h,help", "this help")("file", "the old robot file", cxxopts::value<std::string>());
  opts.parse_positional({"file"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "Theta and alpha flagged variable become joint variables with limits -180..180 (the original\n"
                 "had none); models, scales and drawing offsets have no place in a robot file and are listed.\n";
    return 0;
  }
  if (!args.count("file")) throw UsageError("no legacy file given");
  const std::string path = args["file"].as<std::string>();
  std::ifstream f(path);
  if (!f) throw UsageError("cannot read " + path);
  std::ostringstream text;
  text << f.rdbuf();
  host::LegacyImport imp;
  try {
    imp = host::import_legacy(text.str(), path, args["scale"].as<double>());
    host::parse_robot(imp.robot.dump(), path);  // what we write must load
  } catch (const host::LegacyError& e) {
    throw UsageError(e.what());
  }
  const std::string json = imp.robot.dump(2) + "\n";
  if (args.count("output")) {
    const std::string out = args["output"].as<std::string>();
    std::ofstream o(out);
    if (!(o << json)) throw UsageError("cannot write " + out);
    std::cerr << "wrote " << out << '\n';
  } else {
    std::cout << json;
  }
  std::cerr << imp.dropped.size() << " things in " << path << " have no place in a robot file:\n";
  for (const auto& d : imp.dropped) std::cerr << "  " << d << '\n';
  return 0;
}

}  // namespace

int cmd_import_legacy(int argc, char** argv) { return run_import_legacy(argc, argv); }

}  // namespace articula::cli
