// wasm/src/common.h - what the web engine's binding files share: JSON at the door, errors as
// values. The rules at this door (docs/studio.md, "The web engine"):
//  - structured values cross as JSON text (the CLI's --json forms, records_json.h and the
//    shared layer's views), numbers in mm and degrees as everywhere;
//  - nothing throws into JavaScript: a call that can fail returns {"error": "...", ...} (the
//    same text the CLI prints, naming the file, the JSON path or the line), and loaders
//    return that text, "" when they succeeded. wasm/js/engine.mjs turns it into a JS Error;
//  - the hot paths (FK, IK for the benchmark) use a scratch array of doubles on the heap that
//    JavaScript reads and writes in place: no allocation, no JSON, per call.
// The checks and units are the shared layer's (host/lib/robot_view.h, protocol_view.h,
// timeline.h, host/physics/sim_view.h), as python/src's are: no logic here.
#ifndef ARTICULA_WASM_COMMON_H
#define ARTICULA_WASM_COMMON_H

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "program.h"
#include "robot_file.h"
#include "robot_view.h"
#include "scene.h"
#include "cell_file.h"

namespace articula::web {

using json = nlohmann::json;
using host::Robot;

inline std::string error_json(const std::string& message, json extra = json::object()) {
  extra["error"] = message;
  return extra.dump();
}

// Runs f (which returns JSON text) and turns any exception into {"error": ...}: a ProgramError
// keeps its line, a robot file's error its file and JSON path.
template <typename F>
std::string guarded(F&& f) {
  try {
    return f();
  } catch (const host::ProgramError& e) {  // every line that cannot be read, the first as `line`
    json problems = json::array();
    for (const auto& p : e.problems()) problems.push_back({{"line", p.line}, {"problem", p.problem}});
    return error_json(e.what(), {{"line", e.line()}, {"problems", problems}});
  } catch (const host::RobotFileError& e) {
    return error_json(e.what(), {{"file", e.file()}, {"json_path", e.json_path()}, {"problem", e.problem()}});
  } catch (const host::SceneError& e) {
    return error_json(e.what(), {{"json_path", e.json_path()}});
  } catch (const host::CellError& e) {
    return error_json(e.what(), {{"json_path", e.json_path()}, {"problem", e.problem()}});
  } catch (const json::exception& e) {
    return error_json(std::string("not the JSON expected: ") + e.what());
  } catch (const std::exception& e) {
    return error_json(e.what());
  } catch (...) {
    return error_json("an unknown error in the engine");
  }
}

// Numbers from JSON (a JSON null, which is what JavaScript's NaN and infinities become, or any
// non-number is NaN): the shared checks (robot_view.h) then name the bad value.
inline std::vector<double> numbers(const json& j, const char* what) {
  if (!j.is_array()) throw std::invalid_argument(std::string(what) + " must be a list of numbers");
  std::vector<double> v;
  for (const auto& x : j) v.push_back(x.is_number() ? x.get<double>() : std::nan(""));
  return v;
}

inline std::vector<double> finite_numbers(const json& j, const char* what) {
  std::vector<double> v = numbers(j, what);
  host::check_finite(v.data(), v.size(), what);
  return v;
}


}  // namespace articula::web

#endif  // ARTICULA_WASM_COMMON_H
