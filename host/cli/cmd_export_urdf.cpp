// articula export-urdf ROBOT: the robot as URDF for ROS tools (RViz, MoveIt).
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>

#include "cli_util.h"
#include "commands.h"
#include "robot_file.h"
#include "urdf.h"

namespace articula::cli {
namespace {

int run_export_urdf(int argc, char** argv) {
  cxxopts::Options opts("articula export-urdf", "Writes a robot as URDF, for ROS tools (RViz, robot_state_publisher, MoveIt).");
  opts.custom_help("ROBOT [-o OUT.urdf]");
  opts.add_options()("o,output", "write here (default: standard output)", cxxopts::value<std::string>())(
      "h,help", "this help")("robot", "robot file or shipped robot name", cxxopts::value<std::string>());
  opts.parse_positional({"robot"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "Metres and radians. Each joint variable is a revolute (theta, alpha) or prismatic (d) joint named\n"
                 "after it; a linked parameter is one mimic joint per joint it follows; DH frames are links\n"
                 "frame_1 .. frame_n, the tool is the link 'tool'. Check it with check_urdf (liburdfdom-tools).\n";
    return 0;
  }
  if (!args.count("robot")) throw UsageError("no robot given");
  const host::Robot r = host::load_robot_file(host::resolve_robot_path(args["robot"].as<std::string>()));
  const host::UrdfExport u = host::export_urdf(r);
  if (args.count("output")) {
    const std::string out = args["output"].as<std::string>();
    std::ofstream o(out);
    if (!(o << u.xml)) throw UsageError("cannot write " + out);
    std::cerr << "wrote " << out << '\n';
  } else {
    std::cout << u.xml;
  }
  for (const auto& n : u.notes) std::cerr << "note: " << n << '\n';
  return 0;
}

}  // namespace

int cmd_export_urdf(int argc, char** argv) { return run_export_urdf(argc, argv); }

}  // namespace articula::cli
