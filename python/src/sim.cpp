// python/src/sim.cpp - articula.Sim: the arm and a scene as rigid bodies in ODE
// (host/physics/sim.h), stepped from Python: programs or single protocol lines for the
// simulated controller, the state of every link and object, events, and a mouse drag.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>

#include "bindings.h"
#include "program.h"
#include "records_json.h"
#include "scene.h"
#include "sim.h"
#include "sim_view.h"

namespace articula::python {
namespace {

using namespace nb::literals;

struct PySim {
  std::shared_ptr<const Robot> robot;
  host::Scene scene;
  host::SimOptions options;
  std::unique_ptr<host::Simulation> sim;

  void build() { sim = std::make_unique<host::Simulation>(*robot, scene, options); }

  int object_index(nb::handle which) const {
    if (nb::isinstance<nb::int_>(which)) {
      const int i = nb::cast<int>(which);
      if (i < 0 || i >= sim->num_objects())
        throw nb::index_error(("no object " + std::to_string(i) + ": the scene has " + std::to_string(sim->num_objects())).c_str());
      return i;
    }
    const std::string name = nb::cast<std::string>(which);
    for (int i = 0; i < sim->num_objects(); ++i)
      if (sim->object(i).name == name) return i;
    throw nb::key_error(("no object named '" + name + "' in the scene").c_str());
  }
};

// A 4x4 pose from the shared JSON form (16 numbers, row-major) as a numpy array.
Array44 pose_array(const nlohmann::json& flat) {
  Array44 a = new_array44();
  for (size_t k = 0; k < 16; ++k) a.data()[k] = flat[k].get<double>();
  return a;
}

// The world now, as host/physics/sim_view.h describes it (the web engine hands out the same),
// with numpy arrays for the joints and the poses.
nb::dict state(const PySim& s) {
  const nlohmann::json j = host::sim_state_json(*s.sim);
  nb::dict d = nb::borrow<nb::dict>(json_to_python(j));
  Array q = new_array({j["joints"].size()});
  for (size_t k = 0; k < j["joints"].size(); ++k) q.data()[k] = j["joints"][k].get<double>();
  d["joints"] = q;
  Array frames = new_array({j["frames"].size(), 4, 4});
  for (size_t i = 0; i < j["frames"].size(); ++i)
    for (size_t k = 0; k < 16; ++k) frames.data()[16 * i + k] = j["frames"][i][k].get<double>();
  d["frames"] = frames;
  d["tool"] = pose_array(j["tool"]);
  nb::list parts = nb::borrow<nb::list>(d["parts"]), objects = nb::borrow<nb::list>(d["objects"]);
  for (size_t i = 0; i < j["parts"].size(); ++i) nb::borrow<nb::dict>(parts[i])["pose"] = pose_array(j["parts"][i]["pose"]);
  for (size_t i = 0; i < j["objects"].size(); ++i)
    nb::borrow<nb::dict>(objects[i])["pose"] = pose_array(j["objects"][i]["pose"]);
  nb::list contacts = nb::borrow<nb::list>(d["contacts"]);
  for (size_t i = 0; i < j["contacts"].size(); ++i) {
    const auto& p = j["contacts"][i]["point_mm"];
    nb::borrow<nb::dict>(contacts[i])["point_mm"] = nb::make_tuple(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  }
  return d;
}

nb::list scene_objects(const PySim& s) {
  nb::list out = nb::borrow<nb::list>(json_to_python(host::scene_objects_json(s.scene)));
  for (size_t i = 0; i < out.size(); ++i) {
    nb::dict o = nb::borrow<nb::dict>(out[i]);
    nb::list size = nb::borrow<nb::list>(o["size"]);
    o["size"] = nb::make_tuple(size[0], size[1], size[2]);
  }
  return out;
}

}  // namespace

void bind_sim(nb::module_& m) {
  nb::class_<PySim>(m, "Sim",
                    "The arm and a scene as rigid bodies in the Open Dynamics Engine (docs/physics.md): links follow "
                    "the motors' step counts as the firmware times them, objects fall, slide, are pushed and "
                    "grasped. What `articula sim` does, one step at a time.\n\n"
                    ">>> sim = Sim(Robot.load('mk2plus'), scene='grasp-and-lift')\n"
                    ">>> sim.command('L 0 10')\n'ok'\n>>> sim.step(1000)")
      .def("__init__",
           [](PySim* self, const PyRobot& robot, nb::handle scene, double dt, nb::handle settings, bool quick_step,
              double extra_time, bool stall_check) {
             new (self) PySim();
             self->robot = robot.robot;
             if (!scene.is_none()) {
               nb::object os = nb::module_::import_("os");
               self->scene = host::load_scene_file(host::resolve_scene_path(nb::cast<std::string>(os.attr("fspath")(scene))));
             }
             if (!(dt > 0 && dt <= 0.01)) throw nb::value_error("dt (the world step, s) must be in (0, 0.01]");
             if (!(extra_time >= 0) || !std::isfinite(extra_time)) throw nb::value_error("extra_time must be >= 0");
             self->options.dt = dt;
             self->options.quick_step = quick_step;
             self->options.extra_time = extra_time;
             self->options.stall_check = stall_check;
             self->options.settings = settings_from(settings, robot.r());
             self->build();
           },
           "robot"_a, "scene"_a = nb::none(), nb::kw_only(), "dt"_a = host::SimOptions().dt, "settings"_a = nb::none(),
           "quick_step"_a = false, "extra_time"_a = 1.0, "stall_check"_a = true,
           "scene: a shipped scene's name ('grasp-and-lift'), a scene file, or None (the ground only). dt: the "
           "world step, s. settings: the controller's $n at power-up. extra_time: how long done() waits after "
           "the program's last action.")
      .def("step",
           [](PySim& s, int n) {
             if (n < 0) throw nb::value_error("n must be >= 0");
             nb::gil_scoped_release release;
             for (int i = 0; i < n; ++i) s.sim->step();
           },
           "n"_a = 1, "Advances the world n steps of dt.")
      .def("step_path",
           [](PySim& s, int n, int every) {
             if (n < 0) throw nb::value_error("n must be >= 0");
             if (every < 1) throw nb::value_error("every must be >= 1");
             std::vector<double> path;
             {
               nb::gil_scoped_release release;
               s.sim->step_path(n, every, path);
             }
             Array out = new_array({path.size() / 3, 3});
             std::copy(path.begin(), path.end(), out.ptr);
             return out;
           },
           "n"_a, "every"_a = 1,
           "Advances the world n steps of dt; the tool point (x, y, z mm) after every `every`-th step and after "
           "the last, one row each: the path the tool took (a pen's ink is drawn from it).")
      .def("run_until",
           [](PySim& s, double t) {
             if (!std::isfinite(t)) throw nb::value_error("t must be finite");
             nb::gil_scoped_release release;
             s.sim->run_until(t);
           },
           "t"_a, "Steps until time >= t (s).")
      .def("run",
           [](PySim& s) {
             nb::gil_scoped_release release;
             while (!s.sim->done()) s.sim->step();
           },
           "Steps until the program has ended and extra_time has passed (what `articula sim` runs).")
      .def("load_program", [](PySim& s, nb::handle program) { s.sim->load_program(program_from(program, *s.robot)); },
           "program"_a,
           "The program the arm runs from now on (an articula.Program or a path): each line sent to the firmware "
           "once the arm is at rest after the one before. The firmware goes on from where it is: use it on a new "
           "or reset simulation to start from power-up.")
      .def("command", [](PySim& s, const std::string& line) { return host::reply_text(s.sim->command(line)); }, "line"_a,
           "One protocol line to the firmware now (or once the reply before is off the wire); returns its "
           "'ok' or 'error:N'. Commands sent one after another stream: the firmware plans an accepted move into "
           "the moves ahead, as on the arm; a rejected one changes nothing.")
      .def("events",
           [](const PySim& s, size_t since) {
             nb::list out;
             const auto& ev = s.sim->events();
             for (size_t i = since; i < ev.size(); ++i) out.append(record(host::event_json(ev[i])));
             return out;
           },
           "since"_a = 0,
           "The events so far (or from index `since`): t, kind (contact_started, collision, grasp, release, "
           "steps_lost, stall, rejected, ...), line, the parts a and b, point_mm, detail.")
      .def("state", &state,
           "The world now: t, joints (deg or mm, as the steps put them), frames ((rows+2, 4, 4), as Robot.frames), "
           "tool, gripper_mm, counted_steps and lost_steps per motor, busy, parts (arm links and fingers with "
           "their poses), objects (name, pose, movable, carried, removed), contacts (what touches what).")
      .def("drag",
           [](PySim& s, nb::handle which, nb::handle target) {
             const std::vector<double> t = read_vector(target, "target");
             if (t.size() != 3) throw nb::value_error("target must be (x, y, z) in mm");
             s.sim->drag_object(s.object_index(which), make_vec3(t[0], t[1], t[2]));
           },
           "object"_a, "target"_a,
           "Pulls a movable object (index or name) toward target (x, y, z) mm with a damped spring, as a mouse "
           "drag: it is carried among the other bodies, not teleported. Until release().")
      .def("release", [](PySim& s) { s.sim->release_drag(); }, "Lets go of a dragged object: it falls.")
      .def("set_belt",
           [](PySim& s, nb::handle which, double mm_s) {
             try {
               s.sim->set_belt(s.object_index(which), mm_s);
             } catch (const std::invalid_argument& e) {
               throw nb::value_error(e.what());
             }
           },
           "belt"_a, "mm_s"_a,
           "Runs a conveyor belt of the scene (index or name; an object with a \"belt\" speed) at mm_s along its "
           "own x (negative: the other way; 0 stops it, and what lies on it stays there).")
      .def("reset", [](PySim& s) { s.build(); },
           "Back to t = 0: the arm at power-up, the objects where the scene puts them, no program.")
      .def("restart",
           [](PySim& s) { s.sim = std::make_unique<host::Simulation>(*s.robot, s.sim->scene_as_placed(), s.options); },
           "Back to t = 0 as reset() does, but each object a drag let go of stands where it was let go "
           "(the studio's Run after a student moved things by hand).")
      .def_prop_ro("time", [](const PySim& s) { return s.sim->time(); }, "simulated time, s")
      .def_prop_ro("steps", [](const PySim& s) { return s.sim->steps_taken(); })
      .def_prop_ro("dt", [](const PySim& s) { return s.options.dt; })
      .def_prop_ro("done", [](const PySim& s) { return s.sim->done(); })
      .def_prop_ro("busy", [](const PySim& s) { return s.sim->busy(); }, "the arm still has queued actions")
      .def_prop_ro("end_time", [](const PySim& s) { return s.sim->end_time(); })
      .def_prop_ro("objects", &scene_objects, "the scene's objects: name, type, size (mm), movable, mass_kg, friction")
      .def_prop_ro("scene_name", [](const PySim& s) { return s.scene.name; })
      .def("__repr__", [](const PySim& s) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "<Sim '%s' in %s, t = %.3f s, %d objects>", s.robot->name.c_str(),
                      s.scene.name.empty() ? "an empty scene" : ("'" + s.scene.name + "'").c_str(), s.sim->time(),
                      s.sim->num_objects());
        return std::string(buf);
      });
}

}  // namespace articula::python
