// Tests host/lib/draw.cpp: the Hershey font as Debian ships it, text and shapes as strokes,
// placing, the reach check and its advice, ordering, and the program the arm runs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <algorithm>
#include <functional>
#include <sstream>

#include "draw.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"

using namespace articula::host;

namespace {
const Robot& mk2() {
  static const Robot r = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  return r;
}
const InverseKinematics& mk2_ik() {
  static const InverseKinematics ik(mk2());
  return ik;
}
const HersheyFont& font() {
  static const HersheyFont f = load_hershey(default_font_path());  // scripts/bootstrap installs it
  return f;
}
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}
size_t points_of(const std::vector<Stroke>& s) {
  size_t n = 0;
  for (const Stroke& x : s) n += x.size();
  return n;
}
// The MK2 with a 120 mm pen reaches the table around (250, 0).
PenSettings pen120() {
  PenSettings p;
  p.paper_z = 0;
  p.pen_mm = 120;
  return p;
}
}  // namespace

TEST(Hershey, ReadsTheFontDebianShips) {
  const HersheyFont& f = font();
  ASSERT_EQ(f.glyphs.size(), 96u);  // ' ' to '~', and a filled block after them (DEL)
  // The 'H' of the file, "9G]KFK[ RYFY[ RKPYP": three strokes, from F (-12) to [ (9): 21 high
  const HersheyGlyph& h = f.glyphs['H' - 32];
  ASSERT_EQ(h.strokes.size(), 3u);
  EXPECT_EQ(f.cap_height, 21);
  EXPECT_EQ(h.left, 'G' - 'R');
  EXPECT_EQ(h.right, ']' - 'R');
  // its foot on the baseline, its top at the cap height, y up
  const Bounds b = bounds_of(h.strokes);
  EXPECT_EQ(b.min_y, 0);
  EXPECT_EQ(b.max_y, 21);
  EXPECT_TRUE(f.glyphs[0].strokes.empty());  // the space
}

TEST(Hershey, ABrokenFileIsNamedWithItsLine) {
  const std::string good = "12345  9G]KFK[ RYFY[ RKPYP\n";
  EXPECT_EQ(error_of([&] { parse_hershey(good + "12345 xx\n", "f.jhf"); }),
            "f.jhf:2: too short (a Hershey .jhf glyph)");
  EXPECT_EQ(error_of([&] { parse_hershey("12345 40G]KF\n", "f.jhf"); }),
            "f.jhf:1: fewer coordinates than its count, 40 (a Hershey .jhf glyph)");
  EXPECT_EQ(error_of([&] { parse_hershey(good, "f.jhf"); }),
            "f.jhf: 1 glyphs: a font for text has one for each character from ' ' to '~' (95)");
  EXPECT_EQ(error_of([] { load_hershey("/nonexistent.jhf"); }), "cannot read the font /nonexistent.jhf");
}

TEST(Text, CapitalsAsHighAsAskedAndLinesBelowEachOther) {
  const std::vector<Stroke> h = text_strokes(font(), "H", 10);
  const Bounds b = bounds_of(h);
  EXPECT_NEAR(b.height(), 10, 1e-12);
  EXPECT_NEAR(b.min_y, 0, 1e-12);
  // "Hi": the H's strokes and the i's, the i to the right of the H
  const std::vector<Stroke> hi = text_strokes(font(), "Hi", 10);
  EXPECT_EQ(hi.size(), h.size() + font().glyphs['i' - 32].strokes.size());
  EXPECT_GT(bounds_of({hi.back()}).min_x, b.max_x);
  // a second line 1.6 capital heights below
  const Bounds two = bounds_of(text_strokes(font(), "H\nH", 10));
  EXPECT_NEAR(two.min_y, -16, 1e-12);
  EXPECT_NEAR(two.width(), b.width(), 1e-12);
}

TEST(Text, EveryCharacterTheFontLacksIsNamed) {
  EXPECT_EQ(error_of([] { text_strokes(font(), "H\xC3\xA9llo \xE2\x98\xBA \xC3\xA9", 10); }),
            "the font (/usr/share/hershey-fonts/futural.jhf) has no '\xC3\xA9' (U+00E9), '\xE2\x98\xBA' (U+263A): it holds "
            "the characters from ' ' to '~' (ASCII)");
  EXPECT_EQ(error_of([] { text_strokes(font(), "a\tb", 10); }),
            "the font (/usr/share/hershey-fonts/futural.jhf) has no U+0009: it holds the characters from ' ' to '~' (ASCII)");
  EXPECT_EQ(error_of([] { text_strokes(font(), "a\x7F", 10); }),
            "the font (/usr/share/hershey-fonts/futural.jhf) has no U+007F: it holds the characters from ' ' to '~' (ASCII)");
  EXPECT_EQ(error_of([] { text_strokes(font(), "a", 0); }), "the text's height must be > 0 mm");
}

TEST(Shapes, ASquareACircleAndAStarCloseOnThemselves) {
  for (const char* name : {"square", "circle", "star"}) {
    const std::vector<Stroke> s = shape_strokes(name);
    ASSERT_EQ(s.size(), 1u) << name;
    EXPECT_NEAR(s[0].front().x, s[0].back().x, 1e-12) << name;
    EXPECT_NEAR(s[0].front().y, s[0].back().y, 1e-12) << name;
  }
  EXPECT_EQ(shape_strokes("star")[0].size(), 11u);  // five outer corners, five inner, closed
  EXPECT_EQ(error_of([] { shape_strokes("heart"); }), "no shape 'heart': square, circle or star");
}

TEST(Place, WidthCentreAndTurn) {
  const std::vector<Stroke> sq = place_strokes(shape_strokes("square"), 40, 250, 10);
  Bounds b = bounds_of(sq);
  EXPECT_NEAR(b.width(), 40, 1e-9);
  EXPECT_NEAR((b.min_x + b.max_x) / 2, 250, 1e-9);
  EXPECT_NEAR((b.min_y + b.max_y) / 2, 10, 1e-9);
  // a text 60 wide turned 90 degrees: 60 along y
  const std::vector<Stroke> t = place_strokes(text_strokes(font(), "Hello", 10), 60, 250, 0, 90);
  b = bounds_of(t);
  EXPECT_NEAR(b.height(), 60, 1e-9);
  EXPECT_LT(b.width(), 30);
  EXPECT_EQ(error_of([] { place_strokes(shape_strokes("square"), 0, 0, 0); }), "the drawing's width must be > 0 mm");
}

TEST(Reach, ADrawingThatFitsAndOneThatIsToldWhereToGo) {
  const PenSettings pen = pen120();
  const ReachCheck ok = check_reach(mk2(), mk2_ik(), place_strokes(shape_strokes("square"), 40, 260, 0), pen);
  EXPECT_TRUE(ok.fits) << ok.advice;
  EXPECT_GT(ok.points, 80);  // a 160 mm outline every 2 mm, and the lifted ends
  EXPECT_EQ(ok.advice, "");
  // too near the base: out of reach, and the move the check finds makes it fit
  const std::vector<Stroke> near = place_strokes(shape_strokes("square"), 40, 120, 0);
  const ReachCheck no = check_reach(mk2(), mk2_ik(), near, pen);
  ASSERT_FALSE(no.fits);
  ASSERT_TRUE(no.movable) << no.advice;
  EXPECT_GT(no.move_x, 0) << no.advice;  // away from the base
  EXPECT_NE(no.advice.find("mm toward +x (away from the base)"), std::string::npos) << no.advice;
  const ReachCheck moved = check_reach(mk2(), mk2_ik(), place_strokes(shape_strokes("square"), 40, 120 + no.move_x, no.move_y), pen);
  EXPECT_TRUE(moved.fits) << moved.advice;
  // and one move shorter by a step does not fit (the search finds the shortest it tries)
  const ReachCheck shorter =
      check_reach(mk2(), mk2_ik(), place_strokes(shape_strokes("square"), 40, 120 + no.move_x - 5, no.move_y), pen);
  EXPECT_FALSE(shorter.fits);
  // the paper below anything the pen reaches
  PenSettings low = pen;
  low.pen_mm = 0;
  const ReachCheck none = check_reach(mk2(), mk2_ik(), place_strokes(shape_strokes("square"), 40, 260, 0), low);
  EXPECT_FALSE(none.movable);
  EXPECT_NE(none.advice.find("the pen reaches none of the drawing's"), std::string::npos) << none.advice;
  // a drawing bigger than the arm's ring
  const ReachCheck big = check_reach(mk2(), mk2_ik(), place_strokes(shape_strokes("square"), 400, 260, 0), pen);
  EXPECT_FALSE(big.fits);
  EXPECT_FALSE(big.movable);
}

TEST(Order, TheNearestEndNextCutsTheTravel) {
  // four dashes along x, given far apart in order, the second and fourth backwards
  std::vector<Stroke> s = {{{0, 0}, {10, 0}}, {{50, 0}, {40, 0}}, {{20, 0}, {30, 0}}, {{70, 0}, {60, 0}}};
  const Point2 start{0, 0};
  const std::vector<Stroke> o = order_strokes(s, start);
  ASSERT_EQ(o.size(), 4u);
  EXPECT_EQ(o[1].front().x, 20);  // the nearest next
  EXPECT_EQ(o[2].front().x, 40);  // reversed: its end was nearer
  EXPECT_NEAR(travel_mm(o, start), 30, 1e-12);
  EXPECT_NEAR(travel_mm(s, start), 0 + 40 + 20 + 40, 1e-12);
  // the text: shorter than as laid out
  const std::vector<Stroke> t = place_strokes(text_strokes(font(), "Hello world", 10), 80, 260, 0, 90);
  EXPECT_LT(travel_mm(order_strokes(t, {260, 0}), {260, 0}), travel_mm(t, {260, 0}));
  EXPECT_EQ(points_of(order_strokes(t, {0, 0})), points_of(t));
}

TEST(Program, DrawsEachStrokePenDownAndTheArmTakesEveryLine) {
  const PenSettings pen = pen120();
  const std::vector<Stroke> s = order_strokes(place_strokes(text_strokes(font(), "Hi", 10), 30, 260, 0, 90), {260, 0});
  const std::string text = drawing_program(mk2(), s, pen, "Hi");
  std::istringstream in(text);
  std::string line;
  int down = 0, up = 0, p = 0;
  while (std::getline(in, line)) {
    if (line[0] == 'P') ++p;
    if (line[0] != 'T') continue;
    double x, y, z, v;
    ASSERT_EQ(std::sscanf(line.c_str(), "T %lf %lf %lf %lf", &x, &y, &z, &v), 4) << line;
    if (z == 120) ++down;
    else if (z == 130) ++up;
    else ADD_FAILURE() << "a line neither at the paper nor lifted: " << line;
  }
  EXPECT_EQ(p, 1);
  EXPECT_EQ(size_t(down), points_of(s));                 // every point, pen down
  EXPECT_EQ(size_t(up), 2 * s.size() - 1);               // each stroke lifted, and travels between
  const Program prog = parse_program(text, "hi.arm", mk2());
  const Prediction pred = predict_program(mk2(), prog);
  for (const PredictRecord& r : pred.records) EXPECT_EQ(r.reply, articula::kOk) << r.text;
}

TEST(Ink, ThePenAtEveryStepAndItsWorstDistanceFromTheDrawing) {
  DrawRequest req;
  req.text = "Hi<&>";
  req.width_mm = 40;
  req.x = 260;
  req.pen = pen120();
  const Drawing d = make_drawing(mk2(), mk2_ik(), req);
  ASSERT_TRUE(d.reach.fits) << d.reach.advice;
  ASSERT_FALSE(d.ink_lines.empty());
  const Prediction p = predict_program(mk2(), parse_program(d.program, "hi.arm", mk2()), {}, {}, true);
  const PredictedInk ink = predicted_ink(d, p, req.pen);
  EXPECT_GT(ink.steps, 20u);
  // the steps leave the pen off the ideal lines, by less than a few of the MK2's steps at the tool
  EXPECT_GT(ink.worst_mm, 0.05);
  EXPECT_LT(ink.worst_mm, 3.0);
  // the worst is the largest distance of any inked point from the nearest ideal stroke
  double worst = 0;
  for (const Stroke& s : ink.strokes)
    for (size_t k = 1; k < s.size(); ++k) {  // (the first point: where the pen came down)
      double nearest = INFINITY;
      for (const Stroke& id : d.strokes)
        for (size_t i = 1; i < id.size(); ++i) {
          const double dx = id[i].x - id[i - 1].x, dy = id[i].y - id[i - 1].y, l2 = dx * dx + dy * dy;
          const double t = l2 > 0 ? std::clamp(((s[k].x - id[i - 1].x) * dx + (s[k].y - id[i - 1].y) * dy) / l2, 0.0, 1.0) : 0;
          nearest = std::min(nearest, std::hypot(s[k].x - id[i - 1].x - t * dx, s[k].y - id[i - 1].y - t * dy));
        }
      worst = std::max(worst, nearest);
    }
  EXPECT_LE(worst, ink.worst_mm + 1e-9);  // against its own segment the distance is at least the nearest
  const std::string svg = drawing_svg(d, ink, d.what);
  EXPECT_NE(svg.find("<g id=\"ideal\""), std::string::npos);
  EXPECT_NE(svg.find("<g id=\"predicted\""), std::string::npos);
  EXPECT_NE(svg.find("<title>&quot;Hi&lt;&amp;&gt;&quot;</title>"), std::string::npos) << svg.substr(0, 400);
  EXPECT_EQ(svg.find("<&>"), std::string::npos);
}

TEST(Ink, HalfStepsHalveTheStairs) {
  DrawRequest req;
  req.shape = "circle";
  req.width_mm = 40;
  req.x = 260;
  req.pen = pen120();
  double worst[2] = {0, 0};
  size_t steps[2] = {0, 0};
  for (int m = 1; m <= 2; ++m) {
    const Robot r = with_microsteps(mk2(), m);
    const InverseKinematics ik(r);
    const Drawing d = make_drawing(r, ik, req);
    ASSERT_TRUE(d.reach.fits) << d.reach.advice;
    const PredictedInk ink = predicted_ink(d, predict_program(r, parse_program(d.program, "c.arm", r), {}, {}, true), req.pen);
    worst[m - 1] = ink.worst_mm;
    steps[m - 1] = ink.steps;
  }
  EXPECT_LT(worst[1], 0.75 * worst[0]);  // finer steps, smaller stairs
  EXPECT_GT(steps[1], steps[0] * 3 / 2);  // about twice the steps
  EXPECT_EQ(error_of([] { with_microsteps(mk2(), 4); }),
            "microsteps: 1 (full steps) or 2 (half steps), the two the Nano's L298N table makes");
}

TEST(Place, ADrawingBiggerThanThePaperIsRefused) {
  DrawRequest req;
  req.text = "Hello";
  req.width_mm = 300;
  req.x = 260;
  req.pen = pen120();
  req.paper = "A5";
  EXPECT_EQ(error_of([&] { make_drawing(mk2(), mk2_ik(), req); }),
            "the drawing, 300 x 92.647 mm, is bigger than A5 (148 x 210 mm): make it narrower");
  req.width_mm = 60;
  EXPECT_NO_THROW(make_drawing(mk2(), mk2_ik(), req));
  req.paper = "A3";
  EXPECT_EQ(error_of([&] { make_drawing(mk2(), mk2_ik(), req); }), "no paper 'A3': A4, A5 or Letter");
}
