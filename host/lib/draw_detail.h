// host/lib/draw_detail.h - what the drawing's parts (draw*.cpp) share and nothing else sees:
// its spacings and tolerances, plane distances, the font cache.
#ifndef ARTICULA_HOST_DRAW_DETAIL_H
#define ARTICULA_HOST_DRAW_DETAIL_H

#include <algorithm>
#include <cmath>
#include <string>

#include "draw.h"

namespace articula::host::draw_detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSampleMm = 2;      // the reach check's spacing along a stroke
constexpr double kMoveStepMm = 5;    // the reach check's search for a move that fits
constexpr double kMoveMaxMm = 300;
constexpr double kSameMm = 0.01;     // points closer than this are one
constexpr double kTieMm = 1e-6;      // the order's nearest ends: closer than this are a tie

inline double dist(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// The distance of p from the segment a-b.
inline double segment_distance(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

// The fonts read so far, by path and text: a file read again is parsed once (the page's engine
// and a Python session draw many times with the same font). draw_font.cpp.
const HersheyFont& cached_font(const std::string& path);

}  // namespace articula::host::draw_detail

#endif  // ARTICULA_HOST_DRAW_DETAIL_H
