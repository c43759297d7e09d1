// wasm/src/engine.cpp - the web engine: the host library and the physics (host/lib,
// host/physics, over the core in shared/) for JavaScript, through embind. The twin of
// python/src: no kinematics, IK, prediction or physics of its own, only calls into host/.
//
// The rules at this door (docs/studio.md, "The web engine"):
//  - structured values cross as JSON text (the CLI's --json forms, records_json.h and
//    robot_view.h), numbers in mm and degrees as everywhere;
//  - nothing throws into JavaScript: a call that can fail returns {"error": "...", ...} (the
//    same text the CLI prints, naming the file, the JSON path or the line), and loaders
//    return that text, "" when they succeeded. wasm/js/engine.mjs turns it into a JS Error;
//  - the hot paths (FK, IK for the benchmark) use a scratch array of doubles on the heap that
//    JavaScript reads and writes in place: no allocation, no JSON, per call.
#include <emscripten/bind.h>

#include <articula/motion.h>
#include <articula/protocol.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "coil_decoder.h"
#include "geometry.h"
#include "wiring.h"
#include "ik.h"
#include "legacy.h"
#include "predict.h"
#include "program.h"
#include "quantize.h"
#include "records_json.h"
#include "robot.h"
#include "robot_file.h"
#include "robot_view.h"
#include "run.h"
#include "scene.h"
#include "servo.h"
#include "sim.h"
#include "urdf.h"

namespace articula::web {
namespace {

using host::HostFrames;
using host::Robot;
using json = nlohmann::json;

std::string error_json(const std::string& message, json extra = json::object()) {
  extra["error"] = message;
  return extra.dump();
}

// Runs f (which returns JSON text) and turns any exception into {"error": ...}: a ProgramError
// keeps its line, a robot file's error its file and JSON path.
template <typename F>
std::string guarded(F&& f) {
  try {
    return f();
  } catch (const host::ProgramError& e) {
    return error_json(e.what(), {{"line", e.line()}});
  } catch (const host::RobotFileError& e) {
    return error_json(e.what(), {{"file", e.file()}, {"json_path", e.json_path()}, {"problem", e.problem()}});
  } catch (const host::SceneError& e) {
    return error_json(e.what(), {{"json_path", e.json_path()}});
  } catch (const json::exception& e) {
    return error_json(std::string("not the JSON expected: ") + e.what());
  } catch (const std::exception& e) {
    return error_json(e.what());
  } catch (...) {
    return error_json("an unknown error in the engine");
  }
}

json flat(const Transform<double>& T) {
  json out = json::array();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) out.push_back(T.R.m[i][k]);
    out.push_back(T.p[i]);
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) out.push_back(v);
  return out;
}

std::vector<double> finite_numbers(const json& j, const char* what) {
  if (!j.is_array()) throw std::invalid_argument(std::string(what) + " must be a list of numbers");
  std::vector<double> v;
  for (size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_number() || !std::isfinite(j[i].get<double>()))
      throw std::invalid_argument(std::string(what) + "[" + std::to_string(i) + "] must be a finite number");
    v.push_back(j[i].get<double>());
  }
  return v;
}

constexpr size_t kScratch = 1024;  // doubles of the hot paths' scratch array
constexpr size_t kOut = 64;        // where results start in it (joint values and targets before)

}  // namespace

// A robot: the robot file loaded, its IK prepared on first use, what an import left out.
class WebRobot {
 public:
  // Loaders: "" when the robot is loaded, else the error as JSON text ({"error", "file",
  // "json_path", "problem"}). A failed load keeps the robot that was there.
  std::string load(const std::string& path) {
    return adopt([&] { return host::load_robot_file(host::resolve_robot_path(path)); }, {});
  }
  std::string parse(const std::string& text, const std::string& name) {
    return adopt([&] { return host::parse_robot(text, name); }, {});
  }
  std::string from_legacy(const std::string& text, const std::string& name, double scale) {
    if (!(scale > 0) || !std::isfinite(scale)) return error_json("scale (mm per unit) must be > 0");
    std::vector<std::string> notes;
    return adopt(
        [&] {
          const host::LegacyImport imp = host::import_legacy(text, name, scale);
          notes = imp.dropped;
          return host::parse_robot(imp.robot.dump(), name);
        },
        notes);
  }
  // RoboSim's l: other lengths a(i-1) for the adjustable rows, in row order.
  std::string set_link_lengths(const std::string& values) {
    return adopt([&] { return host::with_link_lengths(*robot_, finite_numbers(json::parse(values), "lengths")); },
                 notes_);
  }

  bool loaded() const { return robot_ != nullptr; }

  // The robot as the studio draws and describes it.
  std::string info() const {
    return guarded([&] {
      const Robot& r = *robot_;
      json home = json::array(), limits = json::array();
      for (int j = 0; j < r.model.num_joints; ++j) {
        home.push_back(size_t(j) < r.home.size() ? host::joint_from_model(r, j, r.home[size_t(j)]) : 0.0);
        limits.push_back({host::joint_from_model(r, j, r.model.joints[j].lo), host::joint_from_model(r, j, r.model.joints[j].hi)});
      }
      return json{{"name", r.name},
                  {"description", r.description},
                  {"source", r.source},
                  {"num_rows", r.model.num_rows},
                  {"num_joints", r.model.num_joints},
                  {"num_motors", r.has_motors ? int(r.actuation.num_motors) : 0},
                  {"joint_names", r.joint_names},
                  {"motor_names", r.motor_names},
                  {"joints", host::joints_json(r)},
                  {"dh", host::dh_rows_json(r)},
                  {"home", home},
                  {"limits", limits},
                  {"motors", host::motors_json(r)},
                  {"links", host::links_json(r)},
                  {"gripper", host::gripper_json(r)},
                  {"tool_offset", flat(r.model.T_last_tool)},
                  {"reach_mm", ik().reach_bound()},
                  {"import_notes", notes_}}
          .dump();
    });
  }

  // Everything a drawing of the arm at q (deg or mm) needs, in one crossing: every frame
  // (base, rows, tool; 16 numbers each), the tool's position and rpy, the DH table at q,
  // whether q is within the limits, and with a gripper opened opening_mm, its two fingers.
  std::string pose(const std::string& q_json, double opening_mm) const {
    return guarded([&] {
      const Robot& r = *robot_;
      const std::vector<double> q = model_joints(json::parse(q_json), "q");
      HostFrames f;
      forward_kinematics(f, r.model, q.data());
      json frames = json::array();
      for (int i = 0; i <= r.model.num_rows; ++i) frames.push_back(flat(f.T_base_frame[i]));
      frames.push_back(flat(f.T_base_tool));
      const Vec3<double> rpy = matrix_to_rpy(f.T_base_tool.R);
      DhRow<double> table[host::kMaxRows];
      dh_table(table, r.model, q.data());
      json dh = json::array();
      for (int i = 0; i < r.model.num_rows; ++i)
        dh.push_back({table[i].a, rad_to_deg(table[i].alpha), table[i].d, rad_to_deg(table[i].theta)});
      json out = {{"frames", frames},
                  {"tool", {{"xyz", {f.T_base_tool.p.x, f.T_base_tool.p.y, f.T_base_tool.p.z}},
                            {"rpy", {rad_to_deg(rpy.x), rad_to_deg(rpy.y), rad_to_deg(rpy.z)}}}},
                  {"dh_table", dh},
                  {"within_limits", host::within_limits(ik(), r, q)}};
      if (r.gripper.present && std::isfinite(opening_mm))
        out["fingers"] = {flat(host::finger_pose(r.gripper, f.T_base_tool, opening_mm, +1)),
                          flat(host::finger_pose(r.gripper, f.T_base_tool, opening_mm, -1))};
      return out.dump();
    });
  }

  // IK (docs/ik.md): {"target": [x,y,z(,roll,pitch,yaw)], "solver", "start", "weights",
  // "max_iterations", "tolerance_mm", "seed"} -> `articula ik --json`'s result, plus
  // beyond_reach.
  std::string ik_solve(const std::string& args_json) const {
    return guarded([&] {
      const Robot& r = *robot_;
      const json a = json::parse(args_json);
      const std::vector<double> t = finite_numbers(a.at("target"), "target");
      if (t.size() != 3 && t.size() != 6)
        throw std::invalid_argument("target must be (x, y, z) mm or (x, y, z, roll, pitch, yaw) mm and deg");
      host::IkTarget target = host::IkTarget::at(make_vec3(t[0], t[1], t[2]));
      if (t.size() == 6) {
        target.has_rotation = true;
        target.rotation = rpy_to_matrix(deg_to_rad(t[3]), deg_to_rad(t[4]), deg_to_rad(t[5]));
      }
      host::IkOptions o;
      const std::string solver = a.value("solver", "auto");
      if (!host::parse_ik_method(solver, o.method))
        throw std::invalid_argument("unknown solver '" + solver + "': one of auto, closed, lm, jt");
      if (a.contains("weights") && !a["weights"].is_null()) o.weights = finite_numbers(a["weights"], "weights");
      o.max_iterations = a.value("max_iterations", 0);
      o.position_tolerance_mm = a.value("tolerance_mm", 0.01);
      o.seed = a.value("seed", uint64_t(1));
      if (o.max_iterations < 0) throw std::invalid_argument("max_iterations must be >= 0");
      if (!(o.position_tolerance_mm > 0)) throw std::invalid_argument("tolerance_mm must be > 0");
      std::vector<double> q0 = r.home;
      q0.resize(size_t(r.model.num_joints), 0.0);
      if (a.contains("start") && !a["start"].is_null()) q0 = model_joints(a["start"], "start");
      const host::IkResult res = ik().solve(target, q0, o);
      json j = host::ik_result_json(r, res);
      j["beyond_reach"] = res.beyond_reach;
      return j.dump();
    });
  }

  // Programs: the controller model (`articula predict --json`), the kinematic model (`run
  // --json`), protocol lines through the firmware's arithmetic (`quantize --json`).
  std::string predict(const std::string& text, const std::string& name, const std::string& settings) const {
    return guarded([&] {
      const Robot& r = *robot_;
      if (!r.has_motors)
        throw std::invalid_argument(r.name + " has no motors: there are no steps to predict (run executes programs "
                                             "on the kinematic model)");
      const host::Program p = host::parse_program(text, name, r);
      host::ControllerSettings s;
      if (!settings.empty()) host::apply_settings_text(s, settings, r.actuation.num_motors);
      return host::prediction_json(r, p, host::predict_program(r, p, s)).dump();
    });
  }
  std::string run(const std::string& text, const std::string& name) const {
    return guarded([&] {
      const host::Program p = host::parse_program(text, name, *robot_);
      return host::run_json(*robot_, p, host::run_program(*robot_, p)).dump();
    });
  }
  std::string quantize(const std::string& lines_json) const {
    return guarded([&] {
      const Robot& r = *robot_;
      if (!r.has_motors) throw std::invalid_argument(r.name + " has no motors: nothing to quantize");
      json out = json::array();
      for (const auto& q : host::quantize_lines(r, json::parse(lines_json).get<std::vector<std::string>>()))
        out.push_back(host::quantize_record_json(r, q));
      return out.dump();
    });
  }
  std::string program_format(const std::string& text, const std::string& name) const {
    return host::detect_format(text, name) == host::Program::Format::kRoboSim ? "robosim" : "protocol";
  }

  std::string urdf() const {
    return guarded([&] { return json{{"xml", host::export_urdf(*robot_).xml}}.dump(); });
  }

  // q = C u and u = C^-1 q: joint variables (deg or mm) from motor angles (deg) and back.
  std::string joints_from_motors(const std::string& u_json) const {
    return guarded([&] {
      const Robot& r = *robot_;
      if (!r.has_motors) throw std::invalid_argument(r.name + " has no motors");
      const std::vector<double> u = finite_numbers(json::parse(u_json), "motor angles");
      if (u.size() != size_t(r.actuation.num_motors))
        throw std::invalid_argument("motor angles has " + std::to_string(u.size()) + " values; " + r.name + " has " +
                                    std::to_string(r.actuation.num_motors) + " motors");
      double u_rad[host::kMaxJoints], q[host::kMaxJoints];
      for (size_t i = 0; i < u.size(); ++i) u_rad[i] = deg_to_rad(u[i]);
      joints_from_actuators(q, r.actuation, u_rad);
      return joints_out(q).dump();
    });
  }
  std::string motors_from_joints(const std::string& q_json) const {
    return guarded([&] {
      const Robot& r = *robot_;
      if (!r.has_motors) throw std::invalid_argument(r.name + " has no motors");
      const std::vector<double> q = model_joints(json::parse(q_json), "q");
      double u[host::kMaxJoints];
      actuators_from_joints(u, r.actuation, q.data());
      json out = json::array();
      for (int i = 0; i < r.actuation.num_motors; ++i) out.push_back(rad_to_deg(u[i]));
      return out.dump();
    });
  }

  // ---- the hot paths, on the scratch array (scratch(): its address in the heap, in bytes)

  uintptr_t scratch() const { return reinterpret_cast<uintptr_t>(scratch_.data()); }
  // The tool pose at the joint values in scratch[0..n) (model units: rad or mm), into
  // scratch[64..80) as a row-major 4x4.
  void fk_scratch() const {
    HostFrames f;
    forward_kinematics(f, robot_->model, scratch_.data());
    const Transform<double>& T = f.T_base_tool;
    double* out = scratch_.data() + kOut;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) out[4 * i + k] = T.R.m[i][k];
      out[4 * i + 3] = T.p[i];
    }
    out[12] = out[13] = out[14] = 0;
    out[15] = 1;
  }
  // IK from the start in scratch[0..n) to the target in scratch[32..32+len) (mm; rpy in rad
  // when len is 6), solver 0 auto, 1 closed, 2 lm, 3 jt: q into scratch[64..64+n), the
  // position error into scratch[63]; returns the status (0 reached ... 3 budget).
  int ik_scratch(int len, int solver) const {
    const double* t = scratch_.data() + 32;
    host::IkTarget target = host::IkTarget::at(make_vec3(t[0], t[1], t[2]));
    if (len == 6) {
      target.has_rotation = true;
      target.rotation = rpy_to_matrix(t[3], t[4], t[5]);
    }
    host::IkOptions o;
    static const host::IkMethod kMethods[] = {host::IkMethod::kAuto, host::IkMethod::kClosedForm, host::IkMethod::kLevenbergMarquardt,
                                              host::IkMethod::kJacobianTranspose};
    o.method = kMethods[solver & 3];
    const size_t n = size_t(robot_->model.num_joints);
    const std::vector<double> q0(scratch_.data(), scratch_.data() + n);
    const host::IkResult res = ik().solve(target, q0, o);
    std::copy(res.q.begin(), res.q.end(), scratch_.data() + kOut);
    scratch_[kOut - 1] = res.position_error_mm;
    return int(res.status);
  }

  std::shared_ptr<const Robot> shared() const { return robot_; }

 private:
  template <typename F>
  std::string adopt(F&& make, const std::vector<std::string>& notes) {
    std::string err = guarded([&] {
      auto r = std::make_shared<const Robot>(make());
      robot_ = std::move(r);
      ik_.reset();
      return std::string();
    });
    if (err.empty()) notes_ = notes;
    return err;
  }

  const host::InverseKinematics& ik() const {
    if (!ik_) ik_ = std::make_shared<const host::InverseKinematics>(*robot_);
    return *ik_;
  }

  // Joint values (deg or mm, one per joint variable) into model units, checked.
  std::vector<double> model_joints(const json& j, const char* what) const {
    const Robot& r = *robot_;
    const std::vector<double> v = finite_numbers(j, what);
    if (v.size() != size_t(r.model.num_joints))
      throw std::invalid_argument(std::string(what) + " has " + std::to_string(v.size()) + " values; " + r.name +
                                  " has " + std::to_string(r.model.num_joints) + " joint variables");
    std::vector<double> q(v.size());
    for (size_t k = 0; k < v.size(); ++k) q[k] = host::joint_to_model(r, int(k), v[k]);
    return q;
  }
  json joints_out(const double* q) const {
    json out = json::array();
    for (int j = 0; j < robot_->model.num_joints; ++j) out.push_back(host::joint_from_model(*robot_, j, q[j]));
    return out;
  }

  std::shared_ptr<const Robot> robot_;
  std::vector<std::string> notes_;
  mutable std::shared_ptr<const host::InverseKinematics> ik_;
  mutable std::vector<double> scratch_ = std::vector<double>(kScratch, 0.0);
};

// The arm and a scene in ODE (host/physics/sim.h), stepped from JavaScript.
class WebSim {
 public:
  // The robot (its state now) in a scene given as its file's text ("" for the ground only);
  // "" when made, else the error as JSON text.
  std::string create(const WebRobot& robot, const std::string& scene_text, const std::string& scene_name, double dt) {
    return guarded([&] {
      if (!robot.loaded()) throw std::invalid_argument("no robot loaded");
      if (!(dt > 0 && dt <= 0.01)) throw std::invalid_argument("dt (the world step, s) must be in (0, 0.01]");
      host::Scene scene;
      if (!scene_text.empty()) scene = host::parse_scene(scene_text, scene_name);
      host::SimOptions options;
      options.dt = dt;
      auto sim = std::make_unique<host::Simulation>(*robot.shared(), scene, options);
      robot_ = robot.shared();
      scene_ = std::move(scene);
      options_ = options;
      sim_ = std::move(sim);
      return std::string();
    });
  }
  void reset() {
    if (robot_) sim_ = std::make_unique<host::Simulation>(*robot_, scene_, options_);
  }

  void step(int n) {
    for (int i = 0; i < n; ++i) sim_->step();
  }
  void run_until(double t) {
    if (std::isfinite(t)) sim_->run_until(t);
  }
  std::string load_program(const std::string& text, const std::string& name) {
    return guarded([&] {
      sim_->load_program(host::parse_program(text, name, *robot_));
      return std::string();
    });
  }
  // One protocol line for the simulated controller: "ok" or "error:N", as the arm answers.
  std::string command(const std::string& line) { return host::reply_text(sim_->command(line)); }
  // The events from index `since` on, as `articula sim --events` writes them.
  std::string events(int since) const {
    json out = json::array();
    const auto& ev = sim_->events();
    for (size_t i = size_t(std::max(0, since)); i < ev.size(); ++i) out.push_back(host::event_json(ev[i]));
    return out.dump();
  }
  // The world now: t, joints (deg or mm), frames, gripper_mm, counted_steps, lost_steps, busy,
  // objects (name, pose, movable, carried, removed), contacts [a, b].
  std::string state() const {
    const host::Simulation& s = *sim_;
    const Robot& r = *robot_;
    json q = json::array(), frames = json::array(), objects = json::array(), contacts = json::array();
    for (int j = 0; j < r.model.num_joints; ++j) q.push_back(host::joint_from_model(r, j, s.joints()[size_t(j)]));
    for (int i = 0; i <= r.model.num_rows; ++i) frames.push_back(flat(s.frames().T_base_frame[i]));
    frames.push_back(flat(s.frames().T_base_tool));
    for (int i = 0; i < s.num_objects(); ++i)
      objects.push_back({{"name", s.object(i).name},
                         {"pose", flat(s.object_pose(i))},
                         {"movable", s.object(i).movable},
                         {"carried", s.object_carried(i)},
                         {"removed", s.object_removed(i)}});
    for (const auto& c : s.contacts()) contacts.push_back({c.a, c.b});
    return json{{"t", s.time()},           {"joints", q},
                {"frames", frames},        {"gripper_mm", s.gripper_opening_mm()},
                {"counted_steps", s.counted_steps()}, {"lost_steps", s.lost_steps()},
                {"busy", s.busy()},        {"objects", objects},
                {"contacts", contacts}}
        .dump();
  }
  // The scene's objects: name, type, size (mm), movable, mass_kg, friction.
  std::string objects() const {
    static const char* kTypes[] = {"box", "cylinder", "sphere"};
    json out = json::array();
    for (const auto& o : scene_.objects)
      out.push_back({{"name", o.name},
                     {"type", kTypes[int(o.type)]},
                     {"size", {o.size[0], o.size[1], o.size[2]}},
                     {"movable", o.movable},
                     {"mass_kg", o.movable ? o.mass_kg() : 0.0},
                     {"friction", o.friction}});
    return out.dump();
  }
  // A mouse drag of the movable object `name` toward (x, y, z) mm; "" or the error as JSON.
  std::string drag(const std::string& name, double x, double y, double z) {
    return guarded([&] {
      if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z)))
        throw std::invalid_argument("drag: the target must be finite (x, y, z) mm");
      for (int i = 0; i < sim_->num_objects(); ++i)
        if (sim_->object(i).name == name) {
          sim_->drag_object(i, make_vec3(x, y, z));
          return std::string();
        }
      throw std::invalid_argument("drag: no object named '" + name + "' in the scene");
    });
  }
  void release() { sim_->release_drag(); }

  double time() const { return sim_->time(); }
  double dt() const { return options_.dt; }
  bool busy() const { return sim_->busy(); }
  bool done() const { return sim_->done(); }
  double end_time() const { return sim_->end_time(); }
  std::string scene_name() const { return scene_.name; }

 private:
  std::shared_ptr<const Robot> robot_;
  host::Scene scene_;
  host::SimOptions options_;
  std::unique_ptr<host::Simulation> sim_;
};

// One stepper motor's four L298N inputs as the virtual Nano in the page sees them: the
// harness's decoder (hil/vnano/coil_decoder.h), the one home of what a motor makes of its
// coil patterns, for the page's emulated Nano (avr8js).
class WebCoilDecoder {
 public:
  // A new IN1..IN4 pattern (bit 0 = IN1): 0 no change, 1 a step, 2 released, 3 energised,
  // 4 a fault (a pattern the motor cannot follow).
  int feed(int pattern) {
    const vnano::CoilChange c = d_.feed(uint8_t(pattern));
    if (c.event == vnano::CoilEvent::kFault) ++faults_;
    return int(c.event);
  }
  void force_half_step() { d_.force_half_step(); }
  double steps() const { return double(d_.steps()); }
  double half_steps() const { return double(d_.half_steps()); }
  int faults() const { return faults_; }
  int pattern() const { return d_.pattern(); }

 private:
  vnano::CoilDecoder d_;
  int faults_ = 0;
};

// The Nano's wiring (hil/vnano/wiring.h): ports "B", "C", "D"; motors [{port, shift}],
// endstops [{port, bit}], servo and led {port, bit}.
std::string nano_wiring() {
  json motors = json::array(), endstops = json::array();
  for (int m = 0; m < vnano::kWiredMotors; ++m) {
    motors.push_back({{"port", std::string(1, vnano::kPortNames[vnano::kMotorPins[m].port])},
                      {"shift", vnano::kMotorPins[m].shift}});
    endstops.push_back({{"port", std::string(1, vnano::kPortNames[vnano::kEndstopPins[m].port])},
                        {"bit", vnano::kEndstopPins[m].bit}});
  }
  return json{{"motors", motors},
              {"endstops", endstops},
              {"servo", {{"port", std::string(1, vnano::kPortNames[vnano::kServoPort])}, {"bit", vnano::kServoBit}}},
              {"led", {{"port", std::string(1, vnano::kPortNames[vnano::kLedPort])}, {"bit", vnano::kLedBit}}}}
      .dump();
}

// A line from the arm, read by the core's own parsers (shared/articula/protocol.h): a reply
// {"kind": "reply", "code"}, a status report {"kind": "status", "state", "steps", "angles"
// (deg), "gripper", "free", "coils", "warning"}, the banner {"kind": "info", "version",
// "protocol", "joints", "robot", "warning"}, or {"kind": "other"}.
std::string parse_arm_line(const std::string& text) {
  const char* line = text.c_str();
  const uint16_t len = uint16_t(std::min<size_t>(text.size(), 1000));
  uint8_t code = 0;
  if (len < 256 && parse_reply(code, line, uint8_t(len))) return json{{"kind", "reply"}, {"code", code}}.dump();
  StatusReport<8> st;
  if (parse_status(st, line, len)) {
    json steps = json::array(), angles = json::array();
    for (int i = 0; i < st.num_joints; ++i) {
      steps.push_back(st.steps[i]);
      angles.push_back(st.millideg[i] / 1000.0);
    }
    return json{{"kind", "status"}, {"state", kStateWords[st.state]}, {"steps", steps}, {"angles", angles},
                {"gripper", st.gripper}, {"free", st.free_slots}, {"coils", st.coils}, {"warning", st.warning}}
        .dump();
  }
  InfoReport info;
  if (parse_info(info, line, len))
    return json{{"kind", "info"},
                {"version", std::to_string(info.version[0]) + "." + std::to_string(info.version[1]) + "." +
                                std::to_string(info.version[2])},
                {"protocol", info.protocol},
                {"joints", info.num_joints},
                {"robot", std::string(info.name)},
                {"warning", info.warning}}
        .dump();
  return json{{"kind", "other"}}.dump();
}

// The first step interval of a move from rest at these settings (shared/articula/motion.h's
// profile_constants), s: no pin shows when a move starts, so an emulated Nano's measured
// duration is this plus the span of the move's steps (the harness measures it so).
double first_interval_s(double max_rate, double accel) {
  ProfileConstants k;
  const MotionSettings s{2000000UL, uint32_t(max_rate), uint32_t(accel)};
  if (profile_constants(k, s) != kMotionOk) return -1;
  return k.first / 2e6;
}

// The protocol's status table (shared/articula/status.h): {code: [name, text]}.
std::string status_table() {
  json out = json::object();
  for (uint8_t c = 0; c < kStatusCount; ++c) out[std::to_string(c)] = {status_name(c), status_text(c)};
  return out.dump();
}

}  // namespace articula::web

EMSCRIPTEN_BINDINGS(articula) {
  using namespace emscripten;
  using articula::web::WebRobot;
  using articula::web::WebCoilDecoder;
  using articula::web::WebSim;
  class_<WebRobot>("Robot")
      .constructor<>()
      .function("load", &WebRobot::load)
      .function("parse", &WebRobot::parse)
      .function("fromLegacy", &WebRobot::from_legacy)
      .function("setLinkLengths", &WebRobot::set_link_lengths)
      .function("loaded", &WebRobot::loaded)
      .function("info", &WebRobot::info)
      .function("pose", &WebRobot::pose)
      .function("ik", &WebRobot::ik_solve)
      .function("predict", &WebRobot::predict)
      .function("run", &WebRobot::run)
      .function("quantize", &WebRobot::quantize)
      .function("programFormat", &WebRobot::program_format)
      .function("urdf", &WebRobot::urdf)
      .function("jointsFromMotors", &WebRobot::joints_from_motors)
      .function("motorsFromJoints", &WebRobot::motors_from_joints)
      .function("scratch", &WebRobot::scratch)
      .function("fkScratch", &WebRobot::fk_scratch)
      .function("ikScratch", &WebRobot::ik_scratch);
  class_<WebSim>("Sim")
      .constructor<>()
      .function("create", &WebSim::create)
      .function("reset", &WebSim::reset)
      .function("step", &WebSim::step)
      .function("runUntil", &WebSim::run_until)
      .function("loadProgram", &WebSim::load_program)
      .function("command", &WebSim::command)
      .function("events", &WebSim::events)
      .function("state", &WebSim::state)
      .function("objects", &WebSim::objects)
      .function("drag", &WebSim::drag)
      .function("release", &WebSim::release)
      .function("time", &WebSim::time)
      .function("dt", &WebSim::dt)
      .function("busy", &WebSim::busy)
      .function("done", &WebSim::done)
      .function("endTime", &WebSim::end_time)
      .function("sceneName", &WebSim::scene_name);
  class_<WebCoilDecoder>("CoilDecoder")
      .constructor<>()
      .function("feed", &WebCoilDecoder::feed)
      .function("forceHalfStep", &WebCoilDecoder::force_half_step)
      .function("steps", &WebCoilDecoder::steps)
      .function("halfSteps", &WebCoilDecoder::half_steps)
      .function("faults", &WebCoilDecoder::faults)
      .function("pattern", &WebCoilDecoder::pattern);
  function("statusText", +[](int code) { return std::string(articula::status_text(uint8_t(code))); });
  function("statusTable", &articula::web::status_table);
  function("nanoWiring", &articula::web::nano_wiring);
  function("parseArmLine", &articula::web::parse_arm_line);
  function("firstIntervalS", &articula::web::first_interval_s);
  function("servoAngleDeg", &vnano::servo_angle_deg);
  function("servoAperturePercent", &vnano::servo_aperture_percent);
}
