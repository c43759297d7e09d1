// Tests host/lib/blocks.cpp: the one protocol line formatter, the studio's blocks as programs
// (limits, reach, speed, comments, the block of each line) and programs as blocks again.
#include <gtest/gtest.h>

#include <cmath>

#include "blocks.h"
#include "draw.h"
#include "program.h"
#include "robot_file.h"
#include "test_robots.h"
#include "robot_view.h"

using namespace articula::host;
using nlohmann::json;

namespace {
const InverseKinematics& mk2_ik() {
  static const InverseKinematics ik(mk2());
  return ik;
}
json compile(const json& ops) { return blocks_program_json(mk2(), mk2_ik(), ops); }

// The text's lines, the header included.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  size_t at = 0;
  for (size_t nl; (nl = text.find('\n', at)) != std::string::npos; at = nl + 1) out.push_back(text.substr(at, nl - at));
  return out;
}
}  // namespace

TEST(ProtocolLine, WritesNumbersAsTheParserReadsThem) {
  EXPECT_EQ(protocol_number(12.5), "12.5");
  EXPECT_EQ(protocol_number(100), "100");
  EXPECT_EQ(protocol_number(-0.0001), "0");
  EXPECT_EQ(protocol_number(1.23456), "1.235");
  EXPECT_EQ(protocol_number(-7.1), "-7.1");
  EXPECT_EQ(protocol_line(mk2(), 'P', {200, 0, 50.5}), "P 200 0 50.5");
  EXPECT_EQ(protocol_line(mk2(), 'T', {250, -30, 150, 30}), "T 250 -30 150 30");
  EXPECT_EQ(protocol_line(mk2(), '$', {0, 600}), "$0=600");
  EXPECT_EQ(protocol_line(mk2(), 'H', {}), "H");
  EXPECT_EQ(protocol_line(mk2(), 'L', {1, -12.25}), "L 1 -12.25");
  // Every line it writes, the firmware's parser reads back to the same thousandths.
  const std::vector<double> v = {12.3456, -0.5, 98.7654};
  articula::Command cmd{};
  ASSERT_EQ(parse_protocol_line(cmd, protocol_line(mk2(), 'M', v), 3), articula::kOk);
  for (size_t i = 0; i < v.size(); ++i) EXPECT_EQ(cmd.arg[i], std::lround(v[i] * 1000)) << i;
}

TEST(ProtocolLine, RefusesWhatTheArmCouldNotRead) {
  auto problem = [](char word, const std::vector<double>& values) {
    try {
      protocol_line(mk2(), word, values);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(problem('M', {1, 2}), "M takes 3 values on MK2 Plus, not 2");
  EXPECT_EQ(problem('X', {1}), "the protocol has no command 'X'");
  EXPECT_EQ(problem('P', {1, NAN, 3}), "P: value 2 must be a finite number within +-1,000,000");
  EXPECT_EQ(problem('P', {1, 2e6, 3}), "P: value 2 must be a finite number within +-1,000,000");
  EXPECT_EQ(problem('L', {0.5, 10}), "L: value 1 must be whole");
  EXPECT_EQ(problem('N', {1}), "N takes text, not numbers");
}

TEST(ProtocolLine, MovesWithTheMotorsAnglesOfAPose) {
  const std::vector<double> q = {10, 80, -100};
  const std::vector<double> u = motors_from_joints(mk2(), joints_in(mk2(), q, "q"));
  EXPECT_EQ(move_line(mk2(), q), protocol_line(mk2(), 'M', u));
  EXPECT_EQ(move_line(mk2(), q).substr(0, 2), "M ");
}

TEST(BlocksProgram, EachLineNamesItsBlockAndRoboSimFollows) {
  const json out = compile(json::array({
      {{"op", "joints"}, {"values", {0, 90, -110}}, {"block", "a"}},
      {{"op", "tool_to"}, {"xyz", {235, 0, 213}}, {"block", "b"}},
      {{"op", "gripper"}, {"percent", 40}, {"block", "c"}},
      {{"op", "speed"}, {"percent", 50}, {"block", "d"}},
      {{"op", "wait"}, {"seconds", 0.5}, {"block", "e"}},
  }));
  ASSERT_FALSE(out.contains("error")) << out.dump();
  const std::vector<std::string> lines = lines_of(out["text"]);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], "# made from blocks in Articula Studio");
  EXPECT_EQ(lines[1], move_line(mk2(), {0, 90, -110}));
  EXPECT_EQ(lines[2], "P 235 0 213");
  EXPECT_EQ(lines[3], "G 40");
  EXPECT_EQ(lines[4], "$0=300");  // half the firmware's default top rate, 600 steps/s
  EXPECT_EQ(lines[5], "D 0.5");
  EXPECT_EQ(out["lines"], json({"", "a", "b", "c", "d", "e"}));
  EXPECT_TRUE(out["problems"].empty()) << out["problems"].dump();
  // RoboSim: its hand 0 (open) .. 0.5 (closed), its speed 1 .. 82
  const std::string rs = out["robosim"];
  EXPECT_NE(rs.find("m\n0\n90\n-110\n"), std::string::npos) << rs;
  EXPECT_NE(rs.find("h\n0.3\n"), std::string::npos) << rs;
  EXPECT_NE(rs.find("s\n41\n"), std::string::npos) << rs;
  // and the program runs as written: the prediction accepts every line
  const Program p = parse_program(out["text"], "blocks.arm", mk2());
  EXPECT_EQ(p.statements.size(), 5u);
}

TEST(BlocksProgram, ARefusedMoveNamesTheJointAndLeavesThePose) {
  const json out = compile(json::array({
      {{"op", "joints"}, {"values", {0, 90, -110}}, {"block", "start"}},
      {{"op", "joint_to"}, {"joint", 1}, {"value", 140}, {"block", "far"}},
      {{"op", "joint_by"}, {"joint", 0}, {"value", 10}, {"block", "by"}},
  }));
  ASSERT_FALSE(out.contains("error")) << out.dump();
  ASSERT_EQ(out["problems"].size(), 1u);
  EXPECT_EQ(out["problems"][0]["block"], "far");
  EXPECT_EQ(out["problems"][0]["message"], "shoulder at 140\xC2\xB0 is beyond its range, 36\xC2\xB0 to 130\xC2\xB0");
  // "by" moves from the pose before the refused block: shoulder still 90
  EXPECT_EQ(lines_of(out["text"])[3], move_line(mk2(), {10, 90, -110}));
}

TEST(BlocksProgram, AMotorBeyondItsRangeIsNamedWithThePose) {
  // Every joint within its box, the elbow motor (shoulder + elbow) beyond -43 .. 15.
  const json out = compile(json::array({{{"op", "joints"}, {"values", {0, 40, -170}}, {"block", "x"}}}));
  ASSERT_EQ(out["problems"].size(), 1u) << out.dump();
  const std::string m = out["problems"][0]["message"];
  EXPECT_NE(m.find("this pose needs the"), std::string::npos) << m;
  EXPECT_NE(m.find("beyond its range"), std::string::npos) << m;
  EXPECT_NE(m.find("(the joints: base 0\xC2\xB0, shoulder 40\xC2\xB0, elbow -170\xC2\xB0)"), std::string::npos) << m;
}

TEST(BlocksProgram, AnUnreachablePointAndABadSpeedAreProblemsOnTheirBlocks) {
  const json out = compile(json::array({
      {{"op", "tool_to"}, {"xyz", {900, 0, 0}}, {"block", "far"}},
      {{"op", "line_to"}, {"xyz", {235, 0, 213}}, {"speed", 2000}, {"block", "fast"}},
      {{"op", "gripper"}, {"percent", 120}, {"block", "grip"}},
  }));
  ASSERT_EQ(out["problems"].size(), 3u) << out.dump();
  EXPECT_EQ(out["problems"][0]["block"], "far");
  EXPECT_EQ(out["problems"][0]["message"], "the tool cannot reach (900, 0, 0) mm: it is farther than the arm is long; the nearest the tool comes is 573.2 mm away");
  EXPECT_EQ(out["problems"][1]["message"], "the speed is from more than 0 to 1000 mm/s, not 2000 mm/s");
  EXPECT_EQ(out["problems"][2]["message"], "the gripper opens from 0 % to 100 %, not 120 %");
}

TEST(BlocksProgram, ABlockThatCannotBecomeALineIsAnErrorOnIt) {
  json out = compile(json::array({{{"op", "joint_to"}, {"joint", 5}, {"value", 1}, {"block", "j"}}}));
  EXPECT_EQ(out["error"]["block"], "j");
  EXPECT_EQ(out["error"]["message"], "MK2 Plus has no joint 6: choose one of base, shoulder, elbow");
  out = compile(json::array({{{"op", "joints"}, {"values", {1, 2}}, {"block", "k"}}}));
  EXPECT_EQ(out["error"]["message"], "MK2 Plus has 3 joints (base, shoulder, elbow): this block gives 2 values");
  out = compile(json::array({{{"op", "speed"}, {"percent", 0}, {"block", "s"}}}));
  EXPECT_EQ(out["error"]["message"], "the speed is from 1 % to 100 %, not 0 %");
  out = compile(json::array({{{"op", "tool_to"}, {"xyz", {1, "x", 3}}, {"block", "t"}}}));
  EXPECT_EQ(out["error"]["message"], "'xyz' must hold finite numbers");
}

TEST(BlocksProgram, ALongCommentSplitsBetweenCharactersIntoLinesTheArmTakes) {
  std::string text;
  for (int i = 0; i < 50; ++i) text += "d\xC3\xA9";  // "dé" 50 times: 150 bytes
  const json out = compile(json::array({{{"op", "comment"}, {"text", text + "\nend"}, {"block", "c"}}}));
  const std::vector<std::string> lines = lines_of(out["text"]);
  ASSERT_EQ(lines.size(), 4u) << out.dump();
  std::string joined;
  for (size_t i = 1; i < lines.size(); ++i) {
    EXPECT_LE(lines[i].size(), 64u);
    EXPECT_EQ(lines[i].substr(0, 2), "# ");
    EXPECT_EQ(static_cast<unsigned char>(lines[i][2]) & 0xC0, 0x40u) << "a line starts inside a character";
    joined += lines[i].substr(2);
  }
  EXPECT_EQ(joined, text + " end");
}

TEST(ProgramActions, AProgramFromBlocksReadsBackAsTheSameBlocks) {
  const json ops = json::array({
      {{"op", "comment"}, {"text", "wave"}, {"block", "0"}},
      {{"op", "joints"}, {"values", {10, 80, -100}}, {"block", "1"}},
      {{"op", "line_to"}, {"xyz", {235, 0, 213}}, {"speed", 30}, {"block", "2"}},
      {{"op", "gripper"}, {"percent", 25}, {"block", "3"}},
      {{"op", "wait"}, {"seconds", 1}, {"block", "4"}},
  });
  const json out = compile(ops);
  const json back = program_actions_json(mk2(), out["text"], "blocks.arm");
  EXPECT_EQ(back["format"], "protocol");
  ASSERT_EQ(back["ops"].size(), 6u) << back.dump();  // the header comment first
  EXPECT_EQ(back["ops"][0]["text"], "made from blocks in Articula Studio");
  EXPECT_EQ(back["ops"][1]["text"], "wave");
  for (int j = 0; j < 3; ++j)
    EXPECT_NEAR(back["ops"][2]["values"][j].get<double>(), ops[1]["values"][j].get<double>(), 2e-3) << j;
  EXPECT_EQ(back["ops"][3]["op"], "line_to");
  EXPECT_EQ(back["ops"][3]["speed"], 30.0);
  EXPECT_EQ(back["ops"][4]["percent"], 25.0);
  EXPECT_EQ(back["ops"][5]["seconds"], 1.0);
  // RoboSim reads back too: m in joint values, h as a percent, s as a percent of 82
  const json rs = program_actions_json(mk2(), "m\n0\n90\n-110\nh\n0.25\ns\n41\n", "p.robosim");
  EXPECT_EQ(rs["format"], "robosim");
  EXPECT_EQ(rs["ops"][1]["percent"], 50.0);
  EXPECT_EQ(rs["ops"][2]["percent"], 50.0);
}

TEST(BlocksProgram, ThePensBlocksDrawWhatTheDrawingDraws) {
  const json out = compile(json::parse(R"([
    {"op": "pen", "pen": 120, "z": 0, "block": "p"},
    {"op": "tool_to", "xyz": [230, -20, 130], "block": "a"},
    {"op": "pen_down", "block": "d"},
    {"op": "pen_to", "xy": [270, -20], "block": "l"},
    {"op": "pen_up", "block": "u"},
    {"op": "shape", "shape": "square", "width": 30, "at": [250, 0], "block": "s"},
    {"op": "write", "text": "Hi", "width": 30, "at": [250, 0], "block": "w"}
  ])"));
  ASSERT_FALSE(out.contains("error")) << out.dump();
  EXPECT_TRUE(out["problems"].empty()) << out["problems"].dump();
  const std::vector<std::string> lines = out["lines"];
  const std::string text = out["text"];
  // the pen goes down and up where the tool is, and along at the paper's height
  EXPECT_NE(text.find("\nT 230 -20 120 20\nT 270 -20 120 20\nT 270 -20 130 40\n"), std::string::npos) << text;
  // the square's and the text's lines are their blocks', pen down along each stroke
  const auto count = [&](const std::string& b) { return std::count(lines.begin(), lines.end(), b); };
  EXPECT_EQ(count("s"), 1 + 5 + 1);  // above its start, round its four sides, up
  EXPECT_GT(count("w"), 10);
  // and the arm takes every line: the ink of the program is the square and the letters
  const json check = drawing_check_json(mk2(), mk2_ik(), {{"program", text}, {"target", {{"shape", "square"}, {"width", 30}, {"at", {250, 0}}}},
                                                          {"z", 0}, {"pen", 120}, {"tolerance", 3}});
  EXPECT_LT(check["uncovered_mm"].get<double>(), 3) << check["says"];  // (the line and "Hi" are ink too)
  // a pen block before the pen is said is an error on it
  const json early = compile(json::parse(R"([{"op": "pen_down", "block": "d"}])"));
  ASSERT_TRUE(early.contains("error"));
  EXPECT_EQ(early["error"]["block"], "d");
  // a drawing out of reach is a problem on its block, with the way to move it
  const json far = compile(json::parse(R"([{"op": "pen", "pen": 120, "z": 0, "block": "p"},
    {"op": "shape", "shape": "star", "width": 40, "at": [120, 0], "block": "s"}])"));
  ASSERT_EQ(far["problems"].size(), 1u);
  EXPECT_EQ(far["problems"][0]["block"], "s");
  EXPECT_NE(far["problems"][0]["message"].get<std::string>().find("toward +x"), std::string::npos);
}

// The toolbox's blocks point where the arm reaches (issue 55, 3: a class's meArm reaches about
// 228 mm, and "move the tool to 200, 0, 150" warned on every new block): on every shipped
// robot, the tool's point and the straight line from it are reached, and where a pen and a
// place were found, a square that wide is drawn there. The MK2 keeps the numbers it had.
TEST(ExamplePlaces, EveryShippedArmReachesItsToolboxsPoints) {
  int fitted = 0;
  for (const char* name : {"mk2plus", "mk2plus-cnc", "mearm", "eezybot-mk2", "micro-arm-28byj48", "panda", "puma560",
                           "thesis-example", "three-link-8dof"}) {
    SCOPED_TRACE(name);
    const Robot r = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/" + name + ".json");
    const InverseKinematics ik(r);
    const json p = example_places_json(r, ik);
    const articula::Vec3<double> tool = articula::make_vec3(p["tool"][0].get<double>(), p["tool"][1].get<double>(), p["tool"][2].get<double>());
    const articula::Vec3<double> to = articula::make_vec3(p["line_to"][0].get<double>(), p["line_to"][1].get<double>(), p["line_to"][2].get<double>());
    EXPECT_TRUE(ik.solve(IkTarget::at(tool), ik_start(r, nullptr)).reached());
    for (int k = 0; k <= 10; ++k)
      EXPECT_TRUE(ik.solve(IkTarget::at(tool + (k / 10.0) * (to - tool)), ik_start(r, nullptr)).reached()) << k;
    if (!p["fits"].get<bool>()) continue;
    ++fitted;
    PenSettings pen;
    pen.pen_mm = p["pen"];
    pen.paper_z = p["paper_z"];
    EXPECT_TRUE(check_reach(r, ik, place_strokes(shape_strokes("square"), p["draw_width"], p["draw_at"][0], p["draw_at"][1]), pen).fits);
  }
  EXPECT_GE(fitted, 7);
  const json mk2_places = example_places_json(mk2(), mk2_ik());
  EXPECT_EQ(mk2_places["tool"], json({240, 0, 150}));
  EXPECT_EQ(mk2_places["pen"], 120);
  EXPECT_EQ(mk2_places["draw_at"], json({250, 0}));
}

TEST(BlocksProgram, SignalBlocksBecomeOAndWOnTheDrivesFreePinsAndReadBack) {
  // The MK2's L298Ns leave A5 (19) alone: a signal there, a wait on it, and both read back.
  const json ops = json::array({
      {{"op", "output"}, {"pin", 19}, {"level", 1}, {"block", "o"}},
      {{"op", "wait_input"}, {"pin", 19}, {"level", 0}, {"seconds", 5}, {"block", "w"}},
  });
  const json out = compile(ops);
  EXPECT_TRUE(out["problems"].empty()) << out.dump();
  const std::vector<std::string> lines = lines_of(out["text"]);
  ASSERT_EQ(lines.size(), 3u) << out.dump();
  EXPECT_EQ(lines[1], "O 19 1");
  EXPECT_EQ(lines[2], "W 19 0 5");
  EXPECT_EQ(out["lines"][1], "o");
  EXPECT_EQ(out["lines"][2], "w");
  const json back = program_actions_json(mk2(), out["text"], "signals.arm");
  ASSERT_EQ(back["ops"].size(), 3u) << back.dump();
  EXPECT_EQ(back["ops"][1], json({{"op", "output"}, {"pin", 19.0}, {"level", 1.0}}));
  EXPECT_EQ(back["ops"][2], json({{"op", "wait_input"}, {"pin", 19.0}, {"level", 0.0}, {"seconds", 5.0}}));

  // A pin the motors use, a level that is neither, a wait too long: each a problem on its block.
  const json bad = compile(json::array({
      {{"op", "output"}, {"pin", 4}, {"level", 1}, {"block", "d4"}},
      {{"op", "output"}, {"pin", 19}, {"level", 2}, {"block", "two"}},
      {{"op", "wait_input"}, {"pin", 19}, {"level", 1}, {"seconds", 700}, {"block", "long"}},
  }));
  ASSERT_EQ(bad["problems"].size(), 3u) << bad.dump();
  EXPECT_EQ(bad["problems"][0]["block"], "d4");
  EXPECT_EQ(bad["problems"][0]["message"], "MK2 Plus's board leaves A5 for signals, not D4");
  EXPECT_EQ(bad["problems"][1]["message"], "a pin is high (1) or low (0), not 2");
  EXPECT_EQ(bad["problems"][2]["message"], "a wait for a signal lasts 0 to 600 seconds, not 700");
}
