// host/lib/draw.cpp - a drawing made: its strokes placed, checked against the arm's reach,
// ordered and written as a program (draw.h). The font, the strokes' geometry, the ink and the
// JSON entries have files of their own (draw_*.cpp).
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "blocks.h"
#include "predict.h"
#include "program.h"
#include "svg.h"
#include "robot_view.h"
#include "draw_detail.h"

namespace articula::host {

using namespace draw_detail;

namespace {

// Every point the pen must reach: along each stroke every kSampleMm at the paper, and its
// ends at the lifted height (z). Shifted by (dx, dy).
struct Sample {
  Point2 p;
  bool lifted;
};
std::vector<Sample> samples_of(const std::vector<Stroke>& strokes) {
  std::vector<Sample> out;
  for (const Stroke& s : strokes) {
    if (s.empty()) continue;
    out.push_back({s.front(), true});
    out.push_back({s.front(), false});
    for (size_t i = 1; i < s.size(); ++i) {
      const double d = dist(s[i - 1], s[i]);
      const int n = std::max(1, int(std::ceil(d / kSampleMm)));
      for (int k = 1; k <= n; ++k) {
        const double t = double(k) / n;
        out.push_back({{s[i - 1].x + (s[i].x - s[i - 1].x) * t, s[i - 1].y + (s[i].y - s[i - 1].y) * t}, false});
      }
    }
    out.push_back({s.back(), true});
  }
  return out;
}

class Reach {
 public:
  Reach(const Robot& r, const InverseKinematics& ik, const PenSettings& pen)
      : ik_(ik), pen_(pen), opts_(ik_options("auto", nullptr, 0.01, 0, 1)), q_(joints_in(r, home_pose(r), "home")) {}
  bool reaches(const Sample& s, double dx, double dy) {
    const double z = pen_.paper_z + pen_.pen_mm + (s.lifted ? pen_.lift_mm : 0);
    const double target[3] = {s.p.x + dx, s.p.y + dy, z};
    const IkResult res = ik_.solve(ik_target(target, 3), q_, opts_);
    if (res.status != IkStatus::kReached) return false;
    q_ = res.q;
    return true;
  }
  bool all(const std::vector<Sample>& samples, double dx, double dy) {
    for (const Sample& s : samples)
      if (!reaches(s, dx, dy)) return false;
    return true;
  }

 private:
  const InverseKinematics& ik_;
  PenSettings pen_;
  IkOptions opts_;
  std::vector<double> q_;
};

std::string toward(double d, const char* axis) {
  return protocol_number(std::fabs(d)) + " mm toward " + (d > 0 ? "+" : "-") + axis;
}

}  // namespace

bool reaches_all(const Robot& robot, const InverseKinematics& ik, const std::vector<Stroke>& strokes,
                 const PenSettings& pen) {
  Reach reach(robot, ik, pen);
  return reach.all(samples_of(strokes), 0, 0);
}

ReachCheck check_reach(const Robot& robot, const InverseKinematics& ik, const std::vector<Stroke>& strokes,
                       const PenSettings& pen) {
  ReachCheck out;
  const std::vector<Sample> samples = samples_of(strokes);
  out.points = int(samples.size());
  Reach reach(robot, ik, pen);
  for (const Sample& s : samples)
    if (!reach.reaches(s, 0, 0)) out.unreachable.push_back(s.p);
  out.fits = out.unreachable.empty();
  if (out.fits) return out;
  const Bounds b = bounds_of(strokes);
  const Point2 centre{(b.min_x + b.max_x) / 2, (b.min_y + b.max_y) / 2};
  for (double d = kMoveStepMm; d <= kMoveMaxMm && !out.movable; d += kMoveStepMm) {
    for (int k = 0; k < 8 && !out.movable; ++k) {
      const double dx = std::round(d * std::cos(kPi * k / 4) * 10) / 10, dy = std::round(d * std::sin(kPi * k / 4) * 10) / 10;
      if (reach.all(samples, dx, dy)) out.movable = true, out.move_x = dx, out.move_y = dy;
    }
  }
  const std::string unreached = std::to_string(out.unreachable.size()) + " of " + std::to_string(out.points) +
                                " points of the drawing are out of the pen's reach";
  if (!out.movable) {
    if (out.unreachable.size() == size_t(out.points))
      out.advice = "the pen reaches none of the drawing's " + std::to_string(out.points) + " points, nor after a move of up to " +
                   protocol_number(kMoveMaxMm) + " mm: the tool would go down to z " + protocol_number(pen.paper_z + pen.pen_mm) +
                   " mm; a longer pen or the paper higher up brings it within reach";
    else
      out.advice = unreached + ", and no move of up to " + protocol_number(kMoveMaxMm) +
                   " mm brings all of it within reach: make it smaller";
    return out;
  }
  std::string where;
  if (out.move_x != 0) where = toward(out.move_x, "x");
  if (out.move_y != 0) where += (where.empty() ? "" : " and ") + toward(out.move_y, "y");
  const double radial = out.move_x * centre.x + out.move_y * centre.y;
  const char* side = radial > 0 ? " (away from the base)" : radial < 0 ? " (toward the base)" : "";
  out.advice = unreached + ": move it " + where + side + ", to (" + protocol_number(centre.x + out.move_x) + ", " +
               protocol_number(centre.y + out.move_y) + ") mm";
  return out;
}

ReachMap reach_map(const Robot& robot, const InverseKinematics& ik, const PenSettings& pen, const Bounds& area,
                   double cell_mm) {
  if (!(cell_mm > 0) || !(area.width() > 0) || !(area.height() > 0))
    throw std::invalid_argument("a reach map needs an area and a cell of some size");
  ReachMap m;
  m.area = area;
  m.cell_mm = cell_mm;
  m.rows = std::max(1, int(std::ceil(area.width() / cell_mm)));
  m.cols = std::max(1, int(std::ceil(area.height() / cell_mm)));
  m.reached.assign(size_t(m.rows) * size_t(m.cols), 0);
  Reach reach(robot, ik, pen);
  for (int r = 0; r < m.rows; ++r)
    for (int k = 0; k < m.cols; ++k) {
      const int c = r % 2 ? m.cols - 1 - k : k;  // to and fro: each solve starts beside the last
      const Sample s{{area.min_x + (r + 0.5) * cell_mm, area.min_y + (c + 0.5) * cell_mm}, false};
      m.reached[size_t(r) * size_t(m.cols) + size_t(c)] = reach.reaches(s, 0, 0) ? 1 : 0;
    }
  return m;
}

std::string drawing_program(const Robot& robot, const std::vector<Stroke>& strokes, const PenSettings& pen,
                            const std::string& title) {
  return drawing_program(robot, strokes, pen, title, nullptr);
}

std::string drawing_program(const Robot& robot, const std::vector<Stroke>& strokes, const PenSettings& pen,
                            const std::string& title, std::vector<int>* ink_lines) {
  int line_no = 2;  // the two comment lines
  std::string out = "# " + title + "\n# the pen " + protocol_number(pen.pen_mm) + " mm below the tool point, the paper at z " +
                    protocol_number(pen.paper_z) + " mm; " + protocol_number(pen.speed) + " mm/s drawing, " + protocol_number(pen.travel_speed) +
                    " mm/s between strokes, the pen " + protocol_number(pen.lift_mm) + " mm up\n";
  for (const PenMove& m : pen_moves(strokes, pen)) {
    out += protocol_line(robot, m.reach ? 'P' : 'T',
                         m.reach ? std::vector<double>{m.x, m.y, m.z} : std::vector<double>{m.x, m.y, m.z, m.speed}) + "\n";
    ++line_no;
    if (m.ink && ink_lines) ink_lines->push_back(line_no);
  }
  return out;
}

std::vector<PenMove> pen_moves(const std::vector<Stroke>& strokes, const PenSettings& pen) {
  const double down = pen.paper_z + pen.pen_mm, up = down + pen.lift_mm;
  std::vector<PenMove> out;
  for (const Stroke& s : strokes) {
    if (s.empty()) continue;
    if (out.empty()) out.push_back({true, s.front().x, s.front().y, up, 0, false});
    else out.push_back({false, s.front().x, s.front().y, up, pen.travel_speed, false});
    out.push_back({false, s.front().x, s.front().y, down, pen.speed, false});
    for (size_t i = 1; i < s.size(); ++i) out.push_back({false, s[i].x, s[i].y, down, pen.speed, true});
    out.push_back({false, s.back().x, s.back().y, up, pen.speed, false});
  }
  return out;
}

bool paper_size(const std::string& name, double& width_mm, double& height_mm) {
  if (name == "A4") width_mm = 210, height_mm = 297;
  else if (name == "A5") width_mm = 148, height_mm = 210;
  else if (name == "Letter") width_mm = 215.9, height_mm = 279.4;
  else return false;
  return true;
}

Robot with_microsteps(const Robot& robot, int microsteps) {
  if (!robot.has_motors) throw std::invalid_argument(robot.name + " has no motors: no steps to make finer");
  if (microsteps != 1 && microsteps != 2)
    throw std::invalid_argument("microsteps: 1 (full steps) or 2 (half steps), the two the Nano's L298N table makes");
  Robot r = robot;
  for (int k = 0; k < r.actuation.num_motors; ++k) r.actuation.motors[k].microsteps = uint8_t(microsteps);
  return r;
}

std::string pen_value_problem(const PenField& f, double v) {
  const bool low = f.min_excluded ? !(v > f.min) : !(v >= f.min);
  if (std::isfinite(v) && !low && v <= f.max) return "";
  return std::string(f.key) + " must be " + (f.min_excluded ? "more than " : "at least ") + protocol_number(f.min) +
         " and at most " + protocol_number(f.max) + " " + f.unit + ", not " + (std::isfinite(v) ? protocol_number(v) : std::string("a non-number"));
}

void check_pen(const PenSettings& pen) {
  if (!std::isfinite(pen.paper_z)) throw std::invalid_argument("z, the paper's height, must be a number");
  const double v[] = {pen.pen_mm, pen.lift_mm, pen.speed, pen.travel_speed};
  for (size_t i = 0; i < std::size(kPenFields); ++i) {
    const std::string problem = pen_value_problem(kPenFields[i], v[i]);
    if (!problem.empty()) throw std::invalid_argument(problem);
  }
}

Drawing make_drawing(const Robot& robot, const InverseKinematics& ik, const DrawRequest& req) {
  if (int(!req.text.empty()) + int(!req.shape.empty()) + int(!req.svg.empty()) + int(!req.freehand.empty()) != 1)
    throw std::invalid_argument("give one of a text, a shape, an SVG file and strokes drawn by hand");
  const PenSettings& pen = req.pen;
  check_pen(pen);
  Drawing d;
  std::vector<Stroke> laid;
  if (!req.text.empty()) {
    const HersheyFont& font = cached_font(req.font_path.empty() ? default_font_path() : req.font_path);
    laid = text_strokes(font, req.text, 10, req.line_spacing);
    d.what = "\"" + req.text + "\"";
  } else if (!req.shape.empty()) {
    laid = shape_strokes(req.shape);
    d.what = "a " + req.shape;
  } else if (!req.freehand.empty()) {
    laid = smooth_strokes(req.freehand);
    d.what = "a drawing by hand";
  } else {
    if (!(req.tolerance_mm > 0) || !std::isfinite(req.tolerance_mm)) throw std::invalid_argument("the chord tolerance must be > 0 mm");
    if (!(req.width_mm > 0) || !std::isfinite(req.width_mm)) throw std::invalid_argument("the drawing's width must be > 0 mm");
    const SvgDrawing svg = read_svg(req.svg, req.svg_name);
    if (!(svg.bounds.width() > 0)) throw SvgError(req.svg_name + ": the drawing has no width: nothing to scale");
    // the tolerance on the paper, in the file's units: the drawing is scaled to the width
    laid = flatten_svg(svg, req.tolerance_mm * svg.bounds.width() / req.width_mm);
    d.what = req.svg_name;
  }
  if (!req.freehand.empty()) {  // drawn where it goes
    d.strokes = laid;
    const Bounds own = bounds_of(laid);
    d.width_mm = own.height();  // across the student's view: the table's y
    d.height_mm = own.width();
  } else {
    d.strokes = place_strokes(laid, req.width_mm, req.x, req.y, req.rotation_deg);
    const Bounds own = bounds_of(laid);
    d.width_mm = req.width_mm;
    d.height_mm = own.width() > 0 ? own.height() * req.width_mm / own.width() : 0;
  }
  if (!req.paper.empty()) {
    double pw = 0, ph = 0;
    if (!paper_size(req.paper, pw, ph)) throw std::invalid_argument("no paper '" + req.paper + "': A4, A5 or Letter");
    const double w = d.width_mm, h = d.height_mm;
    if (!((w <= pw && h <= ph) || (w <= ph && h <= pw)))
      throw std::invalid_argument("the drawing, " + protocol_number(w) + " x " + protocol_number(h) + " mm, is bigger than " + req.paper + " (" + protocol_number(pw) +
                                  " x " + protocol_number(ph) + " mm): make it narrower");
  }
  d.bounds = bounds_of(d.strokes);
  d.reach = check_reach(robot, ik, d.strokes, pen);
  // from where the arm powers up: every motor at its zero angle (without motors: its home)
  const std::vector<double> q0 = power_up_pose(robot);
  HostFrames frames;
  forward_kinematics(frames, robot.model, joints_in(robot, q0, "start").data());
  d.start = {frames.T_base_tool.p.x, frames.T_base_tool.p.y};
  d.travel_unordered_mm = travel_mm(d.strokes, d.start);
  if (d.reach.fits) {
    d.strokes = order_strokes(d.strokes, d.start);
    d.travel_mm = travel_mm(d.strokes, d.start);
    d.program = drawing_program(robot, d.strokes, pen, "drawn by Articula: " + d.what, &d.ink_lines);
  } else {
    d.travel_mm = d.travel_unordered_mm;
  }
  return d;
}

}  // namespace articula::host
