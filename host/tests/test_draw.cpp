// Tests host/lib/draw.cpp: the Hershey font as Debian ships it, text and shapes as strokes,
// placing, the reach check and its advice, ordering, and the program the arm runs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <algorithm>
#include <functional>
#include <sstream>

#include "blocks.h"
#include "draw.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "test_robots.h"

using namespace articula::host;

namespace {
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
    for (size_t k = 0; k < s.size(); ++k) {
      double nearest = INFINITY;
      for (const Stroke& id : d.strokes)
        for (size_t i = 1; i < id.size(); ++i) {
          const double dx = id[i].x - id[i - 1].x, dy = id[i].y - id[i - 1].y, l2 = dx * dx + dy * dy;
          const double t = l2 > 0 ? std::clamp(((s[k].x - id[i - 1].x) * dx + (s[k].y - id[i - 1].y) * dy) / l2, 0.0, 1.0) : 0;
          nearest = std::min(nearest, std::hypot(s[k].x - id[i - 1].x - t * dx, s[k].y - id[i - 1].y - t * dy));
        }
      worst = std::max(worst, nearest);
    }
  EXPECT_NEAR(worst, ink.worst_mm, 1e-9);
  // a stroke of ink each time the pen comes down: one per stroke drawn (and per dot)
  EXPECT_EQ(ink.strokes.size(), d.strokes.size());
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

TEST(Ink, ThePenIsOnThePaperBelowHalfItsLift) {
  PenSettings pen;
  pen.paper_z = 10;
  pen.pen_mm = 100;
  pen.lift_mm = 10;
  EXPECT_TRUE(pen_on_paper({0, 0, 110}, pen));
  EXPECT_TRUE(pen_on_paper({0, 0, 114.9}, pen));  // a step's error in height: still drawing
  EXPECT_FALSE(pen_on_paper({0, 0, 115}, pen));
  EXPECT_FALSE(pen_on_paper({0, 0, 120}, pen));   // lifted
  const std::vector<articula::Vec3<double>> path = {{1, 0, 120}, {2, 0, 110}, {3, 0, 110}, {4, 0, 120}, {5, 0, 111}, {6, 0, 130}};
  const std::vector<Stroke> ink = ink_of_tool_path(path, pen);
  ASSERT_EQ(ink.size(), 2u);
  ASSERT_EQ(ink[0].size(), 2u);
  EXPECT_EQ(ink[0][0].x, 2);
  EXPECT_EQ(ink[0][1].x, 3);
  ASSERT_EQ(ink[1].size(), 1u);  // a dot
  EXPECT_EQ(ink[1][0].x, 5);
}

TEST(Ink, StepCountsGiveTheToolThePredictionGives) {
  DrawRequest req;
  req.shape = "square";
  req.width_mm = 30;
  req.x = 250;
  req.pen = pen120();
  const Drawing d = make_drawing(mk2(), mk2_ik(), req);
  ASSERT_TRUE(d.reach.fits) << d.reach.advice;
  const Prediction p = predict_program(mk2(), parse_program(d.program, "sq.arm", mk2()), {}, {}, true);
  std::vector<int32_t> rows;
  std::vector<articula::Vec3<double>> expected;
  for (const PredictRecord& r : p.records)
    if (r.reply == articula::kOk && !r.steps.empty()) {
      rows.insert(rows.end(), r.steps.begin(), r.steps.end());
      expected.push_back(r.tool_quantized);
    }
  const std::vector<articula::Vec3<double>> tool = tool_from_steps(mk2(), rows);
  ASSERT_EQ(tool.size(), expected.size());
  for (size_t i = 0; i < tool.size(); ++i) EXPECT_LT(articula::norm(tool[i] - expected[i]), 1e-9) << i;
  // as the bindings ask: rows of the wrong length, a count that is not whole, an unknown key
  const nlohmann::json ok = ink_json(mk2(), {{"steps", rows}, {"z", 0}, {"pen", 120}});
  EXPECT_GT(ok["points"].get<int>(), 0);
  EXPECT_THROW(ink_json(mk2(), {{"steps", {1, 2}}}), std::invalid_argument);
  EXPECT_THROW(ink_json(mk2(), {{"steps", {1.5, 2, 3}}}), std::invalid_argument);
  EXPECT_THROW(ink_json(mk2(), {{"steps", {1, 2, 3}}, {"colour", 1}}), std::invalid_argument);
  // the physics' tool positions: the same rule
  const nlohmann::json by_tool = ink_json(mk2(), {{"tool", {250, 0, 130, 250, 0, 120, 251, 0, 120.5, 252, 0, 131}}, {"pen", 120}});
  EXPECT_EQ(by_tool["strokes"], nlohmann::json::parse("[[[250, 0], [251, 0]]]"));
  EXPECT_THROW(ink_json(mk2(), {{"tool", {1, 2}}}), std::invalid_argument);
  EXPECT_THROW(ink_json(mk2(), {{"tool", {1, 2, 3}}, {"steps", {1, 2, 3}}}), std::invalid_argument);
}

TEST(Reach, TheMapOfASheetAgreesWithTheCheck) {
  // an A5 sheet in front of the MK2, its near edge close to the base: the pen reaches its middle
  // and not the corner nearest the base (the arm cannot fold that far)
  const Bounds sheet{120, -74, 330, 74};
  const ReachMap m = reach_map(mk2(), mk2_ik(), pen120(), sheet, 10);
  EXPECT_EQ(m.rows, 21);
  EXPECT_EQ(m.cols, 15);
  const size_t reached = size_t(std::count(m.reached.begin(), m.reached.end(), 1));
  EXPECT_GT(reached, m.reached.size() / 3);
  EXPECT_LT(reached, m.reached.size());
  // every cell says what check_reach says of a dot at its centre (the lifted pen aside)
  for (int r = 0; r < m.rows; r += 4)
    for (int c = 0; c < m.cols; c += 3) {
      const Point2 p{sheet.min_x + (r + 0.5) * 10, sheet.min_y + (c + 0.5) * 10};
      PenSettings flat = pen120();
      flat.lift_mm = 0;
      const ReachCheck rc = check_reach(mk2(), mk2_ik(), {{p}}, flat);
      EXPECT_EQ(m.reached[size_t(r * m.cols + c)] == 1, rc.fits) << p.x << ", " << p.y;
    }
  EXPECT_THROW(reach_map_json(mk2(), mk2_ik(), {{"area", {0, 0, 1000, 1000}}, {"cell", 1}}), std::invalid_argument);
  EXPECT_THROW(reach_map_json(mk2(), mk2_ik(), {{"area", {0, 0}}}), std::invalid_argument);
  const nlohmann::json j = reach_map_json(mk2(), mk2_ik(), {{"area", {120, -74, 330, 74}}, {"cell", 10}, {"pen", 120}});
  EXPECT_EQ(j["reached"].get<std::string>().size(), m.reached.size());
  // a sheet by its name and centre: A5 portrait, its 210 mm along x
  const nlohmann::json a5 = reach_map_json(mk2(), mk2_ik(), {{"paper", "A5"}, {"at", {225, 0}}, {"cell", 10}, {"pen", 120}});
  EXPECT_EQ(a5["area"], nlohmann::json({120, -74, 330, 74}));
  EXPECT_EQ(a5["reached"], j["reached"]);
  const nlohmann::json wide = reach_map_json(mk2(), mk2_ik(), {{"paper", "A5"}, {"at", {225, 0}}, {"landscape", true}, {"cell", 10}});
  EXPECT_EQ(wide["area"], nlohmann::json({151, -105, 299, 105}));
  EXPECT_THROW(reach_map_json(mk2(), mk2_ik(), {{"paper", "A3"}, {"at", {225, 0}}}), std::invalid_argument);
}

TEST(Freehand, AShakyLineIsSmoothedAndDrawnWhereItWasDrawn) {
  // a finger's line across the paper, shaking 0.4 mm either side of y = 0
  std::vector<Point2> shaky;
  for (int i = 0; i <= 60; ++i) shaky.push_back({230 + i * 0.5, (i % 2 ? 0.4 : -0.4)});
  const std::vector<Stroke> smooth = smooth_strokes({shaky}, 0.3);
  ASSERT_EQ(smooth.size(), 1u);
  EXPECT_LT(smooth[0].size(), 10u);  // a straight line needs few points
  EXPECT_EQ(smooth[0].front().x, shaky.front().x);
  EXPECT_EQ(smooth[0].back().x, shaky.back().x);
  for (const Point2& p : smooth[0]) EXPECT_LT(std::fabs(p.y), 0.41);
  // through the bindings' request: the strokes are not moved or scaled
  const nlohmann::json strokes = {{{230, 0}, {240, 5}, {250, 0}}, {{260, -5}, {260, 5}}};
  const Drawing d = make_drawing(mk2(), mk2_ik(), draw_request_from_json({{"strokes", strokes}, {"pen", 120}}));
  ASSERT_TRUE(d.reach.fits) << d.reach.advice;
  EXPECT_EQ(d.what, "a drawing by hand");
  EXPECT_NEAR(d.bounds.min_x, 230, 1e-9);
  EXPECT_NEAR(d.bounds.max_x, 260, 1e-9);
  EXPECT_NEAR(d.bounds.min_y, -5, 1e-9);
  EXPECT_FALSE(d.program.empty());
  try {
    draw_request_from_json({{"strokes", {{{230, 0}, {"a", 1}}}}});
    ADD_FAILURE() << "a point that is not a number was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("stroke 1"), std::string::npos) << e.what();
  }
}

TEST(Check, ASquareOf40mmIsMetAndAWrongOneIsNot) {
  const nlohmann::json target = {{"shape", "square"}, {"width", 40}, {"at", {250, 0}}};
  auto check = [&](const nlohmann::json& drawn) {
    nlohmann::json req = drawn;
    req["z"] = 0;
    req["pen"] = 120;
    const Drawing d = make_drawing(mk2(), mk2_ik(), draw_request_from_json(req));
    EXPECT_TRUE(d.reach.fits);
    return drawing_check_json(mk2(), mk2_ik(), {{"program", d.program}, {"target", target}, {"z", 0}, {"pen", 120}, {"tolerance", 3}});
  };
  const nlohmann::json right = check(target);
  EXPECT_TRUE(right["met"].get<bool>()) << right["says"];
  EXPECT_LT(right["ink_off_mm"].get<double>(), 2.0);
  EXPECT_LT(right["uncovered_mm"].get<double>(), 2.0);
  // 30 mm: its ink is 5 mm inside the target's sides
  const nlohmann::json small = check({{"shape", "square"}, {"width", 30}, {"at", {250, 0}}});
  EXPECT_FALSE(small["met"].get<bool>());
  EXPECT_NEAR(small["ink_off_mm"].get<double>(), 5, 1.5);
  EXPECT_NE(small["says"].get<std::string>().find("must be within 3 mm"), std::string::npos) << small["says"];
  // half of it: the ink is on the target, but does not cover it
  const nlohmann::json half = drawing_check_json(mk2(), mk2_ik(), {{"program", "P 230 -20 130\nT 230 -20 120 20\nT 270 -20 120 20\nT 270 20 120 20\nT 270 20 130 20\n"},
                                                                  {"target", target}, {"z", 0}, {"pen", 120}, {"tolerance", 3}});
  EXPECT_FALSE(half["met"].get<bool>());
  EXPECT_GT(half["uncovered_mm"].get<double>(), 20);
  EXPECT_NE(half["says"].get<std::string>().find("not drawn at"), std::string::npos) << half["says"];
  // no ink at all: said so
  const nlohmann::json none = drawing_check_json(mk2(), mk2_ik(), {{"program", "P 250 0 200\n"}, {"target", target}, {"pen", 120}, {"tolerance", 3}});
  EXPECT_FALSE(none["met"].get<bool>());
  EXPECT_NE(none["says"].get<std::string>().find("no ink"), std::string::npos);
  EXPECT_TRUE(none["uncovered_mm"].is_null());
  EXPECT_THROW(drawing_check_json(mk2(), mk2_ik(), {{"program", ""}, {"target", target}, {"tolerance", 0}}), std::invalid_argument);
}

TEST(Check, TheNearestSegmentIsFoundAsByLookingAtEvery) {
  // a scatter of strokes, and points inside, between and far outside them
  std::vector<Stroke> strokes;
  for (int i = 0; i < 40; ++i) {
    const double x = 200 + (i * 37 % 90), y = -40 + (i * 53 % 80);
    strokes.push_back({{x, y}, {x + (i % 7) - 3, y + (i % 5) * 2 - 4}});
    if (i % 9 == 0) strokes.push_back({{x + 5, y + 5}});  // a dot
  }
  for (int k = 0; k < 300; ++k) {
    const Point2 p{150 + (k * 31 % 250) * 0.9, -120 + (k * 17 % 240) * 1.1};
    double brute = INFINITY;
    for (const Stroke& s : strokes) {
      const std::vector<Stroke> one{s};
      brute = std::min(brute, check_drawing(one, {{p}}, 1e9).ink_off_mm);
    }
    EXPECT_NEAR(check_drawing(strokes, {{p}}, 1e9).ink_off_mm, brute, 1e-9) << p.x << ", " << p.y;
  }
}

// The pen's settings live in draw.h's table alone: what a request leaves out is its default,
// and every way in (make_drawing, the JSON requests, the Blocks' pen) refuses a value beyond its
// range by the setting's name and range.
TEST(PenSettings, DefaultsAndRangesComeFromTheOneTable) {
  const PenSettings none;
  EXPECT_EQ(none.pen_mm, kPenFields[kPenLength].fallback);
  EXPECT_EQ(none.lift_mm, kPenFields[kPenLift].fallback);
  EXPECT_EQ(none.speed, kPenFields[kPenSpeed].fallback);
  EXPECT_EQ(none.travel_speed, kPenFields[kPenTravelSpeed].fallback);
  const DrawRequest r = draw_request_from_json({{"shape", "square"}, {"width", 40}, {"at", {250, 0}}});
  EXPECT_EQ(r.pen.lift_mm, kPenFields[kPenLift].fallback);
  EXPECT_EQ(r.pen.travel_speed, kPenFields[kPenTravelSpeed].fallback);

  for (const PenField& f : kPenFields) {
    EXPECT_EQ(pen_value_problem(f, f.max), "") << f.key;
    EXPECT_EQ(pen_value_problem(f, f.min) == "", !f.min_excluded) << f.key;
    const std::string beyond = pen_value_problem(f, f.max + 1);
    EXPECT_NE(beyond.find(f.key), std::string::npos) << beyond;
    EXPECT_NE(beyond.find(protocol_number(f.max)), std::string::npos) << beyond;
    EXPECT_NE(pen_value_problem(f, std::nan("")), "") << f.key;
    nlohmann::json req = {{"shape", "square"}, {"width", 40}, {"at", {250, 0}}, {"pen", 120}};
    req[f.key] = f.max + 1;
    try {
      make_drawing(mk2(), mk2_ik(), draw_request_from_json(req));
      ADD_FAILURE() << f.key << " beyond its range was drawn";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), beyond);
    }
  }
  EXPECT_THROW(reach_map_json(mk2(), mk2_ik(), {{"paper", "A5"}, {"at", {225, 0}}, {"pen", 1001}}), std::invalid_argument);
  const nlohmann::json fields = pen_fields_json();
  ASSERT_EQ(fields.size(), std::size(kPenFields));
  EXPECT_EQ(fields[1]["key"], "lift");
  EXPECT_EQ(fields[1]["default"], kPenFields[kPenLift].fallback);
}

// The Blocks' write and shape walk the strokes as drawing_program does (pen_moves, the one
// writer): the same T lines, in the same order.
TEST(PenSettings, TheBlocksAndTheDrawingWriteThePenOnce) {
  PenSettings pen;
  pen.pen_mm = 120;
  const std::vector<Stroke> strokes = {{{240, -10}, {260, -10}, {260, 10}}, {{240, 10}}};
  const std::vector<PenMove> moves = pen_moves(strokes, pen);
  ASSERT_EQ(moves.size(), 1 + 2 + 2 + (1 + 1 + 0 + 1));
  EXPECT_TRUE(moves[0].reach);
  EXPECT_DOUBLE_EQ(moves[0].z, 130);
  EXPECT_DOUBLE_EQ(moves[1].z, 120);
  EXPECT_TRUE(moves[2].ink && moves[3].ink);
  EXPECT_DOUBLE_EQ(moves[5].speed, pen.travel_speed);
  const std::string program = drawing_program(mk2(), strokes, pen, "t");
  size_t lines = 0;
  for (char c : program) lines += c == '\n';
  EXPECT_EQ(lines, 2 + moves.size());
}
