// wasm/src/cell.cpp - a cell of arms for JavaScript (the twin of python/src/cell.cpp): several
// arms, each on its own firmware, in one world (host/physics/cell_sim.h), stepped from JavaScript.
// The robots, scenes and programs a cell names by path or name are read from the engine's
// in-memory files (engine.writeFile: /robots, /scenes, /cells).
#include <emscripten/bind.h>

#include "cell_file.h"
#include "cell_sim.h"
#include "mat.h"
#include "common.h"
#include "sim_view.h"
#include "records_json.h"

namespace articula::web {

class WebCell {
 public:
  // The cell from its file's text (`name` stands for the file, `dir` its folder); "" when made,
  // else the error as JSON text (a CellError's JSON path with it).
  std::string create(const std::string& text, const std::string& name, const std::string& dir, double dt) {
    return guarded([&] {
      if (!(dt > 0 && dt <= 0.01)) throw std::invalid_argument("dt (the world step, s) must be in (0, 0.01]");
      host::Cell cell = host::parse_cell(text, name, dir);
      host::SimOptions options;
      options.dt = dt;
      sim_ = std::make_unique<host::CellSimulation>(cell, options);
      options_ = options;
      return std::string();
    });
  }
  void reset() {
    if (sim_) sim_ = std::make_unique<host::CellSimulation>(host::Cell(sim_->cell()), options_);
  }
  void step(int n) {
    for (int i = 0; i < n; ++i) sim_->step();
  }
  void run_until(double t) {
    if (std::isfinite(t)) sim_->run_until(t);
  }
  void run() {
    while (!sim_->done()) sim_->step();
  }
  // One arm now (host/physics/cell_sim.h's cell_arms_json), by name; the error as JSON if none.
  std::string arm(const std::string& name) const {
    const int i = sim_->cell().arm_index(name);
    if (i < 0) return error_json("the cell has no arm '" + name + "'");
    return host::cell_arms_json(*sim_)[size_t(i)].dump();
  }
  std::string arms() const {
    json out = json::array();
    for (const auto& a : sim_->cell().arms) out.push_back(a.name);
    return out.dump();
  }
  std::string state() const { return host::cell_state_json(*sim_).dump(); }
  std::string events(int since) const {
    json out = json::array();
    const auto& ev = sim_->world().events();
    for (size_t i = size_t(std::max(0, since)); i < ev.size(); ++i) out.push_back(host::event_json(ev[i]));
    return out.dump();
  }
  std::string name() const { return sim_->cell().name; }
  // The scene's objects as the cell file gives them (sim_view.h's scene_objects_json).
  std::string objects() const { return host::scene_objects_json(sim_->cell().scene).dump(); }
  double time() const { return sim_->time(); }
  bool done() const { return sim_->done(); }
  double end_time() const { return sim_->end_time(); }
  std::string deadlock() const { return sim_->deadlock(); }
  // The table's mat (host/physics/mat.h): an SVG document, 1:1 in mm.
  std::string mat_svg() const { return host::mat_svg(sim_->cell()); }
  // One arm's prediction in the cell (host/physics/cell_sim.h's predict_in_cell) as
  // `articula predict CELL ARM --json` gives it; the error as JSON.
  std::string predict(const std::string& name) const {
    return guarded([&] {
      const host::CellArm& arm = sim_->cell().arms[size_t(host::cell_arm_index(sim_->cell(), name))];
      return host::prediction_json(arm.robot, arm.program, host::predict_in_cell(sim_->cell(), name)).dump();
    });
  }

 private:
  host::SimOptions options_;
  std::unique_ptr<host::CellSimulation> sim_;
};

}  // namespace articula::web

EMSCRIPTEN_BINDINGS(articula_cell) {
  using namespace emscripten;
  using articula::web::WebCell;
  class_<WebCell>("Cell")
      .constructor<>()
      .function("create", &WebCell::create)
      .function("reset", &WebCell::reset)
      .function("step", &WebCell::step)
      .function("runUntil", &WebCell::run_until)
      .function("run", &WebCell::run)
      .function("arm", &WebCell::arm)
      .function("arms", &WebCell::arms)
      .function("state", &WebCell::state)
      .function("events", &WebCell::events)
      .function("name", &WebCell::name)
      .function("objects", &WebCell::objects)
      .function("time", &WebCell::time)
      .function("done", &WebCell::done)
      .function("endTime", &WebCell::end_time)
      .function("deadlock", &WebCell::deadlock)
      .function("matSvg", &WebCell::mat_svg)
      .function("predict", &WebCell::predict);
}
