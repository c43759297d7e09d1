// host/physics/mat.h - the table's mat: a drawing from above, at 1:1 in millimetres, of a scene
// or a cell, for a class to print and lay the real parts on: each object's outline on the table
// (dashed: a movable one) and its name, each arm's base, which way it faces and its reach on the
// table (a bound: its tool touches the table nowhere outside it), each light
// barrier's beam, each belt's way, each feeder's outlet, a 50 mm grid, the axes, and a 100 mm
// scale bar to check the print's scale. `articula mat`, Python's Cell.mat_svg and Scene's, the
// studio's "Print the mat". Every name is written as text (escaped), never as markup.
#ifndef ARTICULA_PHYSICS_MAT_H
#define ARTICULA_PHYSICS_MAT_H

#include <string>

#include "cell_file.h"
#include "scene.h"

namespace articula::host {

// The mat as an SVG document (its width and height in mm: printed at 100 %, 1 mm is 1 mm).
std::string mat_svg(const Cell& cell);
// A scene alone: its arm's base frame at the origin is marked.
std::string mat_svg(const Scene& scene);

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_MAT_H
