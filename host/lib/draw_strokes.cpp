// host/lib/draw_strokes.cpp - the plane geometry of strokes: shapes, bounds, placing on the
// paper, smoothing, the order that cuts the pen's travel (draw.h).
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "draw_detail.h"

namespace articula::host {

using namespace draw_detail;

std::vector<Stroke> shape_strokes(const std::string& shape) {
  Stroke s;
  if (shape == "square") {
    s = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}, {-0.5, -0.5}};
  } else if (shape == "circle") {
    const int n = 96;  // a chord 0.2 % of the radius from the circle
    for (int i = 0; i <= n; ++i) s.push_back({0.5 * std::cos(2 * kPi * i / n), 0.5 * std::sin(2 * kPi * i / n)});
  } else if (shape == "star") {
    // five points: the outer corners and the inner ones between, from the top
    const double inner = 0.5 * std::sin(kPi / 10) / std::sin(7 * kPi / 10);
    for (int i = 0; i <= 10; ++i) {
      const double a = kPi / 2 + kPi * i / 5, r = i % 2 ? inner : 0.5;
      s.push_back({r * std::cos(a), r * std::sin(a)});
    }
  } else {
    throw std::invalid_argument("no shape '" + shape + "': square, circle or star");
  }
  return {s};
}

Bounds bounds_of(const std::vector<Stroke>& strokes) {
  Bounds b;
  bool any = false;
  for (const Stroke& s : strokes)
    for (const Point2& p : s) {
      if (!any) b = {p.x, p.y, p.x, p.y};
      any = true;
      b.min_x = std::min(b.min_x, p.x), b.max_x = std::max(b.max_x, p.x);
      b.min_y = std::min(b.min_y, p.y), b.max_y = std::max(b.max_y, p.y);
    }
  return b;
}

std::vector<Stroke> place_strokes(const std::vector<Stroke>& strokes, double width_mm, double x, double y,
                                  double rotation_deg) {
  if (!(width_mm > 0) || !std::isfinite(width_mm)) throw std::invalid_argument("the drawing's width must be > 0 mm");
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(rotation_deg))
    throw std::invalid_argument("the drawing's place and turn must be finite numbers");
  const Bounds b = bounds_of(strokes);
  if (!(b.width() > 0)) throw std::invalid_argument("the drawing has no width: nothing to scale");
  const double s = width_mm / b.width(), cx = (b.min_x + b.max_x) / 2, cy = (b.min_y + b.max_y) / 2;
  const double c = std::cos(rotation_deg * kPi / 180), sn = std::sin(rotation_deg * kPi / 180);
  std::vector<Stroke> out;
  for (const Stroke& st : strokes) {
    Stroke o;
    for (const Point2& p : st) {
      const double u = (p.x - cx) * s, v = (p.y - cy) * s;
      o.push_back({x + c * u - sn * v, y + sn * u + c * v});
    }
    out.push_back(o);
  }
  return out;
}

namespace {
void simplify(const Stroke& s, size_t i, size_t j, double tol, std::vector<bool>& keep) {
  double worst = 0;
  size_t at = i;
  for (size_t k = i + 1; k < j; ++k) {
    const double d = segment_distance(s[k], s[i], s[j]);
    if (d > worst) worst = d, at = k;
  }
  if (worst <= tol) return;
  keep[at] = true;
  simplify(s, i, at, tol, keep);
  simplify(s, at, j, tol, keep);
}
}  // namespace

std::vector<Stroke> smooth_strokes(const std::vector<Stroke>& strokes, double tolerance_mm) {
  std::vector<Stroke> out;
  for (const Stroke& s : strokes) {
    if (s.empty()) continue;
    Stroke m = s;
    for (size_t i = 1; i + 1 < s.size(); ++i) {
      const size_t a = i >= 2 ? i - 2 : 0, b = std::min(s.size() - 1, i + 2);
      Point2 sum{0, 0};
      for (size_t k = a; k <= b; ++k) sum.x += s[k].x, sum.y += s[k].y;
      m[i] = {sum.x / double(b - a + 1), sum.y / double(b - a + 1)};
    }
    std::vector<bool> keep(m.size(), false);
    keep.front() = keep.back() = true;
    if (m.size() > 2) simplify(m, 0, m.size() - 1, tolerance_mm, keep);
    Stroke k;
    for (size_t i = 0; i < m.size(); ++i)
      if (keep[i]) k.push_back(m[i]);
    out.push_back(std::move(k));
  }
  return out;
}

std::vector<Stroke> order_strokes(std::vector<Stroke> strokes, Point2 start) {
  // drop repeated points
  std::vector<Stroke> left;
  for (Stroke& s : strokes) {
    Stroke c;
    for (const Point2& p : s)
      if (c.empty() || dist(c.back(), p) >= kSameMm) c.push_back(p);
    if (!c.empty()) left.push_back(std::move(c));
  }
  std::vector<Stroke> out;
  Point2 at = start;
  while (!left.empty()) {
    size_t best = 0;
    bool reverse = false;
    double best_d = INFINITY;
    for (size_t i = 0; i < left.size(); ++i) {
      // nearer by more than a micrometre: ties (a pattern's repeats) go to the first, whatever
      // the compiler's rounding (the page's engine and the native library order alike)
      const double a = dist(at, left[i].front()), z = dist(at, left[i].back());
      if (a < best_d - kTieMm) best_d = a, best = i, reverse = false;
      if (z < best_d - kTieMm) best_d = z, best = i, reverse = true;
    }
    Stroke s = std::move(left[best]);
    left.erase(left.begin() + long(best));
    if (reverse) std::reverse(s.begin(), s.end());
    at = s.back();
    out.push_back(std::move(s));
  }
  return out;
}

double travel_mm(const std::vector<Stroke>& strokes, Point2 start) {
  double d = 0;
  Point2 at = start;
  for (const Stroke& s : strokes) {
    if (s.empty()) continue;
    d += dist(at, s.front());
    at = s.back();
  }
  return d;
}

}  // namespace articula::host
