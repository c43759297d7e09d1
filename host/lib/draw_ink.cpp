// host/lib/draw_ink.cpp - the line the arm will draw: the pen's ink from the tool's path or a
// prediction, graded against the drawing, and both drawn as SVG (draw.h).
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blocks.h"
#include "draw_detail.h"
#include "predict.h"
#include "program.h"
#include "xml_text.h"
#include "robot_view.h"

namespace articula::host {

using namespace draw_detail;

bool pen_on_paper(const Vec3<double>& tool, const PenSettings& pen) {
  return tool.z - pen.pen_mm < pen.paper_z + pen.lift_mm / 2;
}

std::vector<Stroke> ink_of_tool_path(const std::vector<Vec3<double>>& tool, const PenSettings& pen) {
  std::vector<Stroke> out;
  bool down = false;
  for (const Vec3<double>& t : tool) {
    const bool on = pen_on_paper(t, pen);
    if (on && !down) out.push_back({});
    if (on) out.back().push_back({t.x, t.y});
    down = on;
  }
  return out;
}

std::vector<Vec3<double>> tool_from_steps(const Robot& robot, const std::vector<int32_t>& steps) {
  const size_t n = size_t(robot.actuation.num_motors);
  if (n == 0) throw std::invalid_argument("the robot has no motors: steps say nothing of where it is");
  if (steps.size() % n)
    throw std::invalid_argument(std::to_string(steps.size()) + " step counts are not rows of " + std::to_string(n) + " (a count per motor)");
  std::vector<Vec3<double>> out;
  out.reserve(steps.size() / n);
  for (size_t k = 0; k < steps.size(); k += n) {
    double q[kMaxJoints];
    joints_from_steps(q, robot.actuation, steps.data() + k);
    out.push_back(tool_position(robot.model, q));
  }
  return out;
}

namespace {
// The strokes' segments (a one-point stroke: a dot) in a grid of 4 mm cells, for the distance
// of a point from the nearest: the cells ring by ring outward from the point's, until a ring
// is farther than the nearest found.
class NearestSegment {
 public:
  explicit NearestSegment(const std::vector<Stroke>& strokes) {
    for (const Stroke& s : strokes)
      for (size_t i = 0; i < s.size(); ++i)
        if (i > 0 || s.size() == 1) segs_.push_back({s[i > 0 ? i - 1 : 0], s[i]});
    if (segs_.empty()) return;
    bounds_ = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (const auto& [a, b] : segs_)
      for (const Point2& p : {a, b})
        bounds_.min_x = std::min(bounds_.min_x, p.x), bounds_.max_x = std::max(bounds_.max_x, p.x),
        bounds_.min_y = std::min(bounds_.min_y, p.y), bounds_.max_y = std::max(bounds_.max_y, p.y);
    nx_ = std::max(1, int(bounds_.width() / kCell) + 1);
    ny_ = std::max(1, int(bounds_.height() / kCell) + 1);
    cells_.resize(size_t(nx_) * size_t(ny_));
    for (size_t k = 0; k < segs_.size(); ++k) {
      const auto& [a, b] = segs_[k];
      const int x0 = cx(std::min(a.x, b.x)), x1 = cx(std::max(a.x, b.x)), y0 = cy(std::min(a.y, b.y)), y1 = cy(std::max(a.y, b.y));
      for (int i = x0; i <= x1; ++i)
        for (int j = y0; j <= y1; ++j) cells_[size_t(i) * size_t(ny_) + size_t(j)].push_back(k);
    }
  }
  double operator()(Point2 p) const {
    if (segs_.empty()) return INFINITY;
    // outside the grid: start from the nearest cell; the rings then grow from there
    const int pi = cx(p.x), pj = cy(p.y);
    const double outside = std::hypot(std::max({bounds_.min_x - p.x, 0.0, p.x - bounds_.max_x}),
                                      std::max({bounds_.min_y - p.y, 0.0, p.y - bounds_.max_y}));
    double best = INFINITY;
    for (int r = 0;; ++r) {
      if (r > 0 && std::max(outside, (r - 1) * kCell) > best) break;  // no nearer segment is left
      bool any = false;
      for (int i = pi - r; i <= pi + r; ++i)
        for (int j = pj - r; j <= pj + r; ++j) {
          if (std::max(std::abs(i - pi), std::abs(j - pj)) != r || i < 0 || j < 0 || i >= nx_ || j >= ny_) continue;
          any = true;
          for (size_t k : cells_[size_t(i) * size_t(ny_) + size_t(j)])
            best = std::min(best, segment_distance(p, segs_[k].first, segs_[k].second));
        }
      if (!any && r > nx_ + ny_) break;
    }
    return best;
  }

 private:
  static constexpr double kCell = 4;
  int cx(double x) const { return std::clamp(int((x - bounds_.min_x) / kCell), 0, nx_ - 1); }
  int cy(double y) const { return std::clamp(int((y - bounds_.min_y) / kCell), 0, ny_ - 1); }
  std::vector<std::pair<Point2, Point2>> segs_;
  Bounds bounds_;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<size_t>> cells_;
};
}  // namespace

PredictedInk predicted_ink(const Drawing& d, const Prediction& prediction, const PenSettings& pen) {
  PredictedInk ink;
  std::vector<Vec3<double>> tool;  // every step of every move, in order
  std::vector<int> line_of;        // the program line that made it
  for (const PredictRecord& r : prediction.records) {
    if (r.reply != kOk) continue;
    tool.insert(tool.end(), r.path.begin(), r.path.end());
    line_of.insert(line_of.end(), r.path.size(), r.line);
  }
  const NearestSegment to_drawing(d.strokes);
  bool down = false;
  for (size_t k = 0; k < tool.size(); ++k) {
    const bool on = pen_on_paper(tool[k], pen);
    if (on && !down) ink.strokes.push_back({});
    down = on;
    if (!on) continue;
    const Point2 p{tool[k].x, tool[k].y};
    ink.strokes.back().push_back(p);
    ++ink.steps;
    const double nearest = to_drawing(p);
    if (nearest > ink.worst_mm) ink.worst_mm = nearest, ink.worst_at = p, ink.worst_line = line_of[k];
  }
  return ink;
}

std::vector<Stroke> program_ink(const Robot& robot, const std::string& program, const std::string& name,
                                const PenSettings& pen) {
  const Prediction p = predict_program(robot, parse_program(program, name, robot), {}, {}, true);
  std::vector<Vec3<double>> tool;
  for (const PredictRecord& r : p.records)
    if (r.reply == kOk) tool.insert(tool.end(), r.path.begin(), r.path.end());
  return ink_of_tool_path(tool, pen);
}

namespace {

std::string at_text(Point2 p) { return "(" + protocol_number(std::round(p.x)) + ", " + protocol_number(std::round(p.y)) + ") mm"; }
}  // namespace

DrawingCheck check_drawing(const std::vector<Stroke>& target, const std::vector<Stroke>& ink, double tolerance_mm) {
  DrawingCheck c;
  const NearestSegment to_target(target), to_ink(ink);
  for (const Stroke& s : ink)
    for (const Point2& p : s) {
      ++c.ink_points;
      const double d = to_target(p);
      if (d > c.ink_off_mm) c.ink_off_mm = d, c.ink_off_at = p;
    }
  if (c.ink_points == 0) {
    c.says = "no ink: the pen never touched the paper (is it down at the paper's height?)";
    c.uncovered_mm = INFINITY;
    return c;
  }
  for (const Stroke& s : target)
    for (size_t i = 0; i < s.size(); ++i) {
      const Point2 a = s[i], b = i + 1 < s.size() ? s[i + 1] : s[i];
      const int n = std::max(1, int(std::ceil(dist(a, b))));  // every mm
      for (int k = 0; k <= n; ++k) {
        const Point2 p{a.x + (b.x - a.x) * k / n, a.y + (b.y - a.y) * k / n};
        const double d = to_ink(p);
        if (d > c.uncovered_mm) c.uncovered_mm = d, c.uncovered_at = p;
      }
    }
  c.met = c.ink_off_mm <= tolerance_mm && c.uncovered_mm <= tolerance_mm;
  const std::string tol = protocol_number(tolerance_mm) + " mm";
  if (c.met)
    c.says = "the ink stays within " + protocol_number(std::round(c.ink_off_mm * 10) / 10) + " mm of the target and covers all of it (within " +
             tol + ")";
  else if (c.ink_off_mm > tolerance_mm && c.uncovered_mm > tolerance_mm)
    c.says = "ink " + protocol_number(std::round(c.ink_off_mm * 10) / 10) + " mm off the target at " + at_text(c.ink_off_at) +
             ", and the target not drawn at " + at_text(c.uncovered_at) + " (" + protocol_number(std::round(c.uncovered_mm * 10) / 10) +
             " mm from any ink): both must be within " + tol;
  else if (c.ink_off_mm > tolerance_mm)
    c.says = "ink " + protocol_number(std::round(c.ink_off_mm * 10) / 10) + " mm off the target at " + at_text(c.ink_off_at) + ": it must stay within " + tol;
  else
    c.says = "the target is not drawn at " + at_text(c.uncovered_at) + ": the nearest ink is " +
             protocol_number(std::round(c.uncovered_mm * 10) / 10) + " mm away (within " + tol + " counts)";
  return c;
}

std::string drawing_svg(const Drawing& d, const PredictedInk& ink, const std::string& title) {
  Bounds b = d.bounds;
  for (const Stroke& s : ink.strokes)
    for (const Point2& p : s) b.min_x = std::min(b.min_x, p.x), b.max_x = std::max(b.max_x, p.x),
                              b.min_y = std::min(b.min_y, p.y), b.max_y = std::max(b.max_y, p.y);
  const double margin = 5 + 0.05 * std::max(b.width(), b.height());
  // seen from above by someone at +x facing the arm: +y to the right, +x down
  const double w = std::max(b.height() + 2 * margin, 150.0), h = b.width() + 2 * margin + 8;  // room for the caption
  auto sx = [&](const Point2& p) { return p.y - b.min_y + margin; };
  auto sy = [&](const Point2& p) { return p.x - b.min_x + margin; };
  auto poly = [&](const Stroke& s) {
    std::string pts;
    char buf[64];
    for (const Point2& p : s) {
      std::snprintf(buf, sizeof buf, "%s%.3f,%.3f", pts.empty() ? "" : " ", sx(p), sy(p));
      pts += buf;
    }
    return "<polyline points=\"" + pts + "\"/>";
  };
  char head[512];
  std::snprintf(head, sizeof head,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.1fmm\" height=\"%.1fmm\" viewBox=\"0 0 %.3f %.3f\">\n",
                w, h, w, h);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + std::string(head);
  out += "<title>" + xml_text(title) + "</title>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out += "<g id=\"ideal\" fill=\"none\" stroke=\"#1d4ed8\" stroke-width=\"0.6\" stroke-linecap=\"round\" "
         "stroke-linejoin=\"round\" opacity=\"0.45\">\n";
  for (const Stroke& s : d.strokes) out += "  " + poly(s) + "\n";
  out += "</g>\n<g id=\"predicted\" fill=\"none\" stroke=\"#c2410c\" stroke-width=\"0.2\" stroke-linejoin=\"round\">\n";
  for (const Stroke& s : ink.strokes) out += "  " + poly(s) + "\n";
  out += "</g>\n";
  if (ink.steps) {
    char mark[600];
    std::snprintf(mark, sizeof mark,
                  "<g id=\"worst\"><circle cx=\"%.3f\" cy=\"%.3f\" r=\"1.5\" fill=\"none\" stroke=\"#b91c1c\" "
                  "stroke-width=\"0.3\"/>\n<text x=\"%.3f\" y=\"%.3f\" font-family=\"sans-serif\" font-size=\"3.5\" "
                  "fill=\"#333\">blue: the drawing; orange: the pen at every step; worst %.2f mm (line %d)</text></g>\n",
                  sx(ink.worst_at), sy(ink.worst_at), margin, h - 3, ink.worst_mm, ink.worst_line);
    out += mark;
  }
  return out + "</svg>\n";
}

}  // namespace articula::host
