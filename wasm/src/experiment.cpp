// wasm/src/experiment.cpp - the numbers of the sim-vs-real experiment for JavaScript (the twin
// of python/src/experiment.cpp), from host/lib/experiment.h: JSON in, JSON out.
#include <emscripten/bind.h>

#include <functional>
#include <string>

#include "experiment.h"
#include "records_json.h"

namespace {

articula::Vec3<double> v3(const std::string& text, const char* what) {
  return articula::host::vec3_of_json(nlohmann::json::parse(text), what);
}

// Errors come back as {"error": message}: the page's worker says them, nothing throws.
std::string guarded(const std::function<nlohmann::json()>& f) {
  try {
    return f().dump();
  } catch (const std::exception& e) {
    return nlohmann::json{{"error", e.what()}}.dump();
  }
}

}  // namespace

EMSCRIPTEN_BINDINGS(articula_experiment) {
  using namespace emscripten;
  using nlohmann::json;
  function("axisErrors", +[](const std::string& value, const std::string& reference) {
    return guarded([&] {
      return articula::host::axis_errors_json(articula::host::axis_errors(v3(value, "value"), v3(reference, "reference")));
    });
  });
  function("table4", +[](const std::string& points) {
    return guarded([&] {
      return articula::host::table4_json(articula::host::table4(articula::host::joint_points_of_json(json::parse(points))));
    });
  });
  function("measurementQuestion", +[](const std::string& measured, const std::string& predicted, double reach_mm,
                                      double far_mm) {
    return guarded([&] {
      return json(articula::host::measurement_question(v3(measured, "the measurement"), v3(predicted, "the prediction"),
                                                        reach_mm, far_mm));
    });
  });
}
