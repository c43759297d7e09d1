// articula predict ROBOT PROGRAM: what the real arm will do with a program, step-exact: for
// each command the motor steps, the joint values they give, the ideal and the quantized tool
// position, and the timing, from a host model of the controller built on the shared core
// (host/lib/predict.h).
#include <cctype>
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cell_file.h"
#include "cell_sim.h"
#include "cli_util.h"
#include "commands.h"
#include "predict.h"
#include "program.h"
#include "records_json.h"
#include "robot_file.h"

namespace articula::cli {
namespace {

std::string joined(const std::vector<int32_t>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? " " : "") + std::to_string(v[i]);
  return s;
}

std::string joined(const std::vector<double>& v, int decimals) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? " " : "") + fmt(v[i], decimals);
  return s;
}

std::string joined(const Vec3<double>& p, int decimals = 3) {
  return joined(std::vector<double>{p.x, p.y, p.z}, decimals);
}

int run_predict_in_cell(const cxxopts::ParseResult& args);
int print_prediction(const cxxopts::ParseResult& args, const host::Robot& robot, const host::Program& program,
                     const host::ControllerSettings& settings, const host::Prediction& p);

int run_predict(int argc, char** argv) {
  cxxopts::Options opts("articula predict",
                        "What the real arm will do with a program, step-exact: for each command the motor steps, "
                        "the joint values they give, the ideal and the quantized tool position and their "
                        "difference, and the timing of the controller's queue.");
  opts.custom_help("ROBOT PROGRAM [--json [--path]|--csv] [--settings n=v,...] [--sender rest|stream] [--stop-at S,...] [-o FILE]\n"
                   "  articula predict CELL ARM [--json [--path]|--csv] [-o FILE]");
  opts.add_options()("json", "one JSON document")("csv", "CSV: a header and one row per command")(
      "path", "with --json: each move's tool position after every step (path_mm), as the arm spreads its steps")(
      "settings", "the controller's settings at power-up, e.g. \"0=800,1=3000\" ($0 max rate, $1 accel, ...)",
      cxxopts::value<std::string>())(
      "sender",
      "how the lines reach the arm, which decides how far its planner sees ahead: rest (each line once the arm "
      "is at rest: the harness, the studio's program runner; the default), stream (the next line when the "
      "previous one is answered, at the Nano's baud rate, taking no time itself)",
      cxxopts::value<std::string>()->default_value("rest"))(
      "stop-at",
      "send '!' at these times, seconds after the arm's first step, e.g. 0.5 or 0.5,2 (a student pressing "
      "STOP): where the arm comes to rest and what it never does",
      cxxopts::value<std::string>())("o,output", "write to FILE instead of standard output",
                                     cxxopts::value<std::string>())("h,help", "this help")(
      "robot", "robot file or shipped robot name (or a cell: its file or shipped name)", cxxopts::value<std::string>())(
      "program", "program file: RoboSim (.robosim) or protocol lines (.arm) (for a cell: the arm's name)",
      cxxopts::value<std::string>());
  opts.parse_positional({"robot", "program"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout
        << opts.help()
        << "The arm powers up with every motor at step 0 and the settings of docs/protocol.md ($0 600 steps/s,\n"
           "$1 2000 steps/s^2, $5 gripper settle 300 ms, ...), or those of --settings; `$n=v` lines change them.\n"
           "Each command runs as the firmware runs it (L, M, P, T, G, S, H, Z; a rejected command changes\n"
           "nothing). T's line is cut into segments within $7 of it (docs/protocol.md \"Straight lines\");\n"
           "the text adds how far the tool strays from the line at any step, --json --path the tool at every step. RoboSim programs map onto the same commands: m -> M (joint values through the\n"
           "coupling), a -> inverse kinematics, then M (not reached: error:10, nothing moves), h -> G\n"
           "(0.0 open = 100 %, 0.5 closed = 0 %), s -> $0 = round($0 at start * s / 82), w -> IK weights,\n"
           "l -> link lengths of the host model only (the real arm cannot), z -> nothing.\n"
           "Every time is the firmware's own (2 MHz ticks, from the first line's arrival): firmware/src, built\n"
           "for the PC (firmware/sitl), runs the lines on a virtual clock as the sender sends them, at the\n"
           "Nano's 117,647 baud. With --sender rest every move runs from rest to rest, G and S take the settle\n"
           "time; with stream, queued moves blend as the firmware's planner blends them ($6, docs/protocol.md\n"
           "\"Timing of moves\"). A line holding only '!' is the stop, sent alone when the line before it is\n"
           "answered; --stop-at sends it at a time instead. The arm decelerates along its path; the lines after\n"
           "it start from the steps it reached. Where that is depends on when the '!' arrives, to the step: the\n"
           "Nano's own time to read and answer a line is not modelled (its main loop takes no time there).\n"
           "One arm of a cell (cells/README.md): articula predict CELL ARM predicts that arm's program from the\n"
           "cell file as the cell runs it, each line at rest, its inputs driven through the cell's wires by the\n"
           "other arms' firmwares running their own programs beside it: each W ends at the tick another arm's\n"
           "output changed (articula sim CELL runs them all, with the world's objects).\n"
           "Exit code: 0 every command accepted, 1 some rejected, 2 a usage error (bad robot or program).\n";
    return 0;
  }
  if (args.count("path") && output_format(args) != "json") throw UsageError("--path needs --json");
  if (args.count("robot") && host::is_cell_reference(args["robot"].as<std::string>())) return run_predict_in_cell(args);
  const host::Robot robot = robot_argument(args);
  if (!robot.has_motors)
    throw UsageError(robot.name + " (" + robot.source +
                     ") has no motors: there are no steps to predict (articula run executes its programs on the "
                     "kinematic model)");
  const host::ControllerSettings settings = settings_argument(args, robot);
  const host::Program program = program_argument(args, robot);
  host::SenderModel sender;
  const std::string sender_text = args["sender"].as<std::string>();
  bool known = false;
  for (host::SenderModel::Kind k : {host::SenderModel::kRest, host::SenderModel::kStream})
    if (sender_text == host::sender_name(k)) sender.kind = k, known = true;
  if (!known) throw UsageError("--sender " + sender_text + ": expected rest or stream");
  if (args.count("stop-at")) {
    const std::string text = args["stop-at"].as<std::string>();
    std::stringstream in(text);
    std::string item;
    double last = -1;
    while (std::getline(in, item, ',')) {
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      if (item.empty() || *end != '\0' || !(v >= 0) || v > 1e6 || v < last)
        throw UsageError("--stop-at " + text + ": '" + item +
                         "' is not a time in seconds (0 or more, in increasing order, comma-separated)");
      last = v;
      sender.stop_ticks.push_back(uint64_t(std::llround(v * articula::kStepTickHz)));
    }
  }
  const host::Prediction p = host::predict_program(robot, program, settings, sender, args.count("path") > 0);
  return print_prediction(args, robot, program, settings, p);
}

// articula predict CELL ARM: one arm of a cell, its inputs driven through the cell's wires by
// the other arms' firmwares (cell_sim.h's predict_in_cell).
int run_predict_in_cell(const cxxopts::ParseResult& args) {
  const std::string ref = args["robot"].as<std::string>();
  for (const char* o : {"settings", "stop-at"})
    if (args.count(o)) throw UsageError(std::string("--") + o + " is for a robot's program: a cell's arms power up as in the cell");
  if (args["sender"].as<std::string>() != "rest")
    throw UsageError("--sender: a cell's arms take each line once at rest after the one before (rest)");
  host::Cell cell;
  try {
    cell = host::load_cell_file(host::resolve_cell_path(ref));
  } catch (const host::CellError& e) {
    throw UsageError(e.what());
  }
  if (!args.count("program"))
    throw UsageError("name the arm of " + cell.name + " to predict (its arms: " + host::cell_arm_names(cell) + ")");
  const std::string name = args["program"].as<std::string>();
  try {
    const host::Prediction p = host::predict_in_cell(cell, name, args.count("path") > 0);
    const host::CellArm& arm = cell.arms[size_t(cell.arm_index(name))];
    return print_prediction(args, arm.robot, arm.program, host::SimOptions().settings, p);
  } catch (const std::invalid_argument& e) {  // (no such arm)
    throw UsageError(e.what());
  } catch (const host::PredictError& e) {  // (an arm without motors)
    throw UsageError(e.what());
  }
}

int print_prediction(const cxxopts::ParseResult& args, const host::Robot& robot, const host::Program& program,
                     const host::ControllerSettings& settings, const host::Prediction& p) {
  const std::string format = output_format(args);
  const std::string out_path = args.count("output") ? args["output"].as<std::string>() : "";
  const bool robosim = program.format == host::Program::Format::kRoboSim;
  const int n = robot.actuation.num_motors;

  std::ostringstream out;
  if (format == "json") {
    out << host::prediction_json(robot, program, p).dump(2) << '\n';
  } else if (format == "csv") {
    std::vector<std::string> head = {"line", "command", "protocol", "reply", "code"};
    for (const auto& m : robot.motor_names) head.push_back("steps_" + m);
    for (const auto& m : robot.joint_names) head.push_back("joint_" + m);
    for (const char* c : {"ideal_x", "ideal_y", "ideal_z", "quantized_x", "quantized_y", "quantized_z", "error_mm",
                          "gripper_percent", "dominant_steps", "ticks", "seconds", "start_s", "end_s", "note"})
      head.push_back(c);
    for (size_t i = 0; i < head.size(); ++i) out << (i ? "," : "") << csv_field(head[i]);
    out << '\n';
    for (const auto& r : p.records) {
      std::vector<std::string> row = {std::to_string(r.line), command_text(r.text), r.protocol,
                                      r.stop ? "none" : r.reply == kOk ? "ok" : "error", std::to_string(int(r.reply))};
      for (int i = 0; i < n; ++i) row.push_back(std::to_string(r.steps[size_t(i)]));
      for (double q : r.joints) row.push_back(fmt_g(q));
      for (const auto& v : {r.tool_ideal, r.tool_quantized})
        for (double c : {v.x, v.y, v.z}) row.push_back(fmt_g(c));
      row.push_back(fmt_g(r.error_mm));
      row.push_back(r.gripper_percent < 0 ? "" : std::to_string(r.gripper_percent));
      row.push_back(std::to_string(r.dominant_steps));
      row.push_back(std::to_string(r.ticks));
      row.push_back(fmt_g(r.seconds()));
      row.push_back(fmt_g(r.start_s()));
      row.push_back(fmt_g(r.end_s()));
      row.push_back(r.reply == kOk ? r.note
                                   : std::string(status_text(r.reply)) + (r.note.empty() ? "" : "; " + r.note));
      for (size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << csv_field(row[i]);
      out << '\n';
    }
  } else {
    out << robot.name << ", " << program.source << ": $0 " << settings.value[0] << " steps/s, $1 " << settings.value[1]
        << " steps/s^2, $5 " << settings.value[5] << " ms\n";
    std::vector<std::string> head = {"line", "command", "reply"};
    if (robosim) head.push_back("sent as");
    for (const char* c :
         {"steps", "joints deg", "ideal tool mm", "quantized tool mm", "diff mm", "time s", "start s", "end s"})
      head.push_back(c);
    Table t(head);
    std::vector<std::string> notes;
    for (const auto& r : p.records) {
      std::vector<std::string> row = {std::to_string(r.line), command_text(r.text),
                                      r.stop ? "-" : host::reply_text(r.reply)};
      if (robosim) row.push_back(r.protocol);
      for (const std::string& c : {joined(r.steps), joined(r.joints, 4), joined(r.tool_ideal), joined(r.tool_quantized),
                                   fmt(r.error_mm), fmt(r.seconds()), fmt(r.start_s()), fmt(r.end_s())})
        row.push_back(c);
      t.add(row);
      std::string note = r.reply == kOk ? r.note
                                        : std::string(status_text(r.reply)) + ", nothing changes" +
                                              (r.note.empty() ? "" : "; " + r.note);
      if (r.has_target && r.reply == kOk)
        note = "tool " + fmt(r.target_error_mm) + " mm from the target" + (note.empty() ? "" : "; " + note);
      if (!note.empty()) notes.push_back("line " + std::to_string(r.line) + ": " + note);
    }
    out << t.str();
    for (const auto& s : notes) out << s << '\n';
    out << p.records.size() << " commands, " << p.rejected << " rejected, worst quantization error "
        << fmt(p.worst_error_mm) << " mm, total duration " << fmt(p.total_s()) << " s\n";
  }
  write_output(out_path, out.str());
  return p.rejected ? 1 : 0;
}

}  // namespace

int cmd_predict(int argc, char** argv) {
  return run_predict(argc, argv);
}

}  // namespace articula::cli
