// host/physics/mat.cpp - see mat.h.
#include "mat.h"

#include "ik.h"
#include "xml_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace articula::host {

namespace {

struct P {
  double x, y;
};

// The convex hull of points (Andrew's monotone chain), counter-clockwise.
std::vector<P> hull(std::vector<P> pts) {
  std::sort(pts.begin(), pts.end(), [](const P& a, const P& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (pts.size() < 3) return pts;
  auto cross = [](const P& o, const P& a, const P& b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  std::vector<P> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i - 1]) <= 0) --k;
    h[k++] = pts[i - 1];
  }
  h.resize(k - 1);
  return h;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

// An object's outline on the table: a circle (centre, radius) or a polygon.
struct Outline {
  bool circle = false;
  P centre{0, 0};
  double r = 0;
  std::vector<P> poly;
};

Outline outline(const SceneObject& o) {
  const Mat3<double> R = o.rotation();
  Outline out;
  out.centre = {o.xyz.x, o.xyz.y};
  double hx = 0, hy = 0, hz = 0;
  switch (o.type) {
    case SceneObject::Type::kSphere:
      out.circle = true, out.r = o.size[0];
      return out;
    case SceneObject::Type::kCylinder:
      if (std::fabs(R.m[2][2]) > 1 - 1e-9) {  // upright: its axis along the table's z
        out.circle = true, out.r = o.size[0];
        return out;
      }
      hx = hy = o.size[0], hz = o.size[1] / 2;
      break;
    case SceneObject::Type::kBox: hx = o.size[0] / 2, hy = o.size[1] / 2, hz = o.size[2] / 2; break;
  }
  std::vector<P> corners;
  for (int k = 0; k < 8; ++k) {
    const Vec3<double> c = make_vec3((k & 1 ? hx : -hx), (k & 2 ? hy : -hy), (k & 4 ? hz : -hz));
    const Vec3<double> p = R * c + o.xyz;
    corners.push_back({p.x, p.y});
  }
  out.poly = hull(corners);
  return out;
}

struct Arm {
  std::string name;
  Vec3<double> xyz;
  double yaw_deg, footprint_mm;
  P reach_centre;  // where its tool can touch the table: within reach_mm of this point (a bound)
  double reach_mm;
};

std::string drawing(const std::string& title, const Scene& scene, const std::vector<Arm>& arms,
                    const std::vector<CellDevice>& devices) {
  // what stands on the table at the start (a feeder's magazine does not)
  std::vector<bool> stowed(scene.objects.size(), false);
  for (const CellDevice& d : devices)
    for (int o : d.magazine) stowed[size_t(o)] = true;
  std::vector<Outline> outlines(scene.objects.size());
  double x0 = -30, x1 = 30, y0 = -30, y1 = 30;  // (the origin, and room for its mark)
  auto take = [&](double x, double y, double r = 0) {
    x0 = std::min(x0, x - r), x1 = std::max(x1, x + r), y0 = std::min(y0, y - r), y1 = std::max(y1, y + r);
  };
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (stowed[i]) continue;
    outlines[i] = outline(scene.objects[i]);
    if (outlines[i].circle) take(outlines[i].centre.x, outlines[i].centre.y, outlines[i].r);
    for (const P& p : outlines[i].poly) take(p.x, p.y);
  }
  for (const Arm& a : arms) take(a.xyz.x, a.xyz.y, std::max(a.footprint_mm, 45.0));
  for (const CellDevice& d : devices) {
    if (d.kind == CellDevice::Kind::kBarrier) take(d.from.x, d.from.y, 8), take(d.to.x, d.to.y, 8);
    if (d.kind == CellDevice::Kind::kFeeder) take(d.at.x, d.at.y, 20);
    if (d.kind == CellDevice::Kind::kSwitch) take(d.at.x, d.at.y, std::hypot(d.size.x, d.size.y) / 2 + 8);
  }
  const double m = 20, foot = 24;  // margins, mm; the foot holds the scale bar and the title
  const double W = std::ceil(x1 - x0 + 2 * m), H = std::ceil(y1 - y0 + 2 * m + foot);
  auto X = [&](double x) { return num(x - x0 + m); };
  auto Y = [&](double y) { return num(y1 - y + m); };  // (the table's y up the sheet)
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(W) << "mm\" height=\"" << num(H) << "mm\" viewBox=\"0 0 "
    << num(W) << " " << num(H) << "\" font-family=\"sans-serif\">\n"
    << "<title>" << xml_text(title) << ": the table's mat, 1:1 in mm</title>\n"
    << "<rect x=\"0.5\" y=\"0.5\" width=\"" << num(W - 1) << "\" height=\"" << num(H - 1) << "\" fill=\"white\" stroke=\"#888\" stroke-width=\"0.3\"/>\n";
  // the grid every 50 mm, and the axes through the arm's (or the table's) origin
  s << "<g stroke=\"#ddd\" stroke-width=\"0.2\">\n";
  for (double x = std::ceil(x0 / 50) * 50; x <= x1; x += 50)
    s << "<line x1=\"" << X(x) << "\" y1=\"" << num(m) << "\" x2=\"" << X(x) << "\" y2=\"" << num(y1 - y0 + m) << "\"/>\n";
  for (double y = std::ceil(y0 / 50) * 50; y <= y1; y += 50)
    s << "<line x1=\"" << num(m) << "\" y1=\"" << Y(y) << "\" x2=\"" << num(x1 - x0 + m) << "\" y2=\"" << Y(y) << "\"/>\n";
  s << "</g>\n<g stroke=\"#999\" stroke-width=\"0.3\">\n"
    << "<line x1=\"" << X(x0) << "\" y1=\"" << Y(0) << "\" x2=\"" << X(x1) << "\" y2=\"" << Y(0) << "\"/>\n"
    << "<line x1=\"" << X(0) << "\" y1=\"" << Y(y0) << "\" x2=\"" << X(0) << "\" y2=\"" << Y(y1) << "\"/>\n</g>\n"
    << "<text x=\"" << num(x1 - x0 + m - 2) << "\" y=\"" << num(y1 + m - 1.5) << "\" font-size=\"4\" text-anchor=\"end\" fill=\"#777\">x</text>\n"
    << "<text x=\"" << num(-x0 + m + 1.5) << "\" y=\"" << num(m + 4) << "\" font-size=\"4\" fill=\"#777\">y</text>\n";
  // the objects: static solid, movable dashed; a belt with its way
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (stowed[i]) continue;
    const SceneObject& o = scene.objects[i];
    const Outline& ol = outlines[i];
    const std::string style = std::string(" fill=\"none\" stroke=\"#222\" stroke-width=\"0.4\"") +
                              (o.movable ? " stroke-dasharray=\"2 1.2\"" : "");
    if (ol.circle) {
      s << "<circle cx=\"" << X(ol.centre.x) << "\" cy=\"" << Y(ol.centre.y) << "\" r=\"" << num(ol.r) << "\"" << style << "/>\n";
    } else {
      s << "<polygon points=\"";
      for (const P& p : ol.poly) s << X(p.x) << "," << Y(p.y) << " ";
      s << "\"" << style << "/>\n";
    }
    std::string label = o.name;
    if (o.belt != 0) {
      const Mat3<double> R = o.rotation();
      const double sign = o.belt > 0 ? 1 : -1, len = std::min(60.0, o.size[0] / 3);
      const double dx = R.m[0][0] * sign, dy = R.m[1][0] * sign, n = std::hypot(dx, dy);
      if (n > 1e-9) {
        const P a{o.xyz.x - dx / n * len / 2, o.xyz.y - dy / n * len / 2}, b{o.xyz.x + dx / n * len / 2, o.xyz.y + dy / n * len / 2};
        const P l{b.x - (dx - dy) / n * 5, b.y - (dy + dx) / n * 5}, r{b.x - (dx + dy) / n * 5, b.y - (dy - dx) / n * 5};
        s << "<polyline points=\"" << X(a.x) << "," << Y(a.y) << " " << X(b.x) << "," << Y(b.y) << " " << X(l.x) << "," << Y(l.y)
          << " " << X(b.x) << "," << Y(b.y) << " " << X(r.x) << "," << Y(r.y) << "\" fill=\"none\" stroke=\"#555\" stroke-width=\"0.5\"/>\n";
      }
      label += " (belt, " + num(std::fabs(o.belt)) + " mm/s)";
    }
    s << "<text x=\"" << X(ol.centre.x) << "\" y=\"" << num(y1 - ol.centre.y + m + 1.3) << "\" font-size=\"3.5\" text-anchor=\"middle\" fill=\"#222\">"
      << xml_text(label) << "</text>\n";
  }
  // each arm's reach on the table: its tool's point touches the table nowhere outside (a bound,
  // so not everywhere inside); drawn under the rest, not widening the sheet
  for (const Arm& a : arms)
    if (a.reach_mm > 0)
      s << "<circle cx=\"" << X(a.reach_centre.x) << "\" cy=\"" << Y(a.reach_centre.y) << "\" r=\"" << num(a.reach_mm)
        << "\" fill=\"#3d5a80\" fill-opacity=\"0.04\" stroke=\"#3d5a80\" stroke-width=\"0.3\" stroke-dasharray=\"4 2\"/>\n";
  // the arms: each base's footprint, and which way it faces (its x)
  for (const Arm& a : arms) {
    const double r = std::max(a.footprint_mm, 20.0), c = std::cos(a.yaw_deg * M_PI / 180), sn = std::sin(a.yaw_deg * M_PI / 180);
    s << "<circle cx=\"" << X(a.xyz.x) << "\" cy=\"" << Y(a.xyz.y) << "\" r=\"" << num(r)
      << "\" fill=\"#3d5a80\" fill-opacity=\"0.12\" stroke=\"#3d5a80\" stroke-width=\"0.5\"/>\n"
      << "<line x1=\"" << X(a.xyz.x) << "\" y1=\"" << Y(a.xyz.y) << "\" x2=\"" << X(a.xyz.x + c * (r + 15)) << "\" y2=\""
      << Y(a.xyz.y + sn * (r + 15)) << "\" stroke=\"#3d5a80\" stroke-width=\"0.6\"/>\n"
      << "<text x=\"" << X(a.xyz.x) << "\" y=\"" << Y(a.xyz.y - r - 5) << "\" font-size=\"4\" text-anchor=\"middle\" fill=\"#3d5a80\">"
      << xml_text(a.name) << "</text>\n";
    if (a.reach_mm > 0)
      s << "<text x=\"" << X(a.xyz.x) << "\" y=\"" << Y(a.xyz.y - r - 10) << "\" font-size=\"3\" text-anchor=\"middle\" fill=\"#3d5a80\">"
        << "its reach on the table: inside the dashed circle</text>\n";
  }
  if (arms.empty())
    s << "<circle cx=\"" << X(0) << "\" cy=\"" << Y(0) << "\" r=\"3\" fill=\"none\" stroke=\"#3d5a80\" stroke-width=\"0.5\"/>\n"
      << "<text x=\"" << X(0) << "\" y=\"" << Y(-9) << "\" font-size=\"3.5\" text-anchor=\"middle\" fill=\"#3d5a80\">the arm's base frame</text>\n";
  // the devices
  for (const CellDevice& d : devices) {
    if (d.kind == CellDevice::Kind::kBarrier) {
      s << "<line x1=\"" << X(d.from.x) << "\" y1=\"" << Y(d.from.y) << "\" x2=\"" << X(d.to.x) << "\" y2=\"" << Y(d.to.y)
        << "\" stroke=\"#d62828\" stroke-width=\"0.6\"/>\n";
      for (const Vec3<double>& e : {d.from, d.to})
        s << "<rect x=\"" << num(e.x - x0 + m - 4) << "\" y=\"" << num(y1 - e.y + m - 4) << "\" width=\"8\" height=\"8\" fill=\"#2b2d42\"/>\n";
      s << "<text x=\"" << X((d.from.x + d.to.x) / 2) << "\" y=\"" << Y((d.from.y + d.to.y) / 2 + 7) << "\" font-size=\"3.5\" text-anchor=\"middle\" fill=\"#d62828\">"
        << xml_text(d.name) << ": light barrier, " << num(d.from.z) << " mm up</text>\n";
    } else if (d.kind == CellDevice::Kind::kSwitch) {
      s << "<rect x=\"" << num(d.at.x - d.size.x / 2 - x0 + m) << "\" y=\"" << num(y1 - d.at.y - d.size.y / 2 + m) << "\" width=\""
        << num(d.size.x) << "\" height=\"" << num(d.size.y) << "\" fill=\"#2a9d8f\" fill-opacity=\"0.25\" stroke=\"#2a9d8f\" stroke-width=\"0.5\"/>\n"
        << "<text x=\"" << X(d.at.x) << "\" y=\"" << Y(d.at.y - d.size.y / 2 - 5) << "\" font-size=\"3.5\" text-anchor=\"middle\" fill=\"#2a9d8f\">"
        << xml_text(d.name) << ": switch, " << num(d.at.z - d.size.z / 2) << " to " << num(d.at.z + d.size.z / 2) << " mm up</text>\n";
    } else if (d.kind == CellDevice::Kind::kFeeder) {
      s << "<path d=\"M" << num(d.at.x - x0 + m - 8) << "," << Y(d.at.y) << " h16 M" << X(d.at.x) << "," << num(y1 - d.at.y + m - 8)
        << " v16\" stroke=\"#b58100\" stroke-width=\"0.6\"/>\n"
        << "<text x=\"" << X(d.at.x) << "\" y=\"" << Y(d.at.y + 12) << "\" font-size=\"3.5\" text-anchor=\"middle\" fill=\"#b58100\">"
        << xml_text(d.name) << ": the feeder's " << d.magazine.size() << " come out here</text>\n";
    }
  }
  // the scale bar and the title
  const double by = H - foot / 2;
  s << "<path d=\"M" << num(m) << "," << num(by) << " h100 M" << num(m) << "," << num(by - 2) << " v4 M" << num(m + 100) << ","
    << num(by - 2) << " v4\" stroke=\"#000\" stroke-width=\"0.5\"/>\n"
    << "<text x=\"" << num(m + 50) << "\" y=\"" << num(by - 3) << "\" font-size=\"3.5\" text-anchor=\"middle\">100 mm: measure it on the print</text>\n"
    << "<text x=\"" << num(m + 108) << "\" y=\"" << num(by + 1.3) << "\" font-size=\"3.5\">" << xml_text(title)
    << ": print at 100 % (actual size), grid 50 mm</text>\n"
    << "</svg>\n";
  return s.str();
}

}  // namespace

std::string mat_svg(const Cell& cell) {
  std::vector<Arm> arms;
  for (const CellArm& a : cell.arms) {
    const InverseKinematics ik(a.robot);
    const Vec3<double> c = a.T_world_base() * ik.reach_centre();
    const double r = ik.reach_bound(), h = std::max(0.0, r * r - c.z * c.z);
    arms.push_back({a.name, a.xyz, a.yaw_deg, a.footprint_mm, {c.x, c.y}, std::sqrt(h)});
  }
  return drawing(cell.name, cell.scene, arms, cell.devices);
}

std::string mat_svg(const Scene& scene) { return drawing(scene.name.empty() ? "scene" : scene.name, scene, {}, {}); }

}  // namespace articula::host
