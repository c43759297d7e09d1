// python/src/program.cpp - programs on a robot: Robot.predict (the firmware itself on its virtual clock, step for
// step, host/lib/predict.h), Robot.run (the kinematic model, run.h) and Robot.quantize
// (quantize.h). The records are the CLI's JSON records (records_json.h) with attribute access.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.h"
#include "blocks.h"
#include "draw.h"
#include "robot_view.h"
#include "timeline.h"
#include "predict.h"
#include "program.h"
#include "quantize.h"
#include "records_json.h"
#include "run.h"

namespace articula::python {

using namespace nb::literals;

// A program's text: str (UTF-8) or bytes (as they are: a plan may hold any byte).
std::string text_of(nb::handle text) {
  if (nb::isinstance<nb::bytes>(text)) {
    nb::bytes b = nb::borrow<nb::bytes>(text);
    return std::string(b.c_str(), b.size());
  }
  return nb::cast<std::string>(text);
}

// A program given as an articula.Program (its text and source), or as a file path.
host::Program program_from(nb::handle program, const Robot& robot) {
  nb::object os = nb::module_::import_("os");
  if (nb::isinstance<nb::str>(program) || nb::isinstance(program, os.attr("PathLike")))
    return host::load_program(nb::cast<std::string>(os.attr("fspath")(program)), robot);
  if (!nb::hasattr(program, "text") || !nb::hasattr(program, "source"))
    throw nb::type_error("program must be an articula.Program or a file path");
  return host::parse_program(text_of(program.attr("text")), nb::cast<std::string>(program.attr("source")), robot);
}

// Settings as {0: 800, 1: 3000}, "0=800,1=3000" or None, read as `$n=v` lines are.
host::ControllerSettings settings_from(nb::handle settings, const Robot& robot) {
  host::ControllerSettings s;
  if (settings.is_none()) return s;
  std::string text;
  if (nb::isinstance<nb::str>(settings)) {
    text = nb::cast<std::string>(settings);
  } else if (nb::isinstance<nb::dict>(settings)) {
    for (auto [k, v] : nb::borrow<nb::dict>(settings)) {
      const std::string key = std::string(nb::str(k).c_str());
      text += (text.empty() ? "" : ",") + (key.rfind('$', 0) == 0 ? key.substr(1) : key) + "=" +
              std::string(nb::str(v).c_str());
    }
  } else {
    throw nb::type_error("settings must be a dict {0: 800, 1: 3000} or a text \"0=800,1=3000\"");
  }
  try {
    host::apply_settings_text(s, text, robot.actuation.num_motors);
  } catch (const std::invalid_argument& e) {
    throw nb::value_error(e.what());
  }
  return s;
}

// A program's time line (host/lib/timeline.h), as the studio plays it: the robot it was made
// for, and the arm at any instant.
struct PyTimeline {
  std::shared_ptr<const Robot> robot;
  host::Timeline tl;
};

void bind_program(nb::module_& m, nb::class_<PyRobot>& robot) {
  m.def("protocol_number", [](double v, bool every_decimal) { return host::protocol_number(v, every_decimal); }, "v"_a,
        "every_decimal"_a = false,
        "A number as a protocol line writes it (the firmware's own writer): rounded to thousandths, no trailing "
        "zeros: protocol_number(12.5) -> '12.5', protocol_number(-0.0004) -> '0'; every_decimal=True: '12.500'.");
  nb::class_<PyTimeline>(m, "Timeline",
                         "A program's time line, as the studio plays it (Robot.timeline): every action from the pose "
                         "before it to its own in its time, back to back; at(t) is the arm at any instant.")
      .def_prop_ro("duration", [](const PyTimeline& s) { return s.tl.duration(); }, "s")
      .def_prop_ro("start_q", [](const PyTimeline& s) { return s.tl.start_q(); }, "where it starts (deg or mm)")
      .def_prop_ro("records", [](const PyTimeline& s) { return json_to_python(host::timeline_json(s.tl)["records"]); },
                   "one per statement: line, command, reply, code, error, note, start_s, end_s, q, q_ideal, tool, "
                   "tool_ideal, error_mm, steps, gripper")
      .def("at", [](const PyTimeline& s, double t) { return json_to_python(host::timeline_pose_json(s.tl.at(t))); }, "t"_a,
           "The arm at time t (s, clamped to the time line): t, line, q, q_ideal (the ghost's), steps, error_mm, "
           "gripper (joint values linear in time within an action: a drawing of the move, not the motors' profile).")
      .def("samples", [](const PyTimeline& s, double per_s, size_t max_samples) {
             return json_to_python(host::timeline_samples_json(*s.robot, s.tl, per_s, max_samples));
           }, "per_s"_a = 50.0, "max_samples"_a = 4000,
           "The path the arm takes, for plots: the time line at every action's start and end and evenly between "
           "(about per_s a second, at most max_samples), column by column: t, line, q (one list a joint), tool "
           "(x, y and z lists, mm: forward kinematics at each sample, so a move shows as the curve it is).")
      .def("__repr__", [](const PyTimeline& s) {
        return "<Timeline of " + std::to_string(s.tl.actions().size()) + " statements, " + std::to_string(s.tl.duration()) +
               " s>";
      });


  m.def("detect_format",
        [](nb::handle text, const std::string& name) {
          return host::detect_format(text_of(text), name) == host::Program::Format::kRoboSim ? "robosim" : "protocol";
        },
        "text"_a, "name"_a = "",
        "Which language a program is in: 'robosim' (thesis appendix B) or 'protocol' (the arm's serial lines), "
        "from the name's extension (.robosim, .arm) or else the first command.");

  robot
      .def("check_program",
           [](const PyRobot& self, nb::handle program) { return int(program_from(program, self.r()).statements.size()); },
           "program"_a,
           "Reads a program for this robot (argument counts and ranges follow the robot) and returns its number "
           "of statements; raises ProgramError naming the line of the first problem.")
      .def("program_fit",
           [](const PyRobot& self, const std::string& text, const std::string& name) {
             return json_to_python(host::program_fit_json(host::program_fit(text, name, self.r())));
           },
           "text"_a, "name"_a = "program.arm",
           "Whether a program fits the robot: {fits, other_arm, line, problem}; other_arm: written for an arm of "
           "another shape (a wrong count of values for its joints or motors, a joint it has not), not broken for "
           "every arm.")
      .def("blocks_program",
           [](const PyRobot& self, nb::handle ops) {
             const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(ops));
             return json_to_python(host::blocks_program_json(self.r(), self.ik(), nlohmann::json::parse(text)));
           },
           "ops"_a,
           "The program of the studio's block actions ([{'op', 'block', ...}]): {text, robosim, lines, problems}, "
           "or {error: {block, message}} for an action that cannot become a line.")
      .def("program_actions",
           [](const PyRobot& self, const std::string& text, const std::string& name) {
             return json_to_python(host::program_actions_json(self.r(), text, name));
           },
           "text"_a, "name"_a = "program.arm", "A program's text as block actions: {ops, format}.")
      .def("draw",
           [](const PyRobot& self, nb::kwargs request) {
             const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(request));
             return json_to_python(
                 host::drawing_with_ink_json(self.r(), self.ik(), host::draw_request_from_json(nlohmann::json::parse(text))));
           },
           "A drawing for a pen held in the gripper (articula draw): text='Hello' or shape='square'|'circle'|'star', "
           "width (mm), at=(x, y) its centre, z the paper's height, pen (mm below the tool point), lift, speed, "
           "travel_speed (mm/s), rotate (deg, 90: upright from +x), line_spacing, font (a .jhf path). Returns {what, "
           "bounds, strokes, reach {fits, points, unreachable, movable, move, advice}, start, travel_mm, "
           "travel_unordered_mm, program, ink_lines} and, when the pen reaches it on a robot with motors, 'ink': the line "
           "the arm will draw (the pen at every step: {strokes, worst_mm, worst_at, worst_line, steps}) and 'seconds'; "
           "the program is '' when the pen cannot reach all of it. Also svg= (an SVG file's text), paper=, tolerance=.")
      .def("ink",
           [](const PyRobot& self, nb::kwargs request) {
             const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(request));
             return json_to_python(host::ink_json(self.r(), nlohmann::json::parse(text)));
           },
           "The ink the pen leaves where its tip is on the paper (below half its lift above it): steps=[a row of "
           "each motor's count per moment, flat] (a virtual Nano's) or tool=[x, y, z after x, y, z, mm] (the physics'), "
           "z (the paper's height), pen (mm below the tool point), lift. Returns {strokes, points}: the rule the "
           "prediction's ink follows.")
      .def("drawing_check",
           [](const PyRobot& self, nb::kwargs request) {
             const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(request));
             return json_to_python(host::drawing_check_json(self.r(), self.ik(), nlohmann::json::parse(text)));
           },
           "A program's ink against a target drawing, both ways (the studio's drawing exercises): program (its text), "
           "target (a draw request: shape= or text=, width, at), z, pen, tolerance (mm). Returns {met, ink_off_mm "
           "(the farthest ink from the target), uncovered_mm (the farthest part of the target from the ink), ink_off_at, "
           "uncovered_at, ink_points, says, what, target, ink}.")
      .def("reach_map",
           [](const PyRobot& self, nb::kwargs request) {
             const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(request));
             return json_to_python(host::reach_map_json(self.r(), self.ik(), nlohmann::json::parse(text)));
           },
           "Where on an area of the table the pen reaches the paper: area=(min_x, min_y, max_x, max_y), cell (mm), z, "
           "pen. Returns {rows, cols, cell, area, reached}: '1' where it reaches, row after row (rows along x).")
      .def("example_places", [](const PyRobot& self) { return json_to_python(host::example_places_json(self.r(), self.ik())); },
           "Where the studio's toolbox blocks point for this arm, all within its reach: {tool, line_to (a straight "
           "line from tool), pen, paper_z, draw_at, draw_width (a square that wide drawn there with that pen), fits}.")
      .def("protocol_line",
           [](const PyRobot& self, const std::string& word, const std::vector<double>& values) {
             if (word.size() != 1) throw nb::value_error("a protocol command is one letter");
             return host::protocol_line(self.r(), word[0], values);
           },
           "word"_a, "values"_a = std::vector<double>{},
           "One protocol line, as every tool here writes it: protocol_line('P', [200, 0, 50]) -> 'P 200 0 50'.")
      .def("move_line",
           [](const PyRobot& self, const std::vector<double>& q) { return host::move_line(self.r(), q); }, "q"_a,
           "The line that moves the arm to joint values q (deg or mm): M with the motors' angles.")
      .def("parse_program",
           [](const PyRobot& self, nb::handle program) {
             const host::Program p = program_from(program, self.r());
             const std::string text = nb::hasattr(program, "text")
                 ? text_of(program.attr("text"))
                 : nb::cast<std::string>(nb::module_::import_("pathlib").attr("Path")(program).attr("read_text")());
             return json_to_python(host::program_json(self.r(), p, text));
           },
           "program"_a,
           "The program as its parser reads it: {format, statements, comments}; a protocol statement has its "
           "command letter and arguments as written (the studio opens programs as blocks from this).")
      .def("predict",
           [](const PyRobot& self, nb::handle program, nb::handle settings) {
             const Robot& r = self.r();
             if (!r.has_motors)
               throw nb::value_error((r.name + " has no motors: there are no steps to predict (robot.run executes "
                                      "programs on the kinematic model)")
                                         .c_str());
             const host::Program p = program_from(program, r);
             const host::ControllerSettings s = settings_from(settings, r);
             return record(host::prediction_json(r, p, host::predict_program(r, p, s)));
           },
           "program"_a, "settings"_a = nb::none(),
           "What the real arm will do with a program, step for step (`articula predict --json`): a Prediction with "
           "the robot, settings, motors, joints, summary and one record per statement (steps, commanded_deg, "
           "actuator_deg, joints, joints_ideal, tool_ideal_mm, tool_quantized_mm, error_mm, seconds, start_s, "
           "end_s, ...). settings: {0: 800, 1: 3000} or \"0=800,1=3000\", the controller's $n at power-up.")
      .def("run",
           [](const PyRobot& self, nb::handle program) {
             const Robot& r = self.r();
             const host::Program p = program_from(program, r);
             return record(host::run_json(r, p, host::run_program(r, p)));
           },
           "program"_a,
           "A program on the kinematic model (`articula run --json`): exact joint values, no steps, no timing; "
           "records with joints, tool (position, rpy, rotation), gripper_percent, target and ik_status.")
      .def("timeline",
           [](const PyRobot& self, nb::handle program, nb::handle start) {
             const Robot& r = self.r();
             std::vector<double> q(size_t(r.model.num_joints));
             if (start.is_none()) q = host::home_pose(r);
             else {
               read_joints(q.data(), start, r, "start");
               q = host::joints_out(r, q.data());
             }
             return PyTimeline{self.robot, host::Timeline::of_program(r, program_from(program, r), q)};
           },
           "program"_a, "start"_a = nb::none(),
           "The program's time line, as the studio plays it: predicted from power-up for a robot with motors, "
           "or run on the kinematic model from `start` (deg or mm; default home) at 60 deg/s and 100 mm/s.")
      .def("quantize",
           [](const PyRobot& self, const std::vector<std::string>& lines) {
             const Robot& r = self.r();
             if (!r.has_motors) throw nb::value_error((r.name + " has no motors: nothing to quantize").c_str());
             nb::list out;
             for (const auto& q : host::quantize_lines(r, lines)) out.append(record(host::quantize_record_json(r, q)));
             return out;
           },
           "lines"_a,
           "Protocol lines through the firmware's codec and step arithmetic from step 0 (`articula quantize "
           "--json`): per line the reply, the motor an L moved, its commanded and reached angle, steps, and the "
           "tool error whole steps leave.");
}

}  // namespace articula::python
