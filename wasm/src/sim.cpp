// wasm/src/sim.cpp - the physics for JavaScript (the twin of python/src/sim.cpp): the arm and a
// scene in ODE (host/physics/sim.h), stepped from JavaScript.
#include <emscripten/bind.h>

#include "robot.h"
#include "scene.h"
#include "sim.h"
#include "sim_view.h"

namespace articula::web {

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
  // From power-up, the objects where the scene file has them.
  void reset() {
    if (robot_) sim_ = std::make_unique<host::Simulation>(*robot_, scene_, options_);
  }
  // From power-up, each object a drag let go of where it was let go (Simulation::scene_as_placed):
  // a program's run starts from where the student put things.
  void restart() {
    if (robot_ && sim_) sim_ = std::make_unique<host::Simulation>(*robot_, sim_->scene_as_placed(), options_);
  }

  void step(int n) {
    for (int i = 0; i < n; ++i) sim_->step();
  }
  // `n` world steps and the tool point after every `every`-th and the last (Simulation::
  // step_path): a view of this object's buffer, valid until the next call (copy it).
  emscripten::val step_path(int n, int every) {
    path_.clear();
    sim_->step_path(n, every, path_);
    return emscripten::val(emscripten::typed_memory_view(path_.size(), path_.data()));
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
  // The world now (host/physics/sim_view.h): t, joints, frames, tool, gripper_mm,
  // counted_steps, lost_steps, busy, parts, objects, contacts.
  std::string state() const { return host::sim_state_json(*sim_).dump(); }
  // The scene's objects: name, type, size (mm), movable, mass_kg, friction.
  std::string objects() const { return host::scene_objects_json(scene_).dump(); }
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
  // A belt of the scene (the object `name`, with a "belt" speed) run at mm_s (0 stops it); "" or
  // the error as JSON (World::set_belt's words).
  std::string set_belt(const std::string& name, double mm_s) {
    return guarded([&] {
      for (int i = 0; i < sim_->num_objects(); ++i)
        if (sim_->object(i).name == name) {
          sim_->set_belt(i, mm_s);
          return std::string();
        }
      throw std::invalid_argument("setBelt: no object named '" + name + "' in the scene");
    });
  }

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
  std::vector<double> path_;
};

}  // namespace articula::web

EMSCRIPTEN_BINDINGS(articula_sim) {
  using namespace emscripten;
  using articula::web::WebSim;
  class_<WebSim>("Sim")
      .constructor<>()
      .function("create", &WebSim::create)
      .function("reset", &WebSim::reset)
      .function("restart", &WebSim::restart)
      .function("step", &WebSim::step)
      .function("stepPath", &WebSim::step_path)
      .function("runUntil", &WebSim::run_until)
      .function("loadProgram", &WebSim::load_program)
      .function("command", &WebSim::command)
      .function("events", &WebSim::events)
      .function("state", &WebSim::state)
      .function("objects", &WebSim::objects)
      .function("drag", &WebSim::drag)
      .function("release", &WebSim::release)
      .function("setBelt", &WebSim::set_belt)
      .function("time", &WebSim::time)
      .function("dt", &WebSim::dt)
      .function("busy", &WebSim::busy)
      .function("done", &WebSim::done)
      .function("endTime", &WebSim::end_time)
      .function("sceneName", &WebSim::scene_name);
  // the world step's default, from the C++ option struct
  constant("defaultDt", articula::host::SimOptions().dt);
}
