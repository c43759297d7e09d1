// Tests host/physics/mat.h: the table's mat at 1:1, each object where the scene puts it, every
// name as text, a cell's arms and devices.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "cell_file.h"
#include "mat.h"
#include "scene.h"

using namespace articula::host;

namespace {

const std::string kSrc = ARTICULA_SOURCE_DIR;

double attr(const std::string& svg, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(svg, m, std::regex(" " + name + "=\"([-0-9.]+)mm\""))) return -1;
  return std::stod(m[1]);
}

}  // namespace

TEST(Mat, ASceneAtOneToOneWithItsNamesAsText) {
  const Scene s = parse_scene(R"({"objects": [
      {"name": "<b>box</b> & co", "type": "box", "size": [40, 20, 30], "xyz": [200, 0, 15], "rpy": [0, 0, 90], "movable": true},
      {"name": "post", "type": "cylinder", "size": [10, 100], "xyz": [-100, 100, 50]}]})", "s.json");
  const std::string svg = mat_svg(s);
  // the sheet: from x -110 (the post's edge) to 210 (the box turned: 20 wide in x), from y -30
  // (the origin's room) to 110, with 20 mm margins and 24 mm at the foot
  EXPECT_EQ(attr(svg, "width"), 360);
  EXPECT_EQ(attr(svg, "height"), 204);
  // the box turned 90 degrees: 20 mm along x, 40 along y, dashed (it moves); at x 190..210
  // (sheet x + 110 + 20: 320..340), y -20..20 (sheet 110 - y + 20: 110..150)
  EXPECT_NE(svg.find("<polygon points=\"320,150 340,150 340,110 320,110 \" fill=\"none\" stroke=\"#222\" stroke-width=\"0.4\" stroke-dasharray"),
            std::string::npos)
      << svg;
  EXPECT_NE(svg.find("<circle cx=\"30\" cy=\"30\" r=\"10\" fill=\"none\""), std::string::npos);  // the post, upright
  // a name is text, never markup
  EXPECT_EQ(svg.find("<b>"), std::string::npos);
  EXPECT_NE(svg.find("&lt;b&gt;box&lt;/b&gt; &amp; co"), std::string::npos);
  EXPECT_NE(svg.find("the arm's base frame"), std::string::npos);
  EXPECT_NE(svg.find("100 mm: measure it on the print"), std::string::npos);
}

TEST(Mat, ACellsArmsBeltBarrierAndFeeder) {
  const Cell cell = load_cell_file(kSrc + "/cells/station.json");
  const std::string svg = mat_svg(cell);
  EXPECT_NE(svg.find(">mk2</text>"), std::string::npos);
  // its reach on the table: a dashed circle about the base's shoulder axis, within its reach bound
  EXPECT_NE(svg.find("its reach on the table: inside the dashed circle"), std::string::npos);
  EXPECT_NE(svg.find("stroke-dasharray=\"4 2\""), std::string::npos);
  EXPECT_NE(svg.find("gate: light barrier, 10 mm up"), std::string::npos);
  EXPECT_NE(svg.find("feeder: the feeder's 3 come out here"), std::string::npos);
  EXPECT_NE(svg.find("belt (belt, 100 mm/s)"), std::string::npos);
  EXPECT_EQ(svg.find(">block1</text>"), std::string::npos) << "a feeder's blocks are not on the table at the start";
  // one line for the beam, the base's circle with its facing
  EXPECT_NE(svg.find("stroke=\"#d62828\""), std::string::npos);
  EXPECT_EQ(std::count(svg.begin(), svg.end(), '\n') > 20, true);
  EXPECT_EQ(svg.rfind("</svg>\n"), svg.size() - 7);
}
