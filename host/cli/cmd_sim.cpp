// articula sim ROBOT PROGRAM [--scene FILE]: the program on the arm as rigid bodies in the
// Open Dynamics Engine (host/physics/sim.h): the trajectory (time, joints, tool, gripper,
// objects) as CSV or JSON lines, and an event log (contacts, collisions, grasps, lost steps).
// articula sim CELL: a cell's arms, each on its own firmware, in one world (cell_sim.h): the
// events with the arm they concern, and how each arm ends.
#include <unistd.h>

#include <chrono>
#include <cxxopts.hpp>
#include <fstream>
#include <cmath>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cell_sim.h"
#include "cli_util.h"
#include "commands.h"
#include "program.h"
#include "robot_file.h"
#include "scene.h"
#include "sim.h"

namespace articula::cli {
namespace {

// A length (mm) or angle (deg) for the CSV: 4 decimals (0.1 um, 0.0001 deg), no "-0.0000".
std::string fixed4(double v) {
  if (std::fabs(v) < 5e-5) v = 0;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string event_text(const host::SimEvent& e) {
  std::ostringstream o;
  o << fmt(e.t, 3) << " s";
  if (!e.arm.empty()) o << "  " << e.arm;
  if (e.line > 0) o << "  line " << e.line;
  o << "  " << host::event_kind_name(e.kind);
  if (!e.a.empty()) o << ": " << e.a;
  if (!e.b.empty()) o << (e.kind == host::SimEvent::Kind::kContactStarted || e.kind == host::SimEvent::Kind::kContactEnded ? " / " : " with ") << e.b;
  if (e.has_point) o << " at (" << fmt(e.point_mm.x, 1) << ", " << fmt(e.point_mm.y, 1) << ", " << fmt(e.point_mm.z, 1) << ") mm";
  if (!e.detail.empty()) o << ": " << e.detail;
  return o.str();
}

bool is_trouble(host::SimEvent::Kind k) {
  using K = host::SimEvent::Kind;
  return k == K::kCollision || k == K::kSelfCollision || k == K::kSqueeze || k == K::kStepsLost || k == K::kBlocked ||
         k == K::kRejected || k == K::kObjectRemoved || k == K::kGripperBlocked || k == K::kDeadlock;
}

void sim_progress(double t, double end) {
  const int width = 40;
  const int filled = int(width * std::min(1.0, t / std::max(end, 1e-9)));
  std::cerr << "\r[" << std::string(size_t(filled), '#') << std::string(size_t(width - filled), ' ') << "] " << fmt(t, 1)
            << " / " << fmt(end, 1) << " s" << std::flush;
}

int run_sim(int argc, char** argv) {
  cxxopts::Options opts("articula sim",
                        "The program on the arm as rigid bodies (Open Dynamics Engine): links follow the motors' "
                        "step counts as the firmware times them, objects fall, slide and are pushed or grasped, and "
                        "a step that would drive the arm into something is refused and reported.");
  opts.custom_help("ROBOT PROGRAM [--scene FILE] [--csv|--json] [-o FILE] [--events FILE] [--sample MS]");
  opts.add_options()("scene", "scene file or shipped scene name (scenes/); default: the ground only",
                     cxxopts::value<std::string>())("csv", "trajectory as CSV (the default)")(
      "json", "trajectory as JSON lines")("o,output", "write the trajectory to FILE (.csv, .json or .jsonl)",
                                          cxxopts::value<std::string>())(
      "events", "write the events as JSON lines to FILE (else: readable, on stderr)", cxxopts::value<std::string>())(
      "sample", "trajectory sample period, ms (0: no trajectory)", cxxopts::value<double>()->default_value("10"))(
      "dt", "world step, ms", cxxopts::value<double>()->default_value("1"))(
      "extra", "seconds simulated after the program's last action", cxxopts::value<double>()->default_value("1"))(
      "settings", "the controller's settings at power-up, e.g. \"0=800,1=3000\"", cxxopts::value<std::string>())(
      "joint-speed", "robots without motors: joint speed, deg/s (mm/s for prismatic joints)",
      cxxopts::value<double>()->default_value("60"))("quick-step", "ODE's iterative dWorldQuickStep instead of dWorldStep")(
      "progress", "show a progress bar even when stderr is not a terminal")("h,help", "this help")(
      "robot", "robot file or shipped robot name", cxxopts::value<std::string>())(
      "program", "program file: RoboSim (.robosim) or protocol lines (.arm)", cxxopts::value<std::string>());
  opts.parse_positional({"robot", "program"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "Links are kinematic bodies at the DH frames of the motors' steps, replayed step by step with the\n"
                 "firmware's timing (motion.h); robots without motors follow their joint targets at --joint-speed.\n"
                 "A step that would push a link into the ground, a static object or a non-adjacent link, or squeeze\n"
                 "a movable object, is refused: the arm holds at contact, the motor skips the step (the controller\n"
                 "does not know: the pose stays off by the steps lost), and an event says which parts, where, when.\n"
                 "Movable objects fall, slide and are pushed; the fingers grasp an object both touch while closing\n"
                 "and let it go when they open. Each move is checked against the motors' pull-out torque curves\n"
                 "(robot file motors[].torque) with what the gripper carries: a `stall` event says which motor would\n"
                 "skip steps and when (docs/stall.md). docs/physics.md explains the model, scenes/README.md the scene\n"
                 "files.\n"
                 "Trajectory columns: t_s, the joint values (deg or mm), the tool (mm, roll/pitch/yaw deg), the\n"
                 "gripper opening (mm) and each object's pose (mm, deg).\n"
                 "Exit code: 0 nothing went wrong, 1 a command was rejected, the arm was blocked or an object left\n"
                 "the world, 2 a usage error (bad robot, program or scene).\n"
                 "A cell of several arms instead (cells/README.md): articula sim CELL (articula sim handover --help).\n";
    return 0;
  }
  const double sample_ms = args["sample"].as<double>(), dt_ms = args["dt"].as<double>(), extra = args["extra"].as<double>();
  if (!(dt_ms > 0 && dt_ms <= 10)) throw UsageError("--dt must be in (0, 10] ms");
  if (!(sample_ms >= 0)) throw UsageError("--sample must be >= 0 ms");
  if (!(extra >= 0 && extra <= 3600)) throw UsageError("--extra must be in 0 .. 3600 s");
  if (!(args["joint-speed"].as<double>() > 0)) throw UsageError("--joint-speed must be > 0");

  const host::Robot robot = robot_argument(args);
  host::Scene scene;
  scene.name = "ground only";
  if (args.count("scene")) {
    try {
      scene = host::load_scene_file(host::resolve_scene_path(args["scene"].as<std::string>()));
    } catch (const host::SceneError& e) {
      throw UsageError(e.what());
    }
  }
  host::SimOptions so;
  so.dt = dt_ms / 1000;
  so.extra_time = extra;
  so.quick_step = args.count("quick-step") > 0;
  so.joints.speed_deg = so.joints.speed_mm = args["joint-speed"].as<double>();
  so.settings = settings_argument(args, robot);
  const host::Program program = program_argument(args, robot);

  std::unique_ptr<host::Simulation> sim;
  try {
    sim = std::make_unique<host::Simulation>(robot, scene, so);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  sim->load_program(program);

  const std::string out_path = args.count("output") ? args["output"].as<std::string>() : "";
  const bool json = args.count("json") || (!args.count("csv") && (ends_with(out_path, ".json") || ends_with(out_path, ".jsonl")));
  std::ofstream out_file;
  if (!out_path.empty()) {
    out_file.open(out_path);
    if (!out_file) throw UsageError("cannot write '" + out_path + "'");
  }
  std::ostream& out = out_path.empty() ? std::cout : out_file;
  std::ofstream events_file;
  if (args.count("events")) {
    events_file.open(args["events"].as<std::string>());
    if (!events_file) throw UsageError("cannot write '" + args["events"].as<std::string>() + "'");
  }

  const int nj = robot.model.num_joints;
  if (sample_ms > 0 && !json) {
    std::vector<std::string> head = {"t_s"};
    for (int j = 0; j < nj; ++j) head.push_back(robot.joint_names[size_t(j)] + "_" + joint_unit(robot, j));
    for (const char* c : {"tool_x", "tool_y", "tool_z", "tool_roll", "tool_pitch", "tool_yaw", "gripper_mm"}) head.push_back(c);
    for (int i = 0; i < sim->num_objects(); ++i)
      for (const char* c : {"_x", "_y", "_z", "_roll", "_pitch", "_yaw"}) head.push_back(sim->object(i).name + c);
    for (size_t i = 0; i < head.size(); ++i) out << (i ? "," : "") << csv_field(head[i]);
    out << '\n';
  }
  auto sample = [&]() {
    const auto& f = sim->frames();
    const Vec3<double> rpy = matrix_to_rpy(f.T_base_tool.R);
    if (json) {
      nlohmann::json j;
      j["t"] = sim->time();
      std::vector<double> q;
      for (int k = 0; k < nj; ++k) q.push_back(joint_from_model(robot, k, sim->joints()[size_t(k)]));
      j["joints"] = q;
      j["tool_mm"] = {f.T_base_tool.p.x, f.T_base_tool.p.y, f.T_base_tool.p.z};
      j["tool_rpy_deg"] = {rpy.x * 180 / M_PI, rpy.y * 180 / M_PI, rpy.z * 180 / M_PI};
      j["gripper_mm"] = sim->gripper_opening_mm();
      nlohmann::json objs = nlohmann::json::object();
      for (int i = 0; i < sim->num_objects(); ++i) {
        if (!sim->object(i).movable) continue;
        const Transform<double> T = sim->object_pose(i);
        const Vec3<double> r = matrix_to_rpy(T.R);
        objs[sim->object(i).name] = {{"xyz_mm", {T.p.x, T.p.y, T.p.z}}, {"rpy_deg", {r.x * 180 / M_PI, r.y * 180 / M_PI, r.z * 180 / M_PI}}};
      }
      j["objects"] = objs;
      out << j.dump() << '\n';
    } else {
      out << fmt_g(sim->time(), 6);
      for (int k = 0; k < nj; ++k) out << ',' << fixed4(joint_from_model(robot, k, sim->joints()[size_t(k)]));
      for (double v : {f.T_base_tool.p.x, f.T_base_tool.p.y, f.T_base_tool.p.z, rpy.x * 180 / M_PI, rpy.y * 180 / M_PI,
                       rpy.z * 180 / M_PI, sim->gripper_opening_mm()})
        out << ',' << fixed4(v);
      for (int i = 0; i < sim->num_objects(); ++i) {
        const Transform<double> T = sim->object_pose(i);
        const Vec3<double> r = matrix_to_rpy(T.R);
        for (double v : {T.p.x, T.p.y, T.p.z, r.x * 180 / M_PI, r.y * 180 / M_PI, r.z * 180 / M_PI}) out << ',' << fixed4(v);
      }
      out << '\n';
    }
  };

  size_t shown = 0;
  std::map<std::string, int> counts;
  auto flush_events = [&]() {
    const auto& ev = sim->events();
    for (; shown < ev.size(); ++shown) {
      ++counts[host::event_kind_name(ev[shown].kind)];
      if (events_file.is_open())
        events_file << host::event_json(ev[shown]).dump() << '\n';
      else
        std::cerr << event_text(ev[shown]) << '\n';
    }
  };

  const bool bar = args.count("progress") || (isatty(2) && sim->end_time() > 5);
  const auto t0 = std::chrono::steady_clock::now();
  const uint64_t sample_every = sample_ms > 0 ? std::max<uint64_t>(1, uint64_t(std::llround(sample_ms / dt_ms))) : 0;
  if (sample_every) sample();
  flush_events();
  double last_bar = 0;
  while (!sim->done()) {
    sim->step();
    if (sample_every && sim->steps_taken() % sample_every == 0) sample();
    if (shown < sim->events().size()) {
      if (bar) std::cerr << '\r' << std::string(70, ' ') << '\r';
      flush_events();
    }
    if (bar && sim->time() - last_bar >= 0.25) {
      last_bar = sim->time();
      sim_progress(sim->time(), sim->end_time());
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (bar) std::cerr << '\r' << std::string(70, ' ') << '\r';
  if (!out) throw UsageError("cannot write '" + (out_path.empty() ? std::string("standard output") : out_path) + "'");

  int trouble = 0;
  for (const auto& e : sim->events()) trouble += is_trouble(e.kind);
  std::ostringstream s;
  // The scene as the user named it (a shipped scene's name, or the path given).
  const std::string scene_label =
      args.count("scene")
          ? "scene " + args["scene"].as<std::string>() + (scene.name.empty() ? "" : " (\"" + scene.name + "\")")
          : "an empty scene";
  s << robot.name << ", " << program.source << " in " << scene_label << ": simulated "
    << fmt(sim->time(), 3) << " s in " << fmt(wall, 3) << " s (" << fmt(sim->time() / std::max(wall, 1e-9), 0)
    << "x real time, " << sim->steps_taken() << " steps of " << fmt(dt_ms, 3) << " ms); ";
  if (counts.empty()) {
    s << "no events";
  } else {
    bool first = true;
    for (const auto& [k, n] : counts) s << (first ? "" : ", ") << n << " " << k, first = false;
  }
  const auto lost = sim->lost_steps();
  std::string off;
  for (size_t i = 0; i < lost.size(); ++i)
    if (lost[i] != 0) off += (off.empty() ? "" : ", ") + robot.motor_names[i] + " " + std::to_string(lost[i]);
  if (!off.empty()) s << "; the arm ends off its counted steps by " << off;
  std::cerr << s.str() << '\n';
  return trouble ? 1 : 0;
}

// articula sim CELL: every arm of the cell on its own firmware, in one world.
int run_cell(int argc, char** argv) {
  cxxopts::Options opts("articula sim",
                        "A cell's arms in one world (Open Dynamics Engine): each arm on its own firmware (a virtual "
                        "Nano each) where the cell file puts it, running its program from t = 0, all on one clock; "
                        "what they do to the objects and to each other is reported.");
  opts.custom_help("CELL [--program ARM=FILE ...] [--json] [--events FILE]");
  opts.add_options()("program", "the program of one arm instead of the cell file's: ARM=FILE (again for another arm)",
                     cxxopts::value<std::vector<std::string>>())(
      "json", "how each arm ends, the objects and every event, as one JSON document on stdout")(
      "events", "write the events as JSON lines to FILE (else: readable, on stderr)", cxxopts::value<std::string>())(
      "dt", "world step, ms", cxxopts::value<double>()->default_value("1"))(
      "extra", "seconds simulated after the last arm's program ends", cxxopts::value<double>()->default_value("1"))(
      "quick-step", "ODE's iterative dWorldQuickStep instead of dWorldStep")(
      "progress", "show a progress bar even when stderr is not a terminal")("h,help", "this help")(
      "cell", "cell file or shipped cell name (cells/)", cxxopts::value<std::string>());
  opts.parse_positional({"cell"});
  const auto args = opts.parse(argc, argv);
  if (args.count("help")) {
    std::cout << opts.help()
              << "A cell file (cells/README.md) puts several arms on one table: each a robot file with its base's\n"
                 "place and heading, its program, and the wires between their I/O pins, in one scene of objects.\n"
                 "Each arm runs its own firmware on its own virtual clock, stepped in lockstep with the others and\n"
                 "with ODE; a step that would drive an arm into another is refused like any other collision, and\n"
                 "the event names both arms and both parts. A block one gripper holds can be taken by the other's.\n"
                 "Exit code: 0 nothing went wrong, 1 a command was rejected, an arm was blocked or an object left\n"
                 "the world, 2 a usage error (a bad cell, robot, program or scene: the message names the file and\n"
                 "the place in it).\n";
    return 0;
  }
  const double dt_ms = args["dt"].as<double>(), extra = args["extra"].as<double>();
  if (!(dt_ms > 0 && dt_ms <= 10)) throw UsageError("--dt must be in (0, 10] ms");
  if (!(extra >= 0 && extra <= 3600)) throw UsageError("--extra must be in 0 .. 3600 s");
  if (!args.count("cell")) throw UsageError("name a cell (a cell file, or a shipped cell: handover, two-arms)");
  host::Cell cell;
  try {
    cell = host::load_cell_file(host::resolve_cell_path(args["cell"].as<std::string>()));
  } catch (const host::CellError& e) {
    throw UsageError(e.what());
  }
  if (args.count("program")) {
    for (const std::string& spec : args["program"].as<std::vector<std::string>>()) {
      const size_t eq = spec.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
        throw UsageError("--program takes ARM=FILE (got '" + spec + "')");
      const std::string arm = spec.substr(0, eq), file = spec.substr(eq + 1);
      const int a = cell.arm_index(arm);
      try {
        if (a < 0) host::set_cell_program(cell, arm, host::Program{});  // (says which arms there are)
        host::set_cell_program(cell, arm, host::load_program(file, cell.arms[size_t(a)].robot));
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--program: ") + e.what());
      } catch (const host::ProgramError& e) {
        throw UsageError(std::string("--program ") + arm + ": " + e.what());
      }
    }
  }
  host::SimOptions so;
  so.dt = dt_ms / 1000;
  so.extra_time = extra;
  so.quick_step = args.count("quick-step") > 0;
  std::unique_ptr<host::CellSimulation> sim;
  try {
    sim = std::make_unique<host::CellSimulation>(cell, so);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  std::ofstream events_file;
  if (args.count("events")) {
    events_file.open(args["events"].as<std::string>());
    if (!events_file) throw UsageError("cannot write '" + args["events"].as<std::string>() + "'");
  }
  const bool json = args.count("json") > 0;
  size_t shown = 0;
  std::map<std::string, int> counts;
  auto flush_events = [&]() {
    const auto& ev = sim->world().events();
    for (; shown < ev.size(); ++shown) {
      ++counts[host::event_kind_name(ev[shown].kind)];
      if (events_file.is_open())
        events_file << host::event_json(ev[shown]).dump() << '\n';
      else if (!json)
        std::cerr << event_text(ev[shown]) << '\n';
    }
  };
  const bool bar = args.count("progress") || (isatty(2) && sim->end_time() > 5);
  const auto t0 = std::chrono::steady_clock::now();
  flush_events();
  double last_bar = 0;
  while (!sim->done()) {
    sim->step();
    if (shown < sim->world().events().size()) {
      if (bar) std::cerr << '\r' << std::string(70, ' ') << '\r';
      flush_events();
    }
    if (bar && sim->time() - last_bar >= 0.25) {
      last_bar = sim->time();
      sim_progress(sim->time(), sim->end_time());
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (bar) std::cerr << '\r' << std::string(70, ' ') << '\r';
  int trouble = 0;
  for (const auto& e : sim->world().events()) trouble += is_trouble(e.kind);
  const nlohmann::json arms = host::cell_arms_json(*sim);
  if (json) {
    nlohmann::json out = host::cell_state_json(*sim), events = nlohmann::json::array();
    for (const auto& e : sim->world().events()) events.push_back(host::event_json(e));
    out["cell"] = cell.name;
    out["events"] = events;
    std::cout << out.dump(2) << '\n';
  } else {
    Table t({"arm", "robot", "program", "ends at (s)", "joints", "tool (mm)", "lost steps"});
    for (const auto& a : arms) {
      std::string q, tool, lost;
      for (const auto& v : a["joints"]) q += (q.empty() ? "" : " ") + fmt(v.get<double>(), 1);
      for (const auto& v : a["tool_mm"]) tool += (tool.empty() ? "" : " ") + fmt(v.get<double>(), 1);
      for (const auto& v : a["lost_steps"]) lost += (lost.empty() ? "" : " ") + std::to_string(v.get<int>());
      const std::string program = a["program"].get<std::string>();
      t.add({a["name"].get<std::string>(), a["robot"].get<std::string>(), program.empty() ? "(none)" : program,
             fmt(a["program_end_s"].get<double>(), 3), q, tool, lost.empty() ? "-" : lost});
    }
    std::cout << t.str();
  }
  std::ostringstream s;
  s << cell.name << ": " << cell.arms.size() << " arms, simulated " << fmt(sim->time(), 3) << " s in " << fmt(wall, 3)
    << " s (" << fmt(sim->time() / std::max(wall, 1e-9), 0) << "x real time); ";
  if (counts.empty()) {
    s << "no events";
  } else {
    bool first = true;
    for (const auto& [k, n] : counts) s << (first ? "" : ", ") << n << " " << k, first = false;
  }
  std::cerr << s.str() << '\n';
  return trouble ? 1 : 0;
}

}  // namespace

int cmd_sim(int argc, char** argv) {
  // A cell instead of a robot: `articula sim CELL`.
  if (argc >= 2 && argv[1][0] != '-' && host::is_cell_reference(argv[1])) return run_cell(argc, argv);
  return run_sim(argc, argv);
}

}  // namespace articula::cli
