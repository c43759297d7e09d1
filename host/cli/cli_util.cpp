#include "cli_util.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <sstream>

#include "program.h"
#include "robot_file.h"

namespace articula::cli {

std::vector<double> parse_number_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  int index = 0;
  while (std::getline(ss, item, ',')) {
    ++index;
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (item.empty() || used != item.size() || !std::isfinite(v))
      throw UsageError(what + ": entry " + std::to_string(index) + " ('" + item + "') is not a finite number");
    out.push_back(v);
  }
  if (out.empty()) throw UsageError(what + ": no numbers given");
  return out;
}

std::string fmt_g(double v, int significant) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", significant, v);
  return buf;
}

std::string output_format(const cxxopts::ParseResult& args) {
  if (args.count("json")) return "json";
  if (args.count("csv")) return "csv";
  const std::string path = args.count("output") ? args["output"].as<std::string>() : "";
  auto ends_with = [&](const std::string& tail) {
    return path.size() > tail.size() && path.compare(path.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends_with(".json")) return "json";
  if (ends_with(".csv")) return "csv";
  return "table";
}

void write_output(const std::string& path, const std::string& text) {
  if (path.empty()) {
    std::cout << text;
    return;
  }
  std::ofstream f(path);
  if (!f || !(f << text)) throw UsageError("cannot write '" + path + "'");
}

std::string fmt(double v, int decimals) {
  if (std::fabs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0;  // no "-0.000"
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string Table::str() const {
  std::vector<size_t> width;
  for (const auto& r : rows_)
    for (size_t c = 0; c < r.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], r[c].size());
    }
  auto numeric = [](const std::string& s) {
    return !s.empty() && (std::isdigit(static_cast<unsigned char>(s[0])) || ((s[0] == '-' || s[0] == '+') && s.size() > 1));
  };
  std::ostringstream os;
  for (size_t i = 0; i < rows_.size(); ++i) {
    const auto& r = rows_[i];
    for (size_t c = 0; c < r.size(); ++c) {
      const std::string pad(width[c] - r[c].size(), ' ');
      if (c) os << "  ";
      os << (i > 0 && numeric(r[c]) ? pad + r[c] : r[c] + (c + 1 < r.size() ? pad : ""));
    }
    os << '\n';
    if (i == 0) {
      for (size_t c = 0; c < width.size(); ++c) os << (c ? "  " : "") << std::string(width[c], '-');
      os << '\n';
    }
  }
  return os.str();
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

namespace {
// cxxopts wants long options of two letters or more; the CLI's documented spelling uses one
// (--q), so "--q VALUE" and "--q=VALUE" become the short form "-q VALUE" before parsing.
std::vector<std::string> normalise_args(int argc, char** argv) {
  std::vector<std::string> out;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.size() >= 3 && a[0] == '-' && a[1] == '-' && std::isalpha(static_cast<unsigned char>(a[2])) &&
        (a.size() == 3 || a[3] == '=')) {
      out.push_back(std::string("-") + a[2]);
      if (a.size() > 4) out.push_back(a.substr(4));
    } else {
      out.push_back(a);
    }
  }
  return out;
}
}  // namespace

int guarded(const char* command, int (*body)(int, char**), int argc, char** argv) {
  try {
    std::vector<std::string> args = normalise_args(argc, argv);
    std::vector<char*> ptrs;
    for (auto& a : args) ptrs.push_back(a.data());
    ptrs.push_back(nullptr);
    return body(int(args.size()), ptrs.data());
  } catch (const host::RobotFileError& e) {
    std::cerr << "articula " << command << ": " << e.what() << '\n';
  } catch (const host::ProgramError& e) {  // a line for each line that cannot be read
    std::istringstream lines(e.what());
    for (std::string l; std::getline(lines, l);) std::cerr << "articula " << command << ": " << l << '\n';
  } catch (const UsageError& e) {
    std::cerr << "articula " << command << ": " << e.what() << " (see: articula " << command << " --help)\n";
  } catch (const cxxopts::exceptions::exception& e) {
    std::cerr << "articula " << command << ": " << e.what() << " (see: articula " << command << " --help)\n";
  }
  return 2;
}

host::Robot robot_argument(const cxxopts::ParseResult& args) {
  if (!args.count("robot")) throw UsageError("no robot given");
  if (!args.count("program")) throw UsageError("no program given");
  if (args.count("json") && args.count("csv")) throw UsageError("--json and --csv exclude each other");
  return host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>()));
}

std::optional<OneRobot> one_robot_command(cxxopts::Options& opts, int argc, char** argv, const char* example) {
  opts.custom_help("ROBOT [--json]");
  opts.add_options()("json", "print one JSON document")("h,help", "this help")(
      "robot", "robot file or shipped robot name", cxxopts::value<std::string>());
  opts.parse_positional({"robot"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help() << "ROBOT is a robot file (robots/README.md) or a shipped robot's name, e.g. " << example
              << ".\n";
    return std::nullopt;
  }
  if (!args.count("robot")) throw UsageError("no robot given");
  return OneRobot{host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>())),
                  args.count("json") > 0};
}

host::Program program_argument(const cxxopts::ParseResult& args, const host::Robot& robot) {
  const std::string path = args["program"].as<std::string>();
  if (!std::ifstream(path)) throw UsageError("cannot read the program file '" + path + "'");
  return host::load_program(path, robot);
}

host::ControllerSettings settings_argument(const cxxopts::ParseResult& args, const host::Robot& robot) {
  host::ControllerSettings settings;
  if (args.count("settings")) {
    try {
      host::apply_settings_text(settings, args["settings"].as<std::string>(), robot.actuation.num_motors);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--settings: ") + e.what());
    }
  }
  return settings;
}

}  // namespace articula::cli
