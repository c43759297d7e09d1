// host/lib/draw.cpp - strokes from text and shapes, placed, checked, ordered and written as a
// program (draw.h).
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "blocks.h"
#include "predict.h"
#include "program.h"
#include "svg.h"
#include "robot_view.h"

namespace articula::host {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSampleMm = 2;      // the reach check's spacing along a stroke
constexpr double kMoveStepMm = 5;    // the reach check's search for a move that fits
constexpr double kMoveMaxMm = 300;
constexpr double kSameMm = 0.01;     // points closer than this are one
constexpr double kTieMm = 1e-6;      // the order's nearest ends: closer than this are a tie

double dist(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

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

// The code points of UTF-8 text (a malformed byte stands for itself).
std::vector<uint32_t> code_points(const std::string& s) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 0 : c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    uint32_t cp = n == 0 ? c : c & (0x3F >> n);
    size_t k = 1;
    for (; k <= size_t(n) && i + k < s.size() && (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80; ++k)
      cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    if (k != size_t(n) + 1) cp = c, k = 1;
    out.push_back(cp);
    i += k;
  }
  return out;
}

std::string utf8(uint32_t cp) {
  std::string s;
  if (cp < 0x80) {
    s += char(cp);
  } else if (cp < 0x800) {
    s += char(0xC0 | (cp >> 6)), s += char(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    s += char(0xE0 | (cp >> 12)), s += char(0x80 | ((cp >> 6) & 0x3F)), s += char(0x80 | (cp & 0x3F));
  } else {
    s += char(0xF0 | (cp >> 18)), s += char(0x80 | ((cp >> 12) & 0x3F)), s += char(0x80 | ((cp >> 6) & 0x3F)),
        s += char(0x80 | (cp & 0x3F));
  }
  return s;
}

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

// ---- the font

std::string default_font_path() { return "/usr/share/hershey-fonts/futural.jhf"; }

HersheyFont parse_hershey(const std::string& text, const std::string& name) {
  HersheyFont font;
  font.source = name;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const int first = number;
    auto bad = [&](const std::string& why) {
      return std::invalid_argument(name + ":" + std::to_string(first) + ": " + why + " (a Hershey .jhf glyph)");
    };
    if (line.size() < 10) throw bad("too short");
    int count = 0;
    try {
      count = std::stoi(line.substr(5, 3));
    } catch (const std::exception&) {
      throw bad("no vertex count in columns 6-8");
    }
    if (count < 1) throw bad("a vertex count below 1");
    std::string pairs = line.substr(8);
    // a long glyph may go on over the next lines
    while (pairs.size() < size_t(count) * 2 && std::getline(in, line)) {
      ++number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      pairs += line;
    }
    if (pairs.size() < size_t(count) * 2) throw bad("fewer coordinates than its count, " + std::to_string(count));
    HersheyGlyph g;
    g.left = pairs[0] - 'R';
    g.right = pairs[1] - 'R';
    Stroke cur;
    for (int i = 1; i < count; ++i) {
      const char cx = pairs[size_t(i) * 2], cy = pairs[size_t(i) * 2 + 1];
      if (cx == ' ' && cy == 'R') {
        if (!cur.empty()) g.strokes.push_back(cur);
        cur.clear();
        continue;
      }
      if (cx < ' ' || cx > '~' || cy < ' ' || cy > '~') throw bad("a coordinate outside ' ' .. '~'");
      cur.push_back({double(cx - 'R'), -double(cy - 'R')});  // the font's y points down
    }
    if (!cur.empty()) g.strokes.push_back(cur);
    font.glyphs.push_back(std::move(g));
  }
  if (font.glyphs.size() < size_t('H' - ' ' + 1))
    throw std::invalid_argument(name + ": " + std::to_string(font.glyphs.size()) +
                                " glyphs: a font for text has one for each character from ' ' to '~' (95)");
  const Bounds h = bounds_of(font.glyphs[size_t('H' - ' ')].strokes);
  if (!(h.height() > 0)) throw std::invalid_argument(name + ": its 'H' has no height");
  font.cap_height = h.height();
  // the baseline at y 0: the foot of the 'H'
  for (HersheyGlyph& g : font.glyphs)
    for (Stroke& s : g.strokes)
      for (Point2& p : s) p.y -= h.min_y;
  return font;
}

namespace {
std::invalid_argument unreadable_font(const std::string& path) {
  return std::invalid_argument("cannot read the font " + path +
                               (path == default_font_path() ? " (Debian's hershey-fonts-data: scripts/bootstrap installs it)" : ""));
}
}  // namespace

HersheyFont load_hershey(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw unreadable_font(path);
  std::ostringstream s;
  s << f.rdbuf();
  return parse_hershey(s.str(), path);
}

namespace {
// The fonts read so far, by path and text: a file read again is parsed once (the page's engine
// and a Python session draw many times with the same font).
const HersheyFont& cached_font(const std::string& path) {
  static std::mutex lock;
  static std::map<std::string, std::pair<std::string, HersheyFont>> fonts;
  std::ifstream f(path, std::ios::binary);
  if (!f) throw unreadable_font(path);
  std::ostringstream s;
  s << f.rdbuf();
  const std::lock_guard<std::mutex> hold(lock);
  auto it = fonts.find(path);
  if (it == fonts.end() || it->second.first != s.str())
    it = fonts.insert_or_assign(path, std::make_pair(s.str(), parse_hershey(s.str(), path))).first;
  return it->second.second;
}
}  // namespace

std::vector<Stroke> text_strokes(const HersheyFont& font, const std::string& text, double cap_height_mm,
                                 double line_spacing) {
  if (!(cap_height_mm > 0) || !std::isfinite(cap_height_mm)) throw std::invalid_argument("the text's height must be > 0 mm");
  if (!(line_spacing > 0) || !std::isfinite(line_spacing)) throw std::invalid_argument("the line spacing must be > 0");
  const std::vector<uint32_t> cps = code_points(text);
  std::vector<std::string> missing;
  for (uint32_t c : cps) {
    if (c == '\n' || c == '\r') continue;
    if (c < 32 || c > 126 || c - 32 >= font.glyphs.size()) {
      char code[16];
      std::snprintf(code, sizeof code, "U+%04X", unsigned(c));
      const std::string name = c < 32 || c == 0x7F ? std::string(code) : "'" + utf8(c) + "' (" + code + ")";
      if (std::find(missing.begin(), missing.end(), name) == missing.end()) missing.push_back(name);
    }
  }
  if (!missing.empty()) {
    std::string list;
    for (size_t i = 0; i < missing.size(); ++i) list += (i ? ", " : "") + missing[i];
    throw std::invalid_argument("the font (" + font.source + ") has no " + list +
                                ": it holds the characters from ' ' to '~' (ASCII)");
  }
  const double s = cap_height_mm / font.cap_height;
  std::vector<Stroke> out;
  double x = 0, y = 0;
  for (uint32_t c : cps) {
    if (c == '\r') continue;
    if (c == '\n') {
      x = 0;
      y -= line_spacing * cap_height_mm;
      continue;
    }
    const HersheyGlyph& g = font.glyphs[c - 32];
    for (const Stroke& st : g.strokes) {
      Stroke placed;
      for (const Point2& p : st) placed.push_back({x + (p.x - g.left) * s, y + p.y * s});
      out.push_back(placed);
    }
    x += (g.right - g.left) * s;
  }
  return out;
}

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

// ---- placing, reaching, ordering, the program

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

namespace {
double segment_distance(Point2 p, Point2 a, Point2 b);
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
  pen.pen_mm = num("pen", 0);
  const ReachMap m = reach_map(robot, ik, pen, area, cell);
  std::string bits(m.reached.size(), '0');
  for (size_t i = 0; i < bits.size(); ++i) bits[i] = m.reached[i] ? '1' : '0';
  return json{{"rows", m.rows}, {"cols", m.cols}, {"cell", m.cell_mm},
              {"area", {area.min_x, area.min_y, area.max_x, area.max_y}}, {"reached", bits}};
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

std::string drawing_program(const Robot& robot, const std::vector<Stroke>& strokes, const PenSettings& pen,
                            const std::string& title) {
  return drawing_program(robot, strokes, pen, title, nullptr);
}

std::string drawing_program(const Robot& robot, const std::vector<Stroke>& strokes, const PenSettings& pen,
                            const std::string& title, std::vector<int>* ink_lines) {
  const double down = pen.paper_z + pen.pen_mm, up = down + pen.lift_mm;
  int line_no = 2;  // the two comment lines
  std::string out = "# " + title + "\n# the pen " + protocol_number(pen.pen_mm) + " mm below the tool point, the paper at z " +
                    protocol_number(pen.paper_z) + " mm; " + protocol_number(pen.speed) + " mm/s drawing, " + protocol_number(pen.travel_speed) +
                    " mm/s between strokes, the pen " + protocol_number(pen.lift_mm) + " mm up\n";
  auto line = [&](char word, Point2 p, double z, double speed, bool ink) {
    out += protocol_line(robot, word, word == 'P' ? std::vector<double>{p.x, p.y, z} : std::vector<double>{p.x, p.y, z, speed}) + "\n";
    ++line_no;
    if (ink && ink_lines) ink_lines->push_back(line_no);
  };
  bool first = true;
  for (const Stroke& s : strokes) {
    if (s.empty()) continue;
    if (first) line('P', s.front(), up, 0, false);
    else line('T', s.front(), up, pen.travel_speed, false);
    first = false;
    line('T', s.front(), down, pen.speed, false);
    for (size_t i = 1; i < s.size(); ++i) line('T', s[i], down, pen.speed, true);
    line('T', s.back(), up, pen.speed, false);
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

Drawing make_drawing(const Robot& robot, const InverseKinematics& ik, const DrawRequest& req) {
  if (int(!req.text.empty()) + int(!req.shape.empty()) + int(!req.svg.empty()) + int(!req.freehand.empty()) != 1)
    throw std::invalid_argument("give one of a text, a shape, an SVG file and strokes drawn by hand");
  const PenSettings& pen = req.pen;
  if (!std::isfinite(pen.paper_z) || !(pen.pen_mm >= 0) || !std::isfinite(pen.pen_mm))
    throw std::invalid_argument("the paper's height must be a number and the pen's length >= 0 mm");
  if (!(pen.lift_mm > 0) || !(pen.speed > 0) || !(pen.travel_speed > 0) || !std::isfinite(pen.lift_mm) ||
      pen.speed > 1000 || pen.travel_speed > 1000)
    throw std::invalid_argument("the lift must be > 0 mm and the speeds from more than 0 to 1000 mm/s");
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
  r.pen.pen_mm = num("pen", 0);
  r.pen.lift_mm = num("lift", r.pen.lift_mm);
  r.pen.speed = num("speed", r.pen.speed);
  r.pen.travel_speed = num("travel_speed", r.pen.travel_speed);
  return r;
}

namespace {
double segment_distance(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}
std::string svg_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}
}  // namespace

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
  const std::vector<Stroke> ink = ink_of_tool_path(tool, pen);
  size_t points = 0;
  for (const Stroke& s : ink) points += s.size();
  return json{{"strokes", strokes_json(ink)}, {"points", points}};
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
  out += "<title>" + svg_text(title) + "</title>\n";
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
