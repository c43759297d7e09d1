// Tests host/lib/legacy.cpp: the thesis's appendix C robot format imported into a robot
// file that the loader accepts and whose kinematics equal the hand-made thesis example.
#include <articula/dh.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "legacy.h"
#include "robot_file.h"

using namespace articula;
using namespace articula::host;

namespace {
std::string read(const std::string& rel) {
  std::ifstream f(std::string(ARTICULA_SOURCE_DIR) + "/" + rel);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

const std::string kExample = read("docs/examples/thesis-example.legacy.txt");

std::string error_of(const std::string& text) {
  try {
    import_legacy(text, "old.txt", 10);
  } catch (const LegacyError& e) {
    return e.what();
  }
  return "no error";
}

// Replaces the n-th value line (1-based, counting only lines with content) of the example.
std::string with_line(int n, const std::string& replacement) {
  std::istringstream in(kExample);
  std::ostringstream out;
  std::string s;
  int content = 0;
  while (std::getline(in, s)) {
    const bool is_content = !s.empty() && s[0] != '#';
    if (is_content && ++content == n)
      out << replacement << '\n';
    else
      out << s << '\n';
  }
  return out.str();
}
}  // namespace

TEST(Legacy, ThesisExampleImportsAsTheHandMadeRobot) {
  const LegacyImport imp = import_legacy(kExample, "thesis-example.legacy.txt", 10);
  const Robot imported = parse_robot(imp.robot.dump(), "imported.json");
  const Robot reference = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/thesis-example.json");
  ASSERT_EQ(imported.model.num_rows, 4);
  ASSERT_EQ(imported.model.num_joints, 8);  // theta and alpha on every row
  EXPECT_TRUE(imported.gripper.present);
  // Table 2's pose on both: theta = 90, -110, 0, 0 and alpha(2) = 90 on row 3.
  double q[8] = {0};
  q[0] = deg_to_rad(90.0);
  q[2] = deg_to_rad(-110.0);
  q[5] = deg_to_rad(90.0);
  for (int j = 0; j < 8; ++j) EXPECT_EQ(imported.model.joints[j].param, reference.model.joints[j].param) << j;
  const Vec3<double> a = tool_position(imported.model, q), b = tool_position(reference.model, q);
  EXPECT_NEAR(norm(a - b), 0, 1e-9);
  EXPECT_NEAR(a.z, 7, 1e-9);  // d = 0.7 units * 10 mm
}

TEST(Legacy, ListsWhatDoesNotMap) {
  const LegacyImport imp = import_legacy(kExample, "old.txt", 10);
  auto has = [&](const std::string& piece) {
    for (const auto& d : imp.dropped)
      if (d.find(piece) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(has("old.txt:5: arm 0 model scale"));
  EXPECT_TRUE(has("arm model path 'Models/arm.obj'"));
  EXPECT_TRUE(has("hand model path 'Models/hand2.obj'"));
  EXPECT_TRUE(has("restrictions 'none'"));
  EXPECT_TRUE(has("gripper kept horizontal"));
  EXPECT_GE(imp.dropped.size(), 20u);
}

TEST(Legacy, ErrorsNameTheLine) {
  EXPECT_EQ(error_of(""), "old.txt:0: the file ends before set 1 (number of arms)");
  EXPECT_EQ(error_of(with_line(1, "x")), "old.txt:4: set 1 (number of arms): 'x' is not a number");
  EXPECT_EQ(error_of(with_line(1, "0")), "old.txt:4: set 1 (number of arms): a whole number from 1 to 15 expected");
  EXPECT_EQ(error_of(with_line(6, "6 0.7 0")), "old.txt:9: set 3 (DH: length offset theta alpha): 4 numbers expected, 3 given");
  EXPECT_EQ(error_of(with_line(12, "2")), "old.txt:15: set 5 (hand): 1 or 0 expected");
  EXPECT_EQ(error_of(with_line(21, "1 2 0")), "old.txt:24: set 9 (variable flags): each flag is 1 or 0");
  EXPECT_EQ(error_of(kExample + "extra\n"), "old.txt:43: more lines than the 20 sets take");
  try {
    import_legacy(kExample, "old.txt", 0);
    FAIL();
  } catch (const LegacyError& e) {
    EXPECT_NE(std::string(e.what()).find("positive number of mm per unit"), std::string::npos);
  }
}
