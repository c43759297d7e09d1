// host/lib/svg.h - an SVG file's drawable geometry, for drawing with a pen (draw.h): paths
// (lines, curves, arcs), lines, polylines, polygons, rects, circles and ellipses, with their
// transforms and the viewBox, read by SVG++ over rapidxml_ns (Debian's libsvgpp-dev; here and
// nowhere else), then flattened to polylines within a chord tolerance.
//
// A file is untrusted input: nothing in it runs or is fetched. Refused, with the reason: more
// than 5 MB; not XML, or XML whose root is not <svg>; a DOCTYPE with declarations or an
// entity (an XML bomb's way in); a <script>, an event handler attribute (onload=...), or a
// reference to anything outside the file (href to another file or a URL); no drawable path;
// nothing that shows.
//
// What the file shows is drawn, and nothing else: a shape whose stroke and fill are both none,
// that is display:none, hidden, or transparent (opacity, stroke-opacity with no fill,
// fill-opacity with no stroke), on itself or a group around it, set by attribute, by its style
// attribute or by a <style> sheet's class rule, is left out (an icon set's invisible 24 x 24
// frame among them); so is what sits in <defs>, <symbol>, <clipPath>, <mask> and <marker>
// (<use> is not read: what only a <use> shows is not drawn). A filled shape without a stroke
// is drawn as its outline, as pen plotters draw it.
#ifndef ARTICULA_HOST_SVG_H
#define ARTICULA_HOST_SVG_H

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "draw.h"

namespace articula::host {

constexpr size_t kMaxSvgBytes = 5u * 1024 * 1024;

// A file that cannot be drawn: what() names the file and the problem.
class SvgError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A subpath: its start and cubic Bezier segments (a straight line is a cubic with its
// control points on it), in the SVG's user units after every transform and the viewBox, y up.
struct SvgPath {
  Point2 start;
  std::vector<std::array<Point2, 3>> cubics;  // control 1, control 2, end
  bool closed = false;
};
struct SvgDrawing {
  std::string source;
  std::vector<SvgPath> paths;
  Bounds bounds;  // of every point and control point
};

// Reads an SVG's text; `name` names it in messages. Throws SvgError.
SvgDrawing read_svg(const std::string& text, const std::string& name);
// Polylines within `tolerance` (user units) of the curves.
std::vector<Stroke> flatten_svg(const SvgDrawing& svg, double tolerance);

}  // namespace articula::host

#endif  // ARTICULA_HOST_SVG_H
