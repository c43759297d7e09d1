// articula - the host command line. `main` looks argv[1] up in one table of commands;
// each command owns its options and its --help.
#include <cstring>
#include <iostream>

#include "cli_util.h"
#include "commands.h"

namespace {

struct CommandEntry {
  const char* name;
  int (*run)(int, char**);
  const char* help;
};

const CommandEntry kCommands[] = {
    {"info", articula::cli::cmd_info, "the robot's DH table, joints, limits, motors and reach"},
    {"fk", articula::cli::cmd_fk, "forward kinematics: every frame and the tool pose for joint values"},
    {"ik", articula::cli::cmd_ik, "inverse kinematics: joint values for a tool target (or a file of targets)"},
    {"quantize", articula::cli::cmd_quantize, "what whole motor steps make of protocol moves (L lines), in degrees and mm"},
    {"predict", articula::cli::cmd_predict, "what the real arm does with a program: steps, tool error, timing"},
    {"run", articula::cli::cmd_run, "run a program on the kinematic model: the pose after each command"},
    {"sim", articula::cli::cmd_sim, "run a program on the arm, or a cell of arms, as rigid bodies (ODE): contacts, grasps"},
    {"draw", articula::cli::cmd_draw, "a program that draws text or a shape with a pen in the gripper, reach checked"},
    {"configure", articula::cli::cmd_configure, "configure a Nano for a robot (its EEPROM), or print the lines that do"},
    {"wiring", articula::cli::cmd_wiring, "every wire of the arm: board pins to driver inputs, switches and servos"},
    {"mat", articula::cli::cmd_mat, "the table's mat of a cell or a scene: a 1:1 drawing from above (SVG) to print"},
    {"export-urdf", articula::cli::cmd_export_urdf, "the robot as URDF, for ROS tools"},
    {"import-legacy", articula::cli::cmd_import_legacy, "convert the original system's robot text file (thesis appendix C)"},
};

void usage(std::ostream& os) {
  os << "usage: articula <command> [options]\n\n"
        "Simulate and predict articulate robot arms described by modified DH tables.\n"
        "Robots are JSON files (robots/README.md); a shipped one can be named without path (mk2plus).\n"
        "Lengths are in mm and angles in degrees at every interface.\n\ncommands:\n";
  for (const auto& c : kCommands) os << "  " << c.name << std::string(15 - std::strlen(c.name), ' ') << c.help << '\n';
  os << "\n'articula <command> --help' describes a command's options.\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    usage(std::cerr);
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    usage(std::cout);
    return 0;
  }
  for (const auto& c : kCommands)
    if (name == c.name) return articula::cli::guarded(c.name, c.run, argc - 1, argv + 1);
  std::cerr << "articula: unknown command '" << name << "' (see: articula --help)\n";
  return 2;
}
