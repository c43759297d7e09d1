// articula wiring ROBOT: every wire of the arm, board pin to driver input, switch or servo, as the
// firmware build for its drive expects them (host/lib/wiring.h, from firmware/src/board.h).
#include <cxxopts.hpp>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "robot_file.h"
#include "wiring.h"

namespace articula::cli {
namespace {

int run_wiring(int argc, char** argv) {
  cxxopts::Options opts("articula wiring",
                        "Every wire of a robot's arm: which pin of its board goes to which driver input, switch or servo,\n"
                        "from the robot file's board and drivers (robots/README.md, \"Drive\"; docs/drives.md).");
  const std::optional<OneRobot> one = one_robot_command(opts, argc, argv, "mk2plus-cnc");
  if (!one) return 0;
  const host::Robot& r = one->robot;
  const nlohmann::json w = host::wiring_json(r);
  if (one->json) {
    std::cout << w.dump(2) << '\n';
    return 0;
  }
  if (w.contains("error")) throw UsageError("cannot wire " + r.name + ": " + w["error"].get<std::string>());
  std::cout << r.name << " on an " << w["board_title"].get<std::string>()
            << (w["given"].get<bool>() ? "" : " (the file names no drive: the thesis's wiring, L298Ns on a Nano)") << "\n";
  std::cout << "firmware: " << w["firmware"].get<std::string>() << ".hex\n\n";
  Table t({"pin", "goes to", "input", "motor"});
  for (const auto& x : w["wires"])
    t.add({x["pin"].get<std::string>(), x["part"].get<std::string>(), x["signal"].get<std::string>(),
           x["motor"].is_null() ? "" : x["motor"].get<std::string>()});
  std::cout << t.str();
  for (const auto& note : w["supply"]) std::cout << "\n" << note.get<std::string>() << '\n';
  return 0;
}

}  // namespace

int cmd_wiring(int argc, char** argv) { return run_wiring(argc, argv); }

}  // namespace articula::cli
