// host/lib/draw_json.cpp - the drawing's JSON entries, for the bindings (Python, the page's
// engine): requests read and checked key by key, results written (draw.h).
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "blocks.h"
#include "draw_detail.h"
#include "predict.h"
#include "program.h"
#include "robot_view.h"

namespace articula::host {

using namespace draw_detail;

namespace {

// A request's keys: any other is refused by name ("a drawing request has no 'colour'").
void only_keys(const nlohmann::json& j, std::initializer_list<const char*> keys, const char* what) {
  for (auto it = j.begin(); it != j.end(); ++it)
    if (std::find_if(keys.begin(), keys.end(), [&](const char* k) { return it.key() == k; }) == keys.end())
      throw std::invalid_argument(std::string(what) + " has no '" + it.key() + "'");
}

// Strokes as the bindings hand them out: [[[x, y], ...], ...].
nlohmann::json strokes_json(const std::vector<Stroke>& strokes) {
  nlohmann::json out = nlohmann::json::array();
  for (const Stroke& s : strokes) {
    nlohmann::json st = nlohmann::json::array();
    for (const Point2& p : s) st.push_back({p.x, p.y});
    out.push_back(st);
  }
  return out;
}

}  // namespace

nlohmann::json reach_map_json(const Robot& robot, const InverseKinematics& ik, const nlohmann::json& j) {
  using nlohmann::json;
  if (!j.is_object()) throw std::invalid_argument("a reach map request is an object: {area | paper, at, landscape; cell, z, pen}");
  only_keys(j, {"area", "paper", "at", "landscape", "cell", "z", "pen"}, "a reach map request");
  auto num = [&](const char* key, double fallback) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number()) throw std::invalid_argument(std::string("'") + key + "' must be a number");
    return j[key].get<double>();
  };
  auto pair = [](const json& v) { return v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number(); };
  Bounds area;
  if (j.contains("paper")) {  // a sheet: portrait with its height along x (away from a student at +x), or landscape
    double w = 0, h = 0;
    if (!j["paper"].is_string() || !paper_size(j["paper"].get<std::string>(), w, h))
      throw std::invalid_argument("'paper' must be A4, A5 or Letter");
    if (!pair(j.value("at", json()))) throw std::invalid_argument("'at' must be the sheet's centre, [x, y] mm");
    if (j.value("landscape", false)) std::swap(w, h);
    const double x = j["at"][0].get<double>(), y = j["at"][1].get<double>();
    area = {x - h / 2, y - w / 2, x + h / 2, y + w / 2};
  } else {
    const json& a = j.value("area", json());
    if (!a.is_array() || a.size() != 4 || !std::all_of(a.begin(), a.end(), [](const json& v) { return v.is_number(); }))
      throw std::invalid_argument("'area' must be [min_x, min_y, max_x, max_y] mm");
    area = {a[0].get<double>(), a[1].get<double>(), a[2].get<double>(), a[3].get<double>()};
  }
  const double cell = num("cell", 5);
  if (cell > 0 && area.width() / cell * area.height() / cell > 20000)
    throw std::invalid_argument("a reach map of more than 20,000 cells: make the cell bigger");
  PenSettings pen;
  pen.paper_z = num("z", 0);
  pen.pen_mm = num("pen", pen.pen_mm);
  check_pen(pen);
  const ReachMap m = reach_map(robot, ik, pen, area, cell);
  std::string bits(m.reached.size(), '0');
  for (size_t i = 0; i < bits.size(); ++i) bits[i] = m.reached[i] ? '1' : '0';
  return json{{"rows", m.rows}, {"cols", m.cols}, {"cell", m.cell_mm},
              {"area", {area.min_x, area.min_y, area.max_x, area.max_y}}, {"reached", bits}};
}

nlohmann::json drawing_json(const Drawing& d) {
  using nlohmann::json;
  auto pt = [](Point2 p) { return json::array({p.x, p.y}); };
  json unreachable = json::array();
  for (const Point2& p : d.reach.unreachable) unreachable.push_back(pt(p));
  return json{{"what", d.what},
              {"width_mm", d.width_mm},
              {"height_mm", d.height_mm},
              {"bounds", {{"min_x", d.bounds.min_x}, {"min_y", d.bounds.min_y}, {"max_x", d.bounds.max_x}, {"max_y", d.bounds.max_y}}},
              {"strokes", strokes_json(d.strokes)},
              {"reach", {{"fits", d.reach.fits}, {"points", d.reach.points}, {"unreachable", unreachable},
                         {"movable", d.reach.movable}, {"move", {d.reach.move_x, d.reach.move_y}}, {"advice", d.reach.advice}}},
              {"start", pt(d.start)},
              {"travel_mm", d.travel_mm},
              {"travel_unordered_mm", d.travel_unordered_mm},
              {"program", d.program},
              {"ink_lines", d.ink_lines}};
}

nlohmann::json drawing_with_ink_json(const Robot& robot, const InverseKinematics& ik, const DrawRequest& request, bool svg) {
  using nlohmann::json;
  const Drawing d = make_drawing(robot, ik, request);
  json out = drawing_json(d);
  if (d.program.empty() || !robot.has_motors) return out;
  const Robot stepped = request.microsteps ? with_microsteps(robot, request.microsteps) : robot;
  const Prediction p = predict_program(stepped, parse_program(d.program, "drawing.arm", stepped), {}, {}, true);
  const PredictedInk ink = predicted_ink(d, p, request.pen);
  out["ink"] = {{"strokes", strokes_json(ink.strokes)}, {"worst_mm", ink.worst_mm}, {"worst_at", {ink.worst_at.x, ink.worst_at.y}},
                {"worst_line", ink.worst_line}, {"steps", ink.steps}};
  out["seconds"] = p.total_s();
  if (svg) out["svg"] = drawing_svg(d, ink, d.what + " on " + robot.name);
  return out;
}

DrawRequest draw_request_from_json(const nlohmann::json& j) {
  using nlohmann::json;
  if (!j.is_object()) throw std::invalid_argument("a drawing request is an object");
  only_keys(j, {"text", "shape", "svg", "strokes", "svg_name", "tolerance", "paper", "microsteps", "font", "line_spacing", "width", "at", "z", "pen", "lift",
                                      "speed", "travel_speed", "rotate"}, "a drawing request");
  auto num = [&](const char* key, double fallback) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number()) throw std::invalid_argument(std::string("'") + key + "' must be a number");
    return j[key].get<double>();
  };
  auto str = [&](const char* key) {
    if (!j.contains(key) || j[key].is_null()) return std::string();
    if (!j[key].is_string()) throw std::invalid_argument(std::string("'") + key + "' must be text");
    return j[key].get<std::string>();
  };
  DrawRequest r;
  r.text = str("text");
  if (j.contains("strokes")) {
    const json& st = j["strokes"];
    size_t points = 0;
    if (!st.is_array()) throw std::invalid_argument("'strokes' must be a list of strokes, each a list of [x, y] mm");
    for (const json& s : st) {
      if (!s.is_array()) throw std::invalid_argument("'strokes' must be a list of strokes, each a list of [x, y] mm");
      Stroke stroke;
      for (const json& p : s) {
        if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number() ||
            !std::isfinite(p[0].get<double>()) || !std::isfinite(p[1].get<double>()))
          throw std::invalid_argument("stroke " + std::to_string(r.freehand.size() + 1) + " holds " + p.dump().substr(0, 40) +
                                      ", not a point [x, y] mm");
        stroke.push_back({p[0].get<double>(), p[1].get<double>()});
      }
      points += stroke.size();
      if (points > 20000) throw std::invalid_argument("strokes of more than 20,000 points: draw less");
      if (!stroke.empty()) r.freehand.push_back(std::move(stroke));
    }
  }
  r.shape = str("shape");
  r.svg = str("svg");
  r.paper = str("paper");
  r.microsteps = int(num("microsteps", 0));
  if (!str("svg_name").empty()) r.svg_name = str("svg_name");
  r.tolerance_mm = num("tolerance", r.tolerance_mm);
  r.font_path = str("font");
  r.line_spacing = num("line_spacing", r.line_spacing);
  r.width_mm = num("width", 0);
  if (r.freehand.empty() || j.contains("at")) {  // strokes by hand are where they were drawn
    if (!j.contains("at") || !j["at"].is_array() || j["at"].size() != 2 || !j["at"][0].is_number() || !j["at"][1].is_number())
      throw std::invalid_argument("'at' must be the drawing's centre, [x, y] mm");
    r.x = j["at"][0].get<double>();
    r.y = j["at"][1].get<double>();
  }
  r.rotation_deg = num("rotate", r.rotation_deg);
  r.pen.paper_z = num("z", 0);
  r.pen.pen_mm = num("pen", r.pen.pen_mm);
  r.pen.lift_mm = num("lift", r.pen.lift_mm);
  r.pen.speed = num("speed", r.pen.speed);
  r.pen.travel_speed = num("travel_speed", r.pen.travel_speed);
  return r;
}

nlohmann::json ink_json(const Robot& robot, const nlohmann::json& j) {
  using nlohmann::json;
  if (!j.is_object()) throw std::invalid_argument("an ink request is an object: {steps | tool, z, pen, lift}");
  only_keys(j, {"steps", "tool", "z", "pen", "lift"}, "an ink request");
  if (j.contains("steps") == j.contains("tool")) throw std::invalid_argument("give the motors' 'steps' or the 'tool' positions");
  std::vector<Vec3<double>> tool;
  if (j.contains("steps")) {
    if (!j["steps"].is_array()) throw std::invalid_argument("'steps' must be a list of step counts");
    std::vector<int32_t> steps;
    steps.reserve(j["steps"].size());
    for (const json& v : j["steps"]) {
      if (!v.is_number_integer()) throw std::invalid_argument("'steps' holds " + v.dump() + ", not a whole number of steps");
      steps.push_back(v.get<int32_t>());
    }
    tool = tool_from_steps(robot, steps);
  } else {
    const json& t = j["tool"];
    if (!t.is_array() || t.size() % 3) throw std::invalid_argument("'tool' must be x, y, z (mm) after x, y, z");
    for (size_t k = 0; k < t.size(); k += 3) {
      for (size_t i = k; i < k + 3; ++i)
        if (!t[i].is_number() || !std::isfinite(t[i].get<double>()))
          throw std::invalid_argument("'tool' holds " + t[i].dump() + " at " + std::to_string(i) + ", not a position in mm");
      tool.push_back({t[k].get<double>(), t[k + 1].get<double>(), t[k + 2].get<double>()});
    }
  }
  PenSettings pen;
  auto num = [&](const char* key, double& into) {
    if (!j.contains(key)) return;
    if (!j[key].is_number()) throw std::invalid_argument(std::string("'") + key + "' must be a number");
    into = j[key].get<double>();
  };
  num("z", pen.paper_z);
  num("pen", pen.pen_mm);
  num("lift", pen.lift_mm);
  check_pen(pen);
  const std::vector<Stroke> ink = ink_of_tool_path(tool, pen);
  size_t points = 0;
  for (const Stroke& s : ink) points += s.size();
  return json{{"strokes", strokes_json(ink)}, {"points", points}};
}

nlohmann::json pen_fields_json() {
  nlohmann::json out = nlohmann::json::array();
  for (const PenField& f : kPenFields)
    out.push_back({{"key", f.key}, {"default", f.fallback}, {"min", f.min}, {"max", f.max}, {"min_excluded", f.min_excluded},
                   {"unit", f.unit}, {"what", f.what}});
  return out;
}

nlohmann::json drawing_check_json(const Robot& robot, const InverseKinematics& ik, const nlohmann::json& j) {
  using nlohmann::json;
  if (!j.is_object()) throw std::invalid_argument("a drawing check is an object: {program, target, z, pen, tolerance}");
  only_keys(j, {"program", "name", "target", "z", "pen", "lift", "tolerance"}, "a drawing check");
  if (!j.contains("program") || !j["program"].is_string()) throw std::invalid_argument("'program' must be the program's text");
  if (!j.contains("target") || !j["target"].is_object()) throw std::invalid_argument("'target' must be a drawing request");
  const double tolerance = j.value("tolerance", json(0)).is_number() ? j.value("tolerance", 0.0) : -1;
  if (!(tolerance > 0)) throw std::invalid_argument("'tolerance' must be a number of mm above 0");
  json target = j["target"];
  for (const char* k : {"z", "pen", "lift"})
    if (j.contains(k)) target[k] = j[k];
  const DrawRequest req = draw_request_from_json(target);
  const Drawing d = make_drawing(robot, ik, req);
  const std::vector<Stroke> ink = program_ink(robot, j["program"].get<std::string>(), j.value("name", std::string("program.arm")), req.pen);
  const DrawingCheck c = check_drawing(d.strokes, ink, tolerance);
  auto finite = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return json{{"met", c.met}, {"ink_off_mm", finite(c.ink_off_mm)}, {"uncovered_mm", finite(c.uncovered_mm)},
              {"ink_off_at", {c.ink_off_at.x, c.ink_off_at.y}}, {"uncovered_at", {c.uncovered_at.x, c.uncovered_at.y}},
              {"ink_points", c.ink_points}, {"says", c.says}, {"what", d.what},
              {"target", strokes_json(d.strokes)}, {"ink", strokes_json(ink)}};
}

}  // namespace articula::host
