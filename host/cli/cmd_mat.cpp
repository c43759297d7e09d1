// articula mat CELL|SCENE [-o FILE]: the table's mat, a 1:1 drawing from above as SVG, for a
// class to print and lay the real parts on (host/physics/mat.h).
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>

#include "cell_file.h"
#include "cli_util.h"
#include "commands.h"
#include "mat.h"
#include "scene.h"

namespace articula::cli {
namespace {

int run_mat(int argc, char** argv) {
  cxxopts::Options opts("articula mat",
                        "The table's mat: a drawing from above at 1:1 (mm), as SVG, of a cell or a scene, to print at\n"
                        "100 % and lay the real parts on: each object's outline and name (dashed: one that moves), each\n"
                        "arm's base and which way it faces, each light barrier's beam, each belt's way, each feeder's\n"
                        "outlet, a 50 mm grid and a 100 mm bar to check the print's scale.");
  opts.custom_help("CELL|SCENE [-o FILE]");
  opts.add_options()("what", "a cell or a scene: a file, or a shipped one's name", cxxopts::value<std::string>())(
      "o,output", "write the SVG to FILE (default: standard output)", cxxopts::value<std::string>())("h,help", "this help");
  opts.parse_positional({"what"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help() << "\nExamples:\n  articula mat station -o station-mat.svg\n  articula mat grasp-and-lift -o mat.svg\n";
    return 0;
  }
  if (!args.count("what")) throw UsageError("name a cell or a scene (a file, or a shipped one: station, grasp-and-lift)");
  const std::string what = args["what"].as<std::string>();
  std::string svg;
  try {
    if (host::is_cell_reference(what)) {
      svg = host::mat_svg(host::load_cell_file(host::resolve_cell_path(what)));
    } else {
      svg = host::mat_svg(host::load_scene_file(host::resolve_scene_path(what)));
    }
  } catch (const host::CellError& e) {
    throw UsageError(e.what());
  } catch (const host::SceneError& e) {
    throw UsageError(e.what());
  }
  if (!args.count("output")) {
    std::cout << svg;
    return 0;
  }
  const std::string path = args["output"].as<std::string>();
  std::ofstream f(path, std::ios::binary);
  if (!(f << svg)) throw UsageError("cannot write " + path);
  std::cerr << "wrote " << path << ": print it at 100 % (actual size, no fit to page)\n";
  return 0;
}

}  // namespace

int cmd_mat(int argc, char** argv) { return run_mat(argc, argv); }

}  // namespace articula::cli
