// Tests host/lib/svg.cpp: every shape SVG draws, transforms and the viewBox, curves flattened
// within the tolerance, and a hostile file refused with its reason.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "svg.h"

using namespace articula::host;

namespace {
std::string svg(const std::string& body, const std::string& attrs = "") {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" " + attrs + ">" + body +
         "</svg>";
}
std::string refusal(const std::string& text) {
  try {
    read_svg(text, "t.svg");
  } catch (const SvgError& e) {
    return e.what();
  }
  return "no error";
}
std::string file(const std::string& path) {
  std::ifstream f(std::string(ARTICULA_SOURCE_DIR) + "/" + path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(Svg, EveryShapeWithItsTransformAndTheViewBoxYUp) {
  // viewBox 0 0 100 50 on 200 x 100: twice; the rect moved 5 right by its transform
  const SvgDrawing d = read_svg(svg("<rect x=\"10\" y=\"10\" width=\"20\" height=\"10\" transform=\"translate(5,0)\"/>",
                                    "width=\"200\" height=\"100\" viewBox=\"0 0 100 50\""),
                                "t.svg");
  ASSERT_EQ(d.paths.size(), 1u);
  EXPECT_TRUE(d.paths[0].closed);
  EXPECT_NEAR(d.bounds.min_x, 30, 1e-9);
  EXPECT_NEAR(d.bounds.max_x, 70, 1e-9);
  EXPECT_NEAR(d.bounds.max_y, -20, 1e-9);  // y up: SVG's y 10 .. 20, doubled, below 0
  EXPECT_NEAR(d.bounds.min_y, -40, 1e-9);
  // each kind of element draws
  for (const char* e : {"<line x1=\"0\" y1=\"0\" x2=\"10\" y2=\"5\"/>", "<polyline points=\"0,0 10,0 10,10\"/>",
                        "<polygon points=\"0,0 10,0 5,8\"/>", "<circle cx=\"5\" cy=\"5\" r=\"4\"/>",
                        "<ellipse cx=\"5\" cy=\"5\" rx=\"4\" ry=\"2\"/>", "<path d=\"M0 0 Q 5 10 10 0 T 20 0\"/>",
                        "<g transform=\"rotate(90)\"><path d=\"m0 0 h10 v10 z\"/></g>"})
    EXPECT_FALSE(read_svg(svg(e), "t.svg").paths.empty()) << e;
  // a group's transform applies to its children, and not after it
  const SvgDrawing g = read_svg(svg("<g transform=\"translate(100 0)\"><line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"0\"/></g>"
                                    "<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"0\"/>"),
                                "t.svg");
  ASSERT_EQ(g.paths.size(), 2u);
  EXPECT_NEAR(g.paths[0].start.x, 100, 1e-9);
  EXPECT_NEAR(g.paths[1].start.x, 0, 1e-9);
}

TEST(Svg, CurvesAndArcsFlattenWithinTheTolerance) {
  const SvgDrawing c = read_svg(svg("<circle cx=\"0\" cy=\"0\" r=\"50\"/><path d=\"M 100 0 A 10 10 0 0 1 120 0\"/>"), "t.svg");
  for (double tol : {1.0, 0.1, 0.01}) {
    const std::vector<Stroke> s = flatten_svg(c, tol);
    ASSERT_EQ(s.size(), 2u);
    double worst = 0;
    for (const Point2& p : s[0]) worst = std::max(worst, std::fabs(std::hypot(p.x, p.y) - 50));
    // every vertex on the circle (the cubics' own error, about 0.03 % of the radius, beside)
    EXPECT_LT(worst, 0.02 + 1e-9) << tol;
    // and between vertices the chord stays within the tolerance: its middle
    for (size_t i = 1; i < s[0].size(); ++i) {
      const Point2 m{(s[0][i - 1].x + s[0][i].x) / 2, (s[0][i - 1].y + s[0][i].y) / 2};
      EXPECT_LT(50 - std::hypot(m.x, m.y), tol + 0.02) << tol;
    }
    for (const Point2& p : s[1]) EXPECT_NEAR(std::hypot(p.x - 110, p.y), 10, tol + 0.01) << tol;
    if (tol < 1) {
      EXPECT_GT(s[0].size(), 20u);
    }
  }
}

TEST(Svg, TheShippedIconsRead) {
  for (const char* f : {"examples/drawings/house.svg", "examples/drawings/bicycle.svg"}) {
    const SvgDrawing d = read_svg(file(f), f);
    EXPECT_GE(d.paths.size(), 2u) << f;
    EXPECT_NEAR(d.bounds.width(), 16, 1.5) << f;  // a 16-unit icon
  }
}

TEST(Svg, AHostileFileIsRefusedWithItsReason) {
  EXPECT_EQ(refusal(svg("<script>alert(1)</script><line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\"/>")),
            "t.svg: holds a <script>: a drawing never runs code");
  EXPECT_EQ(refusal(svg("<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\" onclick=\"x()\"/>")),
            "t.svg: <line> has an event handler (onclick): a drawing never runs code");
  EXPECT_EQ(refusal(svg("<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\"/>", "onload=\"x()\"")),
            "t.svg: <svg> has an event handler (onload): a drawing never runs code");
  EXPECT_EQ(refusal(svg("<image xlink:href=\"http://example.com/a.png\"/><line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\"/>")),
            "t.svg: <image> refers to something outside the file (http://example.com/a.png): nothing is fetched");
  EXPECT_EQ(refusal(svg("<use href=\"other.svg#a\"/>")),
            "t.svg: <use> refers to something outside the file (other.svg#a): nothing is fetched");
  EXPECT_EQ(refusal(svg("<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\" style=\"fill:url(http://x/y)\"/>")),
            "t.svg: <line> refers to something outside the file (fill:url(http://x/y)): nothing is fetched");
  EXPECT_EQ(refusal(svg("<foreignObject><p>hi</p></foreignObject>")),
            "t.svg: holds a <foreignObject> (HTML inside the drawing): not drawn");
  // a billion laughs
  const std::string bomb = "<?xml version=\"1.0\"?><!DOCTYPE svg [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;\">]>" +
                           svg("<text>&b;</text>");
  EXPECT_EQ(refusal(bomb), "t.svg: declares entities (a DOCTYPE with declarations): refused, as an XML bomb would be");
  EXPECT_EQ(refusal(std::string(kMaxSvgBytes + 1, ' ')), "t.svg: 5120 KB: a drawing is at most 5 MB");
  EXPECT_EQ(refusal("hello, not XML"), "t.svg: not an SVG file: expected < at byte 0");
  EXPECT_EQ(refusal("<html><body/></html>"), "t.svg: not an SVG file: its first element is <html>");
  EXPECT_EQ(refusal(svg("<text x=\"0\" y=\"0\">words only</text>")),
            "t.svg: no drawable path (paths, lines, polylines, polygons, rects, circles, ellipses)");
  EXPECT_EQ(refusal(svg("<path d=\"M 0 0 L 10\"/>")),
            "t.svg: cannot be read: Invalid value of SVG attribute (or property) \"d\": \"M 0 0 L 10\"");
}

// Issue 41: what the file shows, and nothing else. An icon set's invisible 24 x 24 frame (the
// first path of every Tabler icon) is not drawn, so the fit is the icon's own strokes.
TEST(Svg, WhatDoesNotShowIsNotDrawn) {
  const std::string stroke = "<path d=\"M4 12 h16 M12 4 v16\"/>";  // a plus, 4 .. 20
  const SvgDrawing icon =
      read_svg(svg("<path stroke=\"none\" d=\"M0 0h24v24H0z\" fill=\"none\"/>" + stroke,
                   "width=\"24\" height=\"24\" viewBox=\"0 0 24 24\" fill=\"none\" stroke=\"currentColor\" stroke-width=\"2\""),
               "t.svg");
  ASSERT_EQ(icon.paths.size(), 2u);
  EXPECT_NEAR(icon.bounds.min_x, 4, 1e-9);
  EXPECT_NEAR(icon.bounds.max_x, 20, 1e-9);
  // each way a shape does not show, by attribute and by its style attribute, on itself or on
  // a group around it: only the plus is left
  const char* hidden[] = {
      "<rect width=\"24\" height=\"24\" stroke=\"none\" fill=\"none\"/>",
      "<rect width=\"24\" height=\"24\" style=\"stroke:none;fill:none\"/>",
      "<rect width=\"24\" height=\"24\" display=\"none\"/>",
      "<rect width=\"24\" height=\"24\" style=\"display: none\"/>",
      "<g display=\"none\"><rect width=\"24\" height=\"24\" stroke=\"black\"/></g>",
      "<rect width=\"24\" height=\"24\" visibility=\"hidden\"/>",
      "<g style=\"visibility:hidden\"><rect width=\"24\" height=\"24\"/></g>",
      "<rect width=\"24\" height=\"24\" opacity=\"0\"/>",
      "<g opacity=\"0\"><rect width=\"24\" height=\"24\" stroke=\"black\"/></g>",
      "<rect width=\"24\" height=\"24\" fill=\"none\" stroke=\"black\" stroke-opacity=\"0\"/>",
      "<rect width=\"24\" height=\"24\" style=\"fill-opacity:0\"/>",
      "<defs><rect id=\"r\" width=\"24\" height=\"24\" stroke=\"black\"/></defs>",
      "<symbol id=\"s\"><rect width=\"24\" height=\"24\" stroke=\"black\"/></symbol>",
      "<clipPath id=\"c\"><rect width=\"24\" height=\"24\"/></clipPath>",
      "<mask id=\"m\"><rect width=\"24\" height=\"24\" fill=\"white\"/></mask>",
      "<marker id=\"k\"><rect width=\"24\" height=\"24\"/></marker>",
  };
  for (const char* h : hidden) {
    const SvgDrawing d = read_svg(svg(std::string(h) + "<path stroke=\"black\" d=\"M4 12 h16 M12 4 v16\"/>"), "t.svg");
    EXPECT_EQ(d.paths.size(), 2u) << h;
    EXPECT_NEAR(d.bounds.min_x, 4, 1e-9) << h;
    EXPECT_NEAR(d.bounds.max_x, 20, 1e-9) << h;
  }
  // what shows: a child made visible inside a hidden group; a fill without a stroke (drawn
  // as its outline, as pen plotters do); a stroke by style over a fill of none
  for (const char* shown : {"<g visibility=\"hidden\"><rect width=\"24\" height=\"24\" visibility=\"visible\"/></g>",
                            "<rect width=\"24\" height=\"24\"/>",
                            "<rect width=\"24\" height=\"24\" fill=\"none\" style=\"stroke:#000\"/>",
                            "<rect width=\"24\" height=\"24\" stroke=\"none\" fill=\"currentColor\"/>"}) {
    const SvgDrawing d = read_svg(svg(shown), "t.svg");
    ASSERT_EQ(d.paths.size(), 1u) << shown;
    EXPECT_NEAR(d.bounds.width(), 24, 1e-9) << shown;
  }
}

TEST(Svg, AFileWithNothingThatShowsIsRefused) {
  EXPECT_EQ(refusal(svg("<path stroke=\"none\" d=\"M0 0h24v24H0z\" fill=\"none\"/>")),
            "t.svg: nothing in it shows: its 1 shape is invisible (stroke and fill none, hidden, transparent, or kept in <defs> and no <use> shows it)");
  EXPECT_EQ(refusal(svg("<g opacity=\"0\"><line x1=\"0\" y1=\"0\" x2=\"5\" y2=\"5\" stroke=\"red\"/>"
                        "<circle r=\"3\"/></g>")),
            "t.svg: nothing in it shows: its 2 shapes are invisible (stroke and fill none, hidden, transparent, or kept in <defs> and no <use> shows it)");
}

// A <style> sheet's class rule hides as an attribute does; an element's own style still wins.
TEST(Svg, AStyleSheetsClassRulesCount) {
  const std::string sheet = "<style>.frame, .ghost { stroke: none; fill: none } .ink{stroke:#000}</style>";
  const SvgDrawing d = read_svg(svg(sheet + "<rect class=\"frame\" width=\"24\" height=\"24\"/>"
                                            "<rect class=\"big ghost\" x=\"-10\" width=\"50\" height=\"50\"/>"
                                            "<path class=\"ink\" fill=\"none\" d=\"M4 12 h16\"/>"),
                                "t.svg");
  ASSERT_EQ(d.paths.size(), 1u);
  EXPECT_NEAR(d.bounds.min_x, 4, 1e-9);
  EXPECT_NEAR(d.bounds.max_x, 20, 1e-9);
  const SvgDrawing own = read_svg(svg(sheet + "<rect class=\"frame\" style=\"stroke:red\" width=\"24\" height=\"24\"/>"),
                                  "t.svg");
  EXPECT_EQ(own.paths.size(), 1u);
  EXPECT_EQ(refusal(svg(sheet + "<rect class=\"frame\" width=\"24\" height=\"24\"/>")),
            "t.svg: nothing in it shows: its 1 shape is invisible (stroke and fill none, hidden, transparent, or kept in <defs> and no <use> shows it)");
}

// Attributes and style properties the reader does not know pass, as in a browser (Heroicons
// carry aria-hidden, other sets data-* and blend modes): they change nothing drawn.
TEST(Svg, UnknownAttributesAndPropertiesPass) {
  const SvgDrawing d = read_svg(svg("<path aria-hidden=\"true\" data-x=\"1\" style=\"mix-blend-mode:multiply\" "
                                    "stroke=\"black\" d=\"M4 12 h16\"/>", "aria-hidden=\"true\""),
                                "t.svg");
  ASSERT_EQ(d.paths.size(), 1u);
}

// What <defs>, <symbol>, <clipPath>, <mask> and <marker> keep is drawn only where a <use>
// shows it: in its place, moved by the use's x and y, styled by the use; a use of a symbol
// draws the symbol's children. A file with nothing but kept shapes is refused as invisible.
TEST(Svg, UseShowsWhatDefsKeepAndNothingElse) {
  const std::string defs = "<defs><path id=\"d\" stroke=\"red\" d=\"M0 0 h10\"/><clipPath id=\"c\"><rect width=\"99\" height=\"99\"/></clipPath></defs>"
                           "<symbol id=\"s\"><path stroke=\"red\" d=\"M0 0 v10\"/></symbol>";
  const SvgDrawing d = read_svg(svg(defs + "<use href=\"#d\" x=\"5\" y=\"2\"/><use xlink:href=\"#s\" x=\"30\"/>"), "t.svg");
  ASSERT_EQ(d.paths.size(), 2u);
  EXPECT_NEAR(d.bounds.min_x, 5, 1e-9);   // the path moved by x
  EXPECT_NEAR(d.bounds.max_x, 30, 1e-9);  // the symbol's line at x 30; the clip path's 99 mm square not drawn
  EXPECT_NEAR(d.bounds.min_y, -10, 1e-9);  // (y up on the paper: the SVG's y down)
  EXPECT_EQ(read_svg(svg(defs + "<path stroke=\"red\" d=\"M1 1 h3\"/>"), "t.svg").paths.size(), 1u);
  EXPECT_EQ(refusal(svg(defs)),
            "t.svg: nothing in it shows: its 3 shapes are invisible (stroke and fill none, hidden, transparent, or kept in <defs> and no <use> shows it)");
  // a use styled invisible shows nothing; a use of nothing draws nothing
  EXPECT_EQ(read_svg(svg(defs + "<use href=\"#d\" opacity=\"0\"/><use href=\"#nowhere\"/><path stroke=\"red\" d=\"M1 1 h3\"/>"), "t.svg")
                .paths.size(),
            1u);
}

TEST(Svg, AUseOfItselfOrOneThatMultipliesWithoutEndIsRefused) {
  EXPECT_EQ(refusal(svg("<g id=\"a\"><path stroke=\"red\" d=\"M0 0 h3\"/><use href=\"#a\"/></g>")),
            "t.svg: <use href=\"#a\"> sits inside what it names: refused");
  std::string bomb = "<defs><g id=\"l0\"><path stroke=\"red\" d=\"M0 0 h3\"/><path stroke=\"red\" d=\"M0 0 h3\"/></g>";
  for (int level = 1; level <= 4; ++level) {
    bomb += "<g id=\"l" + std::to_string(level) + "\">";
    for (int k = 0; k < 10; ++k) bomb += "<use href=\"#l" + std::to_string(level - 1) + "\"/>";
    bomb += "</g>";
  }
  bomb += "</defs>";
  for (int k = 0; k < 10; ++k) bomb += "<use href=\"#l4\"/>";
  EXPECT_EQ(refusal(svg(bomb)), "t.svg: its <use> elements copy more than 20000 elements: refused");
}
