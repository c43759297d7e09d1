// python/src/cell.cpp - articula.Cell: a cell of arms (host/physics/cell_sim.h), each on its own
// firmware, in one world, stepped from Python: each arm's state and the events naming the arm.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>

#include "bindings.h"
#include "cell_file.h"
#include "cell_sim.h"
#include "mat.h"
#include "records_json.h"
#include "sim_view.h"

namespace articula::python {
namespace {

using namespace nb::literals;

struct PyCell {
  host::Cell cell;
  host::SimOptions options;
  std::unique_ptr<host::CellSimulation> sim;

  void build() { sim = std::make_unique<host::CellSimulation>(cell, options); }

  int arm_index(nb::handle which) const {
    if (nb::isinstance<nb::int_>(which)) {
      const int i = nb::cast<int>(which);
      if (i < 0 || i >= int(cell.arms.size()))
        throw nb::index_error(("no arm " + std::to_string(i) + ": the cell has " + std::to_string(cell.arms.size())).c_str());
      return i;
    }
    const std::string name = nb::cast<std::string>(which);
    const int i = cell.arm_index(name);
    if (i < 0) {
      throw nb::key_error(("the cell has no arm '" + name + "' (its arms: " + host::cell_arm_names(cell) + ")").c_str());
    }
    return i;
  }
};

}  // namespace

void bind_cell(nb::module_& m) {
  nb::class_<PyCell>(m, "Cell",
                     "A cell (cells/README.md): several arms on one table, each on its own firmware (a virtual Nano "
                     "each), running its own program from t = 0 in one world of objects, all on one clock. What "
                     "`articula sim CELL` does, one step at a time.\n\n"
                     ">>> cell = Cell('handover')\n>>> cell.arms\n['giver', 'taker']\n>>> cell.run()\n"
                     ">>> [e.arm for e in cell.events() if e.kind == 'grasp']\n['giver', 'taker']")
      .def("__init__",
           [](PyCell* self, nb::handle file, nb::handle programs, double dt, bool quick_step, double extra_time) {
             new (self) PyCell();
             nb::object os = nb::module_::import_("os");
             self->cell = host::load_cell_file(host::resolve_cell_path(nb::cast<std::string>(os.attr("fspath")(file))));
             if (!programs.is_none()) {
               for (auto item : nb::borrow<nb::dict>(programs)) {
                 const std::string arm = nb::cast<std::string>(item.first);
                 const int i = self->arm_index(nb::str(arm.c_str()));
                 host::set_cell_program(self->cell, arm, program_from(item.second, self->cell.arms[size_t(i)].robot));
               }
             }
             if (!(dt > 0 && dt <= 0.01)) throw nb::value_error("dt (the world step, s) must be in (0, 0.01]");
             if (!(extra_time >= 0) || !std::isfinite(extra_time)) throw nb::value_error("extra_time must be >= 0");
             self->options.dt = dt;
             self->options.quick_step = quick_step;
             self->options.extra_time = extra_time;
             self->build();
           },
           "cell"_a, "programs"_a = nb::none(), nb::kw_only(), "dt"_a = host::SimOptions().dt, "quick_step"_a = false,
           "extra_time"_a = host::SimOptions().extra_time,
           "cell: a shipped cell's name ('handover') or a cell file. programs: {arm name: Program or path} instead "
           "of the file's. dt: the world step, s. extra_time: how long done waits after the last program ends.")
      .def("step",
           [](PyCell& c, int n) {
             if (n < 0) throw nb::value_error("n must be >= 0");
             nb::gil_scoped_release release;
             for (int i = 0; i < n; ++i) c.sim->step();
           },
           "n"_a = 1, "Advances the world n steps of dt: every arm's firmware and ODE together.")
      .def("run_until",
           [](PyCell& c, double t) {
             if (!std::isfinite(t)) throw nb::value_error("t must be finite");
             nb::gil_scoped_release release;
             c.sim->run_until(t);
           },
           "t"_a, "Steps until time >= t (s).")
      .def("run",
           [](PyCell& c) {
             nb::gil_scoped_release release;
             while (!c.sim->done()) c.sim->step();
           },
           "Steps until every arm's program has ended and extra_time has passed.")
      .def("arm",
           [](const PyCell& c, nb::handle which) {
             return record(host::cell_arms_json(*c.sim)[size_t(c.arm_index(which))]);
           },
           "which"_a,
           "One arm now (by name or index): name, robot, io (its I/O pins: name, pin, mode), program, program_end_s, line, joints (deg or mm), tool_mm "
           "(on the table), gripper_mm, counted_steps, lost_steps, signals (each output set and input waited for: kind "
           "'output' or 'wait', line, pin, name, level, t, a wait's end_t and met: True when its input read the level, False "
           "when it ran out).")
      .def("state", [](const PyCell& c) { return record(host::cell_state_json(*c.sim)); },
           "The cell now: t, arms (as arm()), objects (name, xyz_mm, carried_by: the arm holding it or None, removed).")
      .def("events",
           [](const PyCell& c, size_t since) {
             nb::list out;
             const auto& ev = c.sim->world().events();
             for (size_t i = since; i < ev.size(); ++i) out.append(record(host::event_json(ev[i])));
             return out;
           },
           "since"_a = 0,
           "The events so far (or from index `since`), as `articula sim CELL --json` gives them: t, kind, arm (the arm "
           "whose action it is; none for a contact between objects), line, a, b (another arm's part: 'right: link 3'), "
           "point_mm, detail.")
      .def("predict",
           [](const PyCell& c, nb::handle which) {
             const host::CellArm& arm = c.cell.arms[size_t(c.arm_index(which))];
             if (!arm.robot.has_motors)
               throw nb::value_error((arm.name + " (" + arm.robot.name + ") has no motors: there are no steps to predict").c_str());
             host::Prediction p;
             {
               nb::gil_scoped_release release;
               p = host::predict_in_cell(c.cell, arm.name);
             }
             return record(host::prediction_json(arm.robot, arm.program, p));
           },
           "which"_a,
           "What one arm (by name or index) will do with its program in the cell, step for step, as Robot.predict "
           "gives it (`articula predict CELL ARM --json`), with its inputs driven through the cell's wires by the "
           "other arms' firmwares running their programs beside it: each W ends when the other arm's output "
           "changed. Its own firmware, its own clock: the world's objects play no part.")
      .def("reset", [](PyCell& c) { c.build(); }, "Back to t = 0: every arm at power-up, its program loaded again.")
      .def("mat_svg", [](const PyCell& c) { return host::mat_svg(c.cell); },
           "The table's mat: a 1:1 drawing from above (SVG, mm) to print at 100 % and lay the real parts on "
           "(`articula mat CELL`).")
      .def_prop_ro("arms", [](const PyCell& c) {
        std::vector<std::string> out;
        for (const auto& a : c.cell.arms) out.push_back(a.name);
        return out;
      }, "the arms' names, in the file's order")
      .def_prop_ro("name", [](const PyCell& c) { return c.cell.name; })
      .def_prop_ro("objects", [](const PyCell& c) { return record(host::scene_objects_json(c.cell.scene)); },
                   "The scene's objects as the cell file gives them: name, type, size (mm), movable, mass_kg, friction.")
      .def_prop_ro("time", [](const PyCell& c) { return c.sim->time(); }, "simulated time, s")
      .def_prop_ro("done", [](const PyCell& c) { return c.sim->done(); })
      .def_prop_ro("deadlock", [](const PyCell& c) { return c.sim->deadlock(); },
                   "The last deadlock in words (the arms each waiting for a signal none will give), or ''.")
      .def_prop_ro("end_time", [](const PyCell& c) { return c.sim->end_time(); })
      .def("__repr__", [](const PyCell& c) {
        return "<Cell '" + c.cell.name + "': " + std::to_string(c.cell.arms.size()) + " arms, t = " +
               std::to_string(c.sim->time()).substr(0, std::to_string(c.sim->time()).find('.') + 4) + " s>";
      });
}

}  // namespace articula::python
