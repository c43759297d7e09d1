// host/lib/draw.h - drawing and writing with a pen held in the gripper: strokes (polylines on
// the paper, mm) from text in a single-stroke Hershey font (Debian's hershey-fonts-data, read
// here and nowhere else) or from a first lesson's shapes; placed on the paper (width, centre,
// rotation); checked against the arm's reach at the paper's height, with which way and how
// far to move a drawing that does not fit; ordered to cut the pen's travel; and written as a
// protocol program: `T` straight lines with the pen down, the pen lifted between strokes.
//
// The pen hangs straight down from the tool point (the MK2's gripper stays level): its tip is
// the tool point less the pen's length in z. Paper coordinates are the table's x and y, mm.
#ifndef ARTICULA_HOST_DRAW_H
#define ARTICULA_HOST_DRAW_H

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "ik.h"
#include "robot.h"

namespace articula::host {

struct Point2 {
  double x = 0, y = 0;
};
using Stroke = std::vector<Point2>;  // the pen down from the first point to the last

// ---- the font

// A Hershey font in James Hurt's format (.jhf): the glyphs of the characters from ' ' to '~'
// in file order, each its strokes (y up) and its left and right edges, in font units.
struct HersheyGlyph {
  std::vector<Stroke> strokes;
  double left = 0, right = 0;
};
struct HersheyFont {
  std::string source;
  std::vector<HersheyGlyph> glyphs;  // [c - 32]; text takes ' ' to '~'
  double cap_height = 1;             // the height of 'H', font units
};

// Where the font comes from: Debian's hershey-fonts-data (futural: Roman simplex).
std::string default_font_path();
// Reads a .jhf file; throws std::invalid_argument naming the file and line of a bad glyph.
HersheyFont parse_hershey(const std::string& text, const std::string& name);
HersheyFont load_hershey(const std::string& path);

// Text as strokes, its capital letters `cap_height_mm` high, lines `line_spacing` capital
// heights apart ('\n' starts a line), the first line's baseline at y 0, left aligned.
// Throws std::invalid_argument naming every character the font lacks.
std::vector<Stroke> text_strokes(const HersheyFont& font, const std::string& text, double cap_height_mm = 10,
                                 double line_spacing = 1.6);

// A first lesson's shapes, 1 wide, centred on (0, 0): "square", "circle", "star" (five points).
// Throws std::invalid_argument for another name.
std::vector<Stroke> shape_strokes(const std::string& shape);

// Freehand strokes (a finger's or a mouse's points) smoothed: each point the mean of it and
// its two neighbours either side (the ends kept), then points dropped while the stroke stays
// within `tolerance_mm` of them (Douglas-Peucker).
std::vector<Stroke> smooth_strokes(const std::vector<Stroke>& strokes, double tolerance_mm = 0.3);

// ---- placing, reaching, ordering, the program

struct Bounds {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  double width() const { return max_x - min_x; }
  double height() const { return max_y - min_y; }
};
Bounds bounds_of(const std::vector<Stroke>& strokes);

// Strokes scaled to `width_mm` wide, turned by `rotation_deg` about their centre, the centre
// of their bounds at (x, y) on the table.
std::vector<Stroke> place_strokes(const std::vector<Stroke>& strokes, double width_mm, double x, double y,
                                  double rotation_deg = 0);

// The pen's settings: each one's key (in a request; the CLI's option is it with '-' for '_'),
// its default and the values it takes, here and nowhere else. The CLI's options and help, the
// requests of Python and the page, and the page's boxes (the engine hands the page this table)
// all read them. The paper's height z takes any number.
struct PenField {
  const char* key;
  double fallback;
  double min, max;  // the values it takes; above min only when min_excluded
  bool min_excluded;
  const char* unit;
  const char* what;
};
inline constexpr PenField kPenFields[] = {
    {"pen", 0, 0, 1000, false, "mm", "the pen's tip below the tool point"},
    {"lift", 10, 0, 1000, true, "mm", "how far the pen lifts above the paper between strokes"},
    {"speed", 20, 0, 1000, true, "mm/s", "the speed along the strokes, the pen down"},
    {"travel_speed", 40, 0, 1000, true, "mm/s", "the speed between strokes, the pen up"},
};
enum PenFieldId { kPenLength, kPenLift, kPenSpeed, kPenTravelSpeed };

struct PenSettings {
  double paper_z = 0;                                        // the paper's height above the base frame's origin, mm
  double pen_mm = kPenFields[kPenLength].fallback;           // the pen's tip below the tool point, mm
  double lift_mm = kPenFields[kPenLift].fallback;            // above the paper between strokes, mm
  double speed = kPenFields[kPenSpeed].fallback;             // drawing, mm/s
  double travel_speed = kPenFields[kPenTravelSpeed].fallback;  // between strokes, pen up, mm/s
};

// Whether `v` is a value field `f` takes; the message when not ("lift must be more than 0 and
// at most 1000 mm, not 0"), "" when it is.
std::string pen_value_problem(const PenField& f, double v);
// Throws std::invalid_argument naming the first setting out of its range (and a z that is no
// number).
void check_pen(const PenSettings& pen);

// Whether the pen reaches every point of the drawing (its strokes at the paper, sampled every
// 2 mm, and the lifted ends above them); if not, the points it cannot reach, and the shortest
// move of the whole drawing found (5 mm steps, eight directions, up to 300 mm) that makes it
// fit, in words: "move it 35 mm toward +x (away from the base)", or that none does at this size.
struct ReachCheck {
  bool fits = true;
  int points = 0;                    // points checked
  std::vector<Point2> unreachable;   // of them, the pen cannot reach these
  bool movable = false;              // a move was found
  double move_x = 0, move_y = 0;     // that move, mm
  std::string advice;                // what to do, "" when it fits
};
ReachCheck check_reach(const Robot& robot, const InverseKinematics& ik, const std::vector<Stroke>& strokes,
                       const PenSettings& pen);
// The same question answered yes or no, at the first point it cannot reach (no advice).
bool reaches_all(const Robot& robot, const InverseKinematics& ik, const std::vector<Stroke>& strokes,
                 const PenSettings& pen);

// Where on an area of the table (a sheet of paper) the pen reaches the paper: the centre of
// every cell of `cell_mm`, row after row from min_x, each row from min_y; 1 where it reaches.
// The studio shades it: the arm's workspace at the paper's height.
struct ReachMap {
  Bounds area;
  double cell_mm = 5;
  int rows = 0, cols = 0;       // rows along x, columns along y
  std::vector<uint8_t> reached;  // rows * cols
};
ReachMap reach_map(const Robot& robot, const InverseKinematics& ik, const PenSettings& pen, const Bounds& area,
                   double cell_mm);
// {area [min_x, min_y, max_x, max_y] | paper (A4, A5, Letter), at [x, y] its centre, landscape;
// cell, z, pen} -> {rows, cols, cell, area, reached "0110..."}: as the bindings ask; at most
// 20,000 cells. A sheet lies portrait for a student at +x (its height along x) unless landscape.
nlohmann::json reach_map_json(const Robot& robot, const InverseKinematics& ik, const nlohmann::json& request);

// The strokes in a drawing order: each next the nearest end to where the pen is (a stroke is
// reversed when its last point is nearer), from `start`. Points closer than 0.01 mm to the one
// before are dropped, and strokes left with one point become a dot (the pen down and up).
std::vector<Stroke> order_strokes(std::vector<Stroke> strokes, Point2 start);
// The pen's travel with the pen up, mm, along strokes drawn in this order from `start`.
double travel_mm(const std::vector<Stroke>& strokes, Point2 start);

// The pen's path along strokes in their order, the one writer of it (drawing_program and the
// Blocks' write and shape): to above the first stroke (a point to reach, `P`), then per stroke
// the pen down, along it and up again (lines at `speed`), and to the next at the lifted height
// (a line at `travel_speed`).
struct PenMove {
  bool reach;          // the first: to above the first stroke from wherever the arm is (P, not T)
  double x, y, z;      // the tool point, mm
  double speed;        // a line's, mm/s (0 for the reach)
  bool ink;            // along a stroke with the pen down
};
std::vector<PenMove> pen_moves(const std::vector<Stroke>& strokes, const PenSettings& pen);

// The protocol program that draws the strokes in their order (pen_moves): to above the first stroke
// (`P`), then per stroke the pen down, along it and up again (`T` at `speed`), and to the next
// at the lifted height (`T` at `travel_speed`). `title` becomes its first comment.
std::string drawing_program(const Robot& robot, const std::vector<Stroke>& strokes, const PenSettings& pen,
                            const std::string& title);

// The program and, per line (1-based), whether it draws (the pen down along a stroke).
std::string drawing_program(const Robot& robot, const std::vector<Stroke>& strokes, const PenSettings& pen,
                            const std::string& title, std::vector<int>* ink_lines);

// ---- the whole of it, as the CLI, Python and the page ask for it

struct DrawRequest {
  std::string text;          // text to write ('\n' starts a line), or
  std::string shape;         // a shape: square, circle, star, or
  std::string svg;           // an SVG file's text (svg.h), named svg_name, or
  std::vector<Stroke> freehand;  // strokes drawn by hand on the table (mm), smoothed, not placed (exactly one of the four)
  std::string svg_name = "drawing.svg";
  double tolerance_mm = 0.1;  // an SVG's curves flattened within this of the curve, on the paper
  std::string font_path;     // "" : default_font_path()
  double line_spacing = 1.6;
  double width_mm = 0;       // the drawing's width on the paper
  double x = 0, y = 0;       // its centre on the table
  double rotation_deg = 90;  // 90: upright for someone at +x facing the arm
  std::string paper;         // "A4", "A5", "Letter" or "": the drawing must fit on it
  int microsteps = 0;        // the prediction's motors in full (1) or half (2) steps; 0: the robot's
  PenSettings pen;
};

// A sheet's size, mm (portrait): A4, A5, Letter; false for another name.
bool paper_size(const std::string& name, double& width_mm, double& height_mm);

// A copy of the robot whose motors make `microsteps` steps a full step (1 full steps, 2 half
// steps: the Nano's L298N table has both): the same drawing predicted both ways shows what
// half steps do to the stairs. Throws std::invalid_argument for another count or no motors.
Robot with_microsteps(const Robot& robot, int microsteps);

struct Drawing {
  std::string what;              // "\"Hello\"", "a square"
  double width_mm = 0, height_mm = 0;  // its own width and height (before it is turned)
  std::vector<Stroke> strokes;   // placed, in drawing order (when it fits; else as laid out)
  Bounds bounds;
  ReachCheck reach;
  Point2 start{0, 0};            // where the pen starts: the tool at power-up (motors at zero)
  double travel_mm = 0;          // pen up between strokes, in this order
  double travel_unordered_mm = 0;  // the same in the order laid out
  std::string program;           // "" when it does not fit
  std::vector<int> ink_lines;    // the program's lines (1-based) that draw: the pen down along a stroke
};

// Strokes from the text, the shape or the SVG, placed, checked, ordered, and the program when
// the pen reaches all of it. Throws std::invalid_argument for a request that cannot be drawn
// at all (not exactly one of text, shape and SVG, a character the font lacks, a width <= 0, a
// font unread), SvgError (svg.h) for an SVG refused.
Drawing make_drawing(const Robot& robot, const InverseKinematics& ik, const DrawRequest& request);

// {strokes [[[x, y], ...], ...], points}: ink_of_tool_path of the tool's positions, as the
// bindings answer a virtual Nano's steps ({steps: rows of step counts, z, pen, lift}, through
// tool_from_steps) or the physics' tool ({tool: x, y, z after x, y, z, ...}).
nlohmann::json ink_json(const Robot& robot, const nlohmann::json& request);

// {what, bounds {min_x, min_y, max_x, max_y}, strokes [[[x, y], ...], ...], reach {fits,
// points, unreachable [[x, y]...], movable, move [dx, dy], advice}, start, travel_mm,
// travel_unordered_mm, program}: how the bindings hand a drawing out.
nlohmann::json drawing_json(const Drawing& d);

// ---- ink: where the pen touches the paper

// The pen is on the paper while its tip is lower than half the lift above it: the pen holder's
// spring takes up the steps' error in height (a step of the MK2's shoulder moves the tip about
// a millimetre), and a lifted pen is a whole lift above. One rule for the prediction, the
// virtual Nano's steps and the physics.
bool pen_on_paper(const Vec3<double>& tool, const PenSettings& pen);

// The ink the tool's positions leave, in order (every step): a polyline on the paper for each
// time the pen is down, its first point where it came down.
std::vector<Stroke> ink_of_tool_path(const std::vector<Vec3<double>>& tool, const PenSettings& pen);

// The tool's positions (mm) from motor step counts: `steps` holds a row of each motor's count
// (from power-up, as the status report's S) per moment, row after row.
// Throws std::invalid_argument when its length is not a whole number of rows.
std::vector<Vec3<double>> tool_from_steps(const Robot& robot, const std::vector<int32_t>& steps);

// The line the arm will draw: the pen's tip at every step of the prediction (a prediction
// made with its path kept, predict.h) where the pen is on the paper (pen_on_paper), a polyline
// each time it comes down, on the paper (x, y mm); and the worst distance of the tip from the
// nearest ideal stroke, where and on which line.
struct PredictedInk {
  std::vector<Stroke> strokes;
  double worst_mm = 0;
  Point2 worst_at{0, 0};
  int worst_line = 0;
  size_t steps = 0;  // tip positions drawn
};
struct Prediction;
PredictedInk predicted_ink(const Drawing& d, const Prediction& prediction, const PenSettings& pen);

// ---- checking a drawing against a target (the studio's drawing exercises)

// The ink a program leaves: its prediction's every step (predict.h, path kept) through
// pen_on_paper. Throws std::invalid_argument for a program that does not parse.
std::vector<Stroke> program_ink(const Robot& robot, const std::string& program, const std::string& name,
                                const PenSettings& pen);

// How far ink is from a target, both ways: the farthest point of ink from the target's strokes
// (ink where it should not be) and the farthest point of the target (sampled every mm) from
// the ink (the target not covered). Met when both are within the tolerance.
struct DrawingCheck {
  bool met = false;
  double ink_off_mm = 0, uncovered_mm = 0;
  Point2 ink_off_at{0, 0}, uncovered_at{0, 0};
  size_t ink_points = 0;
  std::string says;  // in words: what is met, or which way it is not and where
};
DrawingCheck check_drawing(const std::vector<Stroke>& target, const std::vector<Stroke>& ink, double tolerance_mm);

// {program, name, target {text | shape, width, at, rotate ...: a drawing request}, z, pen, lift,
// tolerance} -> {met, ink_off_mm, uncovered_mm, ink_off_at, uncovered_at, ink_points, says,
// target (its strokes), ink (the program's)}: as the bindings ask.
nlohmann::json drawing_check_json(const Robot& robot, const InverseKinematics& ik, const nlohmann::json& request);
// kPenFields: [{key, default, min, max, min_excluded, unit, what}, ...] (the page's boxes).
nlohmann::json pen_fields_json();

// The drawing seen from above as SVG, the ideal strokes and the predicted ink as two layers
// (groups "ideal" and "predicted"), the worst distance marked: for someone at +x facing the
// arm, the table's +y to the right and +x down.
std::string drawing_svg(const Drawing& d, const PredictedInk& ink, const std::string& title);
// What the bindings answer: drawing_json, and when the pen reaches it on a robot with motors,
// "ink": the line the arm will draw ({strokes, worst_mm, worst_at [x, y], worst_line, steps},
// predicted_ink) and "seconds", the prediction's duration. `svg`: also the drawing as SVG.
nlohmann::json drawing_with_ink_json(const Robot& robot, const InverseKinematics& ik, const DrawRequest& request,
                                     bool svg = false);

// A request from JSON (the bindings): {text | shape | svg | strokes (freehand), width, at [x, y], z, pen, lift, speed,
// travel_speed, rotate, line_spacing, font}; unknown keys refused by name.
DrawRequest draw_request_from_json(const nlohmann::json& j);

}  // namespace articula::host

#endif  // ARTICULA_HOST_DRAW_H
