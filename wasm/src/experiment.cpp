// wasm/src/experiment.cpp - the numbers of the sim-vs-real experiment for JavaScript (the twin
// of python/src/experiment.cpp), from host/lib/experiment.h: JSON in, JSON out.
#include <emscripten/bind.h>

#include <string>

#include "common.h"
#include "experiment.h"
#include "plan.h"
#include "records_json.h"

namespace {

using articula::web::json;

// [x, y, z] from JavaScript: a NaN arrives as null and stays NaN, for measurement_question to
// name it.
articula::Vec3<double> xyz(const std::string& text, const char* what) {
  const std::vector<double> v = articula::web::numbers(json::parse(text), what);
  if (v.size() != 3) throw std::invalid_argument(std::string(what) + " must be three numbers [x, y, z]");
  return articula::make_vec3(v[0], v[1], v[2]);
}

}  // namespace

EMSCRIPTEN_BINDINGS(articula_experiment) {
  using namespace emscripten;
  using articula::web::guarded;
  namespace host = articula::host;
  function("axisErrors", +[](const std::string& value, const std::string& reference) {
    return guarded([&] { return host::axis_errors_json(host::axis_errors(xyz(value, "value"), xyz(reference, "reference"))).dump(); });
  });
  function("table5", +[](const std::string& chains) {
    return guarded([&] { return host::table5_json(host::table5(host::chain_poses_of_json(json::parse(chains)))).dump(); });
  });
  function("toolPoints", +[](const std::string& points) {
    return guarded([&] { return host::tool_points_json(host::tool_points(host::target_poses_of_json(json::parse(points)))).dump(); });
  });
  function("jointVerdicts", +[](const std::string& points) {
    return guarded([&] { return host::joint_verdicts_json(host::joint_verdicts(host::verdict_points_of_json(json::parse(points)))).dump(); });
  });
  function("repeatChains", +[](const std::string& commands) {
    return guarded([&] { return host::repeat_chains_json(host::repeat_chains(host::plan_steps_of_json(json::parse(commands)))).dump(); });
  });
  function("experimentCsv", +[](const std::string& experiment) {
    return guarded([&] { return json(host::experiment_csv(json::parse(experiment))).dump(); });
  });
  function("parsePlan", +[](const std::string& text, const std::string& name) {
    return guarded([&] { return host::plan_json(host::parse_plan(text, name)).dump(); });
  });
  function("table4", +[](const std::string& points) {
    return guarded([&] { return host::table4_json(host::table4(host::joint_points_of_json(json::parse(points)))).dump(); });
  });
  constant("measurementFarMm", host::kMeasurementFarMm);
  function("measurementQuestion", +[](const std::string& measured, const std::string& predicted, double reach_mm,
                                      double far_mm) {
    return guarded([&] {
      return json(host::measurement_question(xyz(measured, "the measurement"), xyz(predicted, "the prediction"), reach_mm,
                                             far_mm)).dump();
    });
  });
}
