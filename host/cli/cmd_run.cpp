// articula run ROBOT PROGRAM: executes a program on the kinematic model (ideal joint values,
// no motor steps, no timing) and prints or saves the pose after each command
// (host/lib/run.h).
#include <cctype>
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_util.h"
#include "commands.h"
#include "program.h"
#include "records_json.h"
#include "robot_file.h"
#include "run.h"

namespace articula::cli {
namespace {

int run_on_the_arm(int argc, char** argv) {
  cxxopts::Options opts("articula run",
                        "Executes a program on the kinematic model and prints or saves the pose after each "
                        "command: joint values, tool position and roll/pitch/yaw, and the IK's status for targets.");
  opts.custom_help("ROBOT PROGRAM [--json|--csv] [-o FILE]");
  opts.add_options()("json", "one JSON document")("csv", "CSV: a header and one row per command")(
      "o,output", "write to FILE instead of standard output (format from --json/--csv, else from .json/.csv)",
      cxxopts::value<std::string>())("h,help", "this help")("robot", "robot file or shipped robot name",
                                                            cxxopts::value<std::string>())(
      "program", "program file: RoboSim (.robosim) or protocol lines (.arm)", cxxopts::value<std::string>());
  opts.parse_positional({"robot", "program"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout
        << opts.help()
        << "The model starts at the robot's home pose (a robot with motors: at its motors' zero angles, where\n"
           "the real arm powers up). RoboSim: m sets the joint values, a solves the inverse kinematics\n"
           "(host/lib/ik.h, with w's weights) from the current pose and moves to the best pose found, reached or\n"
           "not (the status and the distance to the target say which); l changes link lengths, h the gripper;\n"
           "s and z have no effect here. Protocol lines take the commanded angles as exact (no steps): L and M\n"
           "are checked against the limits as the controller does (error:9, nothing moves), P is solved by\n"
           "ik.h (error:10 unless reached), T is cut into segments within $7 of its line, each end solved by ik.h\n"
           "from the last (the segments are in --json). Roll/pitch/yaw are fixed X-Y-Z angles, R = Rz(yaw) Ry(pitch) Rx(roll).\n"
           "`articula predict` shows what whole motor steps and the controller's timing make of the same program.\n"
           "Exit code: 0 every command accepted, 1 some rejected, 2 a usage error (bad robot or program).\n";
    return 0;
  }
  const host::Robot robot = robot_argument(args);
  const host::Program program = program_argument(args, robot);
  const std::vector<host::RunRecord> records = host::run_program(robot, program);
  int rejected = 0;
  for (const auto& r : records) rejected += r.reply != kOk;

  const std::string format = output_format(args);
  const std::string out_path = args.count("output") ? args["output"].as<std::string>() : "";
  const int nj = robot.model.num_joints;

  std::ostringstream out;
  if (format == "json") {
    out << host::run_json(robot, program, records).dump(2) << '\n';
  } else if (format == "csv") {
    std::vector<std::string> head = {"line", "command", "reply", "code"};
    for (int k = 0; k < nj; ++k) head.push_back(robot.joint_names[size_t(k)] + "_" + joint_unit(robot, k));
    for (const char* c : {"x_mm", "y_mm", "z_mm", "roll_deg", "pitch_deg", "yaw_deg", "gripper_percent", "target_x",
                          "target_y", "target_z", "ik_status", "target_error_mm", "note"})
      head.push_back(c);
    for (size_t i = 0; i < head.size(); ++i) out << (i ? "," : "") << csv_field(head[i]);
    out << '\n';
    for (const auto& r : records) {
      std::vector<std::string> row = {std::to_string(r.line), command_text(r.text), r.reply == kOk ? "ok" : "error",
                                      std::to_string(int(r.reply))};
      for (double q : r.joints) row.push_back(fmt_g(q));
      for (double v : {r.tool.p.x, r.tool.p.y, r.tool.p.z, r.rpy_deg.x, r.rpy_deg.y, r.rpy_deg.z})
        row.push_back(fmt_g(v));
      row.push_back(r.gripper_percent < 0 ? "" : std::to_string(r.gripper_percent));
      for (double v : {r.target.x, r.target.y, r.target.z}) row.push_back(r.has_target ? fmt_g(v) : "");
      row.push_back(r.ik_status);
      row.push_back(r.has_target ? fmt_g(r.target_error_mm) : "");
      row.push_back(r.reply == kOk ? r.note
                                   : std::string(status_text(r.reply)) + (r.note.empty() ? "" : "; " + r.note));
      for (size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << csv_field(row[i]);
      out << '\n';
    }
  } else {
    out << robot.name << ", " << program.source << " on the kinematic model\n";
    std::vector<std::string> head = {"line", "command", "reply"};
    for (int k = 0; k < nj; ++k) head.push_back(robot.joint_names[size_t(k)] + " " + joint_unit(robot, k));
    for (const char* c : {"x mm", "y mm", "z mm", "roll deg", "pitch deg", "yaw deg", "ik"}) head.push_back(c);
    Table t(head);
    std::vector<std::string> notes;
    for (const auto& r : records) {
      std::vector<std::string> row = {std::to_string(r.line), command_text(r.text),
                                      r.reply == kOk ? "ok" : "error:" + std::to_string(int(r.reply))};
      for (double q : r.joints) row.push_back(fmt(q));
      for (double v : {r.tool.p.x, r.tool.p.y, r.tool.p.z, r.rpy_deg.x, r.rpy_deg.y, r.rpy_deg.z})
        row.push_back(fmt(v));
      row.push_back(r.has_target && !r.ik_status.empty() ? r.ik_status + " " + fmt(r.target_error_mm) + " mm" : "");
      t.add(row);
      const std::string note = r.reply == kOk ? r.note
                                              : std::string(status_text(r.reply)) + ", nothing changes" +
                                                    (r.note.empty() ? "" : "; " + r.note);
      if (!note.empty()) notes.push_back("line " + std::to_string(r.line) + ": " + note);
    }
    out << t.str();
    for (const auto& s : notes) out << s << '\n';
    out << records.size() << " commands, " << rejected << " rejected\n";
  }
  write_output(out_path, out.str());
  return rejected ? 1 : 0;
}

}  // namespace

int cmd_run(int argc, char** argv) {
  return run_on_the_arm(argc, argv);
}

}  // namespace articula::cli
