// host/cli/cli_util.h - what several commands share: errors, number lists, tables.
#ifndef ARTICULA_CLI_UTIL_H
#define ARTICULA_CLI_UTIL_H

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <articula/transform.h>
#include "predict.h"
#include "program.h"
#include "robot.h"

namespace cxxopts {
class Options;
class ParseResult;
}

namespace articula::cli {

// A user error: printed as one line "articula <command>: <message>", exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "1,2.5,-3" -> {1, 2.5, -3}. Throws UsageError naming `what` on a bad entry.
std::vector<double> parse_number_list(const std::string& text, const std::string& what);

// Joint values in file and model units: joint_is_angle, joint_to_model, joint_from_model
// (robot.h).

// A plain text table: columns padded to their widest cell, numbers right-aligned.
class Table {
 public:
  explicit Table(std::vector<std::string> header) : rows_{std::move(header)} {}
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  std::string str() const;

 private:
  std::vector<std::vector<std::string>> rows_;
};

// A number in a table's column: a fixed count of decimals, so the column lines up (no "-0.000").
// Not a protocol number (protocol_number, host/lib/blocks.h): a table shows, a line commands.
std::string fmt(double v, int decimals = 3);
// A number with `significant` significant digits (printf %g), for machine-readable output.
std::string fmt_g(double v, int significant = 9);

// A protocol line without its comment (program.h).
using host::command_text;

// The output format of predict and run: "json" or "csv" when asked (--json, --csv), else
// from -o FILE's extension (.json, .csv), else "table".
std::string output_format(const cxxopts::ParseResult& args);
// Text to -o FILE, or to standard output when `path` is empty. Throws UsageError when the
// file cannot be written.
void write_output(const std::string& path, const std::string& text);

// One CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s);

// The positional ROBOT and PROGRAM of predict, run and sim. robot_argument checks that both
// are given and that --json and --csv are not both, and loads the robot (file or shipped
// name); program_argument loads the program (RoboSim or protocol lines) for that robot;
// settings_argument reads --settings "0=800,1=3000" as the controller would (the defaults
// when absent). Throw UsageError, RobotFileError or ProgramError.
host::Robot robot_argument(const cxxopts::ParseResult& args);
host::Program program_argument(const cxxopts::ParseResult& args, const host::Robot& robot);
host::ControllerSettings settings_argument(const cxxopts::ParseResult& args, const host::Robot& robot);

// A command that takes one robot and --json (info, wiring): adds ROBOT, --json and --help to
// `opts`, parses argv and loads the robot; on --help prints the help (naming `example`, a shipped
// robot) and gives nothing. Throws UsageError or RobotFileError.
struct OneRobot {
  host::Robot robot;
  bool json = false;
};
std::optional<OneRobot> one_robot_command(cxxopts::Options& opts, int argc, char** argv, const char* example);

// Runs a command body: catches UsageError, RobotFileError, ProgramError and cxxopts errors and turns
// them into one line on stderr and a non-zero exit code.
int guarded(const char* command, int (*body)(int, char**), int argc, char** argv);

}  // namespace articula::cli

#endif
