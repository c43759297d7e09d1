// python/src/experiment.cpp - the numbers of the sim-vs-real experiment from the host library
// (host/lib/experiment.h): hil/harness/report.py's tables are these, as the studio's
// Experiment panel's are through the web engine (wasm/src/experiment.cpp).
#include <nanobind/stl/array.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <array>
#include <tuple>

#include "bindings.h"
#include "experiment.h"
#include "plan.h"
#include "records_json.h"

namespace articula::python {

using namespace nb::literals;

namespace {
using Xyz = std::array<double, 3>;
Vec3<double> v3(const Xyz& a) { return make_vec3(a[0], a[1], a[2]); }

// A list of records from Python (dicts and lists, positions as numbers) through Python's own
// json into the host library's JSON reader `of_json`, its rows back through `to_json`; the
// reader's complaint (naming the entry) as a ValueError.
template <typename Of, typename To>
nb::object via_json(nb::handle records, Of of_json, To to_json) {
  const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(records));
  try {
    return json_to_python(to_json(of_json(nlohmann::json::parse(text))));
  } catch (const std::exception& e) {
    throw nb::value_error(e.what());
  }
}
}  // namespace

void bind_experiment(nb::module_& m) {
  m.def(
      "parse_plan",
      [](const std::string& text, const std::string& name) {
        try {
          return json_to_python(host::plan_json(host::parse_plan(text, name)));
        } catch (const host::PlanError& e) {
          throw nb::value_error(e.what());
        }
      },
      "text"_a, "name"_a,
      "A test plan (hil/plans/README.md): {'name', 'title', 'notes', 'commands': [{'line', 'text', 'expect', "
      "'timeout_s', 'single_joint', 'repeat', 'kind'}]}. ValueError naming name:line for a plan that cannot run.");
  m.def(
      "axis_errors", [](const Xyz& value, const Xyz& reference) {
        return json_to_python(host::axis_errors_json(host::axis_errors(v3(value), v3(reference))));
      },
      "value"_a, "reference"_a,
      "|value - reference| per axis in mm, and as a per cent of |reference| (None where the coordinate is "
      "within 1 mm of 0), as the thesis's single-joint tables give them: {'mm': [x, y, z], 'pct': [x, y, z]}.");
  m.def(
      "table4",
      [](const std::vector<std::tuple<int, Xyz, Xyz>>& points) {
        std::vector<host::JointPoint> in;
        for (const auto& [joint, value, reference] : points) in.push_back({joint, v3(value), v3(reference)});
        return json_to_python(host::table4_json(host::table4(in)));
      },
      "points"_a,
      "The thesis's Table 4 from (joint, value, reference) points: per joint, in ascending order, "
      "{'joint', 'poses', 'axes': [{'max_pct' (None: no coordinate away from 0), 'max_mm', 'avg_mm'}] for x, y, z}.");
  m.def(
      "joint_verdicts",
      [](nb::handle points) {
        return via_json(points, host::verdict_points_of_json,
                        [](const auto& p) { return host::joint_verdicts_json(host::joint_verdicts(p)); });
      },
      "points"_a,
      "A verdict per joint from single-joint poses [{'joint', 'ideal', 'quant', 'measured' (or None)}]: "
      "[{'joint', 'measured', 'worst_mm', 'quant_mm', 'within' (measured within 5 mm of the model on every axis), "
      "'text'}], as the studio's Experiment panel and the harness report give them.");
  m.def(
      "repeat_chains",
      [](nb::handle commands) {
        return via_json(commands, host::plan_steps_of_json,
                        [](const auto& s) { return host::repeat_chains_json(host::repeat_chains(s)); });
      },
      "commands"_a,
      "A plan's repeatability chains from its commands in order [{'line', 'repeat': [chain, 'out'|'back'] or None}]: "
      "[{'chain', 'moves', 'back_moves', 'line_before', 'line_out', 'line_back'} (None: none)], in chain order.");
  m.def(
      "experiment_csv",
      [](nb::handle experiment) {
        const std::string text = nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(experiment));
        return host::experiment_csv(nlohmann::json::parse(text));
      },
      "experiment"_a,
      "The experiment as the studio exports it (CSV): the measurements first, in the harness's --measured format "
      "(plan,plan_line,x_mm,y_mm,z_mm), then the poses, Table 4, Table 5 and the tool points.");
  m.def(
      "table5",
      [](nb::handle chains) {
        return via_json(chains, host::chain_poses_of_json, [](const auto& c) { return host::table5_json(host::table5(c)); });
      },
      "chains"_a,
      "The thesis's Table 5 from repeatability chains [{'chain', 'moves', 'back_moves', 'start', 'dest_quant', "
      "'dest_ideal', 'back_quant', 'start_measured', 'dest_measured', 'back_measured'}] (positions [x, y, z] mm, the "
      "last four may be None): per chain {'dest_error_mm', 'return_error_mm', 'measured_dest_mm', "
      "'measured_return_mm' (None: nothing to compare), 'return_from_measured_start'}.");
  m.def(
      "tool_points",
      [](nb::handle points) {
        return via_json(points, host::target_poses_of_json,
                        [](const auto& p) { return host::tool_points_json(host::tool_points(p)); });
      },
      "points"_a,
      "The tool sent to points (P) from [{'line', 'target', 'quant', 'ideal', 'measured'}] (positions [x, y, z] mm; "
      "measured may be None): per point {'line', 'model_from_target_mm', 'ideal_from_target_mm', "
      "'measured_from_target_mm', 'measured_from_model_mm' (None: not measured)}.");
  m.def(
      "measurement_question",
      [](const Xyz& measured, const Xyz& predicted, double reach_mm, double far_mm) {
        return host::measurement_question(v3(measured), v3(predicted), reach_mm, far_mm);
      },
      "measured"_a, "predicted"_a, "reach_mm"_a, "far_mm"_a = host::kMeasurementFarMm,
      "The question a typed tool position raises before it is used ('' when it looks right): not a number, "
      "typed in centimetres, beyond the arm's reach, or far from the prediction.");
}

}  // namespace articula::python
