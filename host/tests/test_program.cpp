// Tests host/lib/program.cpp: the RoboSim language (thesis appendix B) and protocol
// programs, valid forms and every error with its line, and format detection.
#include <gtest/gtest.h>

#include <fstream>

#include "program.h"
#include "robot_file.h"
#include "test_robots.h"

using namespace articula::host;
using Kind = Statement::Kind;

namespace {
// A two-row arm whose first link length RoboSim's `l` may change (100 .. 200 mm).
Robot adjustable() {
  return parse_robot(R"({"name": "adj", "dh": [
      {"a": 0, "alpha": 0, "d": 0, "theta": {"joint": "j1", "min": -90, "max": 90}},
      {"a": {"value": 150, "min": 100, "max": 200}, "alpha": 0, "d": 0, "theta": {"joint": "j2", "min": -90, "max": 90}}]})",
                     "adj.json");
}

std::string error_of(const std::string& text, const Robot& r, bool robosim = true) {
  try {
    if (robosim)
      parse_robosim(text, "prog.robosim", r);
    else
      parse_protocol_program(text, "prog.arm", r);
  } catch (const ProgramError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(RoboSim, EveryCommandOneItemALine) {
  const Program p = parse_robosim(
      "# the thesis's form: a command letter, then each argument on its own line\n"
      "m\n0\n90\n-90\n"
      "A\n235\n0\n213   # comments anywhere\n"
      "w\n1\n1\n0\n"
      "s\n82\n"
      "h\n0.5\n"
      "\n"
      "Z\n1.5\n",
      "demo.robosim", mk2());
  ASSERT_EQ(p.statements.size(), 6u);
  EXPECT_EQ(p.statements[0].kind, Kind::kJoints);
  EXPECT_EQ(p.statements[0].values, (std::vector<double>{0, 90, -90}));
  EXPECT_EQ(p.statements[0].line, 2);
  EXPECT_EQ(p.statements[1].kind, Kind::kTarget);  // upper case accepted
  EXPECT_EQ(p.statements[1].values, (std::vector<double>{235, 0, 213}));
  EXPECT_EQ(p.statements[2].kind, Kind::kWeights);
  EXPECT_EQ(p.statements[3].kind, Kind::kSpeed);
  EXPECT_EQ(p.statements[4].values, (std::vector<double>{0.5}));
  EXPECT_EQ(p.statements[5].kind, Kind::kZoom);
  EXPECT_EQ(p.statements[5].line, 19);
}

TEST(RoboSim, ErrorsNameTheLineAndTheProblem) {
  EXPECT_EQ(error_of("m\n0\n90\n", mk2()), "prog.robosim:1: m (joint value): 3 values expected, 2 given");
  EXPECT_EQ(error_of("m\n0\n90\na\n1\n2\n3\n", mk2()), "prog.robosim:4: m (joint value): 3 values expected, 2 given");
  EXPECT_EQ(error_of("q\n", mk2()), "prog.robosim:1: unknown command 'q' (m, a, l, w, s, h, z)");
  EXPECT_EQ(error_of("m 0 90 -90\n", mk2()),
            "prog.robosim:1: expected a command letter alone on its line (m, a, l, w, s, h, z), got 'm 0 90 -90'");
  EXPECT_EQ(error_of("s\nfast\n", mk2()), "prog.robosim:2: s (speed): expected one number, got 'fast'");
  EXPECT_EQ(error_of("s\n83\n", mk2()), "prog.robosim:2: speed 83 is outside 1 .. 82");
  EXPECT_EQ(error_of("h\n0.6\n", mk2()), "prog.robosim:2: hand aperture 0.6 is outside 0 .. 0.5");
  EXPECT_EQ(error_of("z\n4\n", mk2()), "prog.robosim:2: zoom 4 is outside 0.1 .. 3.5");
  EXPECT_EQ(error_of("m\n0\n20\n-90\n", mk2()), "prog.robosim:3: joint shoulder 20 is outside 36 .. 130");
  EXPECT_EQ(error_of("w\n1\n0.5\n1\n", mk2()), "prog.robosim:3: w: weights are whole numbers >= 0, got 0.5");
  EXPECT_EQ(error_of("a\n1\nnan\n3\n", mk2()), "prog.robosim:3: a (target coordinate): expected one number, got 'nan'");
  EXPECT_NE(error_of("l\n100\n", mk2()).find("MK2 Plus has no link with an allowed length range"), std::string::npos);
}

TEST(RoboSim, LinkLengthsWithinTheirRange) {
  const Robot r = adjustable();
  ASSERT_EQ(r.length_ranges.size(), 2u);
  EXPECT_TRUE(r.length_ranges[1].adjustable);
  EXPECT_EQ(r.model.rows[1].a, 150);
  const Program p = parse_robosim("l\n120\n", "l.robosim", r);
  EXPECT_EQ(p.statements[0].values, std::vector<double>{120});
  EXPECT_EQ(error_of("l\n99\n", r), "prog.robosim:2: link length 99 is outside 100 .. 200");
}

TEST(RoboSim, LoaderChecksAdjustableLengths) {
  auto load_error = [](const std::string& a) {
    try {
      parse_robot(R"({"name": "x", "dh": [{"a": )" + a + R"(, "alpha": 0, "d": 0, "theta": {"joint": "j", "min": 0, "max": 1}}]})",
                  "x.json");
    } catch (const RobotFileError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(load_error(R"({"value": 50, "min": 100, "max": 200})"), "x.json: /dh/0/a/value: 50 mm is outside its range 100 .. 200");
  EXPECT_EQ(load_error(R"({"value": 150, "min": 200, "max": 100})"), "x.json: /dh/0/a/min: limits inverted (min 200 > max 100)");
  EXPECT_EQ(load_error(R"({"value": 150, "min": 100})"), "x.json: /dh/0/a/max: missing required field \"max\"");
  EXPECT_EQ(load_error(R"({"value": -1, "min": -2, "max": 0})"), "x.json: /dh/0/a/value: negative length (-1 mm)");
}

TEST(ProtocolProgram, EveryLineCheckedBeforeAnythingRuns) {
  const Program p = parse_protocol_program("# a program in the arm's own protocol\nL 0 10\r\n\nS 1\nM 0 90 0 # home\n",
                                           "moves.arm", mk2());
  ASSERT_EQ(p.statements.size(), 3u);
  EXPECT_EQ(p.statements[0].text, "L 0 10");
  EXPECT_EQ(p.statements[0].line, 2);
  EXPECT_EQ(p.statements[2].text, "M 0 90 0 # home");
  EXPECT_EQ(p.statements[2].line, 5);
  // each refusal says why in a beginner's words (explain_line_error)
  EXPECT_EQ(error_of("L 0 10\nL 5 1\n", mk2(), false),
            "prog.arm:2: 'L 5 1': error:6 no such joint: the joints are numbered 0 to 2 (base, shoulder, elbow)");
  EXPECT_EQ(error_of("M 0 90\n", mk2(), false),
            "prog.arm:1: 'M 0 90': error:4 missing argument: M takes 3 values, one angle in degrees for each motor "
            "(base, shoulder, elbow); this line gives 2");
  EXPECT_EQ(error_of("M 0 90 0 1\n", mk2(), false),
            "prog.arm:1: 'M 0 90 0 1': error:5 too many arguments: M takes 3 values, one angle in degrees for each motor "
            "(base, shoulder, elbow); this line gives 4");
  EXPECT_EQ(error_of("L 0 ten\n", mk2(), false),
            "prog.arm:1: 'L 0 ten': error:3 bad number (expected digits with optional sign and decimal point): 'ten' is "
            "not a number: write digits, like 10 or -2.5");
  EXPECT_EQ(error_of("X\n", mk2(), false),
            "prog.arm:1: 'X': error:2 unknown command: 'X' is not a command: a line starts with L, M, P, T, G, S, D, O, W, "
            "H, Z, I or $ (docs/protocol.md)");
  // O and W: the pins this arm's board leaves free, named (the MK2 on L298Ns: A5 alone)
  EXPECT_EQ(error_of("O 20 1\n", mk2(), false),
            "prog.arm:1: 'O 20 1': error:20 no such pin, or one the arm's drive uses (O, W: D0..D13 are 0..13, A0..A5 "
            "14..19): O and W take a pin this arm's board leaves free: A5 (D0..D13 are 0..13, A0..A5 14..19)");
  EXPECT_EQ(error_of("W 19 1\n", mk2(), false),
            "prog.arm:1: 'W 19 1': error:4 missing argument: W takes 3 values: a pin (D0..D13 are 0..13, A0..A5 "
            "14..19), the level to wait for (1 or 0) and the seconds at most, 0 to 600; this line gives 2");
  EXPECT_EQ(error_of("L 0 " + std::string(70, '1') + "\n", mk2(), false), "prog.arm:1: line longer than 64 bytes (error:7)");
}

TEST(Programs, FormatDetection) {
  using F = Program::Format;
  EXPECT_EQ(detect_format("L 0 10\n", "x.robosim"), F::kRoboSim);  // the name decides first
  EXPECT_EQ(detect_format("m\n1\n", "x.arm"), F::kProtocol);
  EXPECT_EQ(detect_format("# hi\nm\n0\n", "x"), F::kRoboSim);
  EXPECT_EQ(detect_format("\nL 0 10\n", "x"), F::kProtocol);
  EXPECT_EQ(detect_format("H\n", "x"), F::kProtocol);  // the protocol's home, not RoboSim's hand
  EXPECT_EQ(detect_format("s\n10\n", "x"), F::kRoboSim);
}

TEST(Programs, LoadProgramReadsFilesAndNamesMissingOnes) {
  const std::string path = testing::TempDir() + "/p.file";
  std::ofstream(path) << "m\n0\n90\n-90\n";
  const Program p = load_program(path, mk2());
  EXPECT_EQ(p.format, Program::Format::kRoboSim);
  EXPECT_EQ(p.statements.size(), 1u);
  try {
    load_program(testing::TempDir() + "/nope.arm", mk2());
    FAIL() << "no error";
  } catch (const ProgramError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.arm:0: cannot read the file"), std::string::npos);
  }
}

TEST(ProgramFit, AProgramForAnotherArmIsToldFromABrokenOne) {
  // fits
  const ProgramFit ok = program_fit("M 0 90 -90\nG 100\n", "p.arm", mk2());
  EXPECT_TRUE(ok.fits);
  EXPECT_FALSE(ok.other_arm);
  // written for a six-motor arm (error:5, too many values), a joint the MK2 has not (error:6),
  // RoboSim's m with six values: another arm's, not broken
  for (const auto& [text, name] : std::vector<std::pair<std::string, std::string>>{
           {"M 0 0 0 0 0 0\n", "six.arm"}, {"L 5 10\n", "j5.arm"}, {"m\n0\n0\n0\n0\n0\n0\na\n1\n2\n3\n", "six.robosim"}}) {
    const ProgramFit f = program_fit(text, name, adjustable());
    EXPECT_FALSE(f.fits) << name;
    EXPECT_TRUE(f.other_arm) << name << ": " << f.problem;
  }
  // broken for every arm: a bad number, an unknown letter, a RoboSim a with two values
  for (const auto& [text, name] : std::vector<std::pair<std::string, std::string>>{
           {"L 0 ten\n", "bad.arm"}, {"Q 1\n", "q.arm"}, {"a\n1\n2\n", "a.robosim"}}) {
    const ProgramFit f = program_fit(text, name, mk2());
    EXPECT_FALSE(f.fits) << name;
    EXPECT_FALSE(f.other_arm) << name << ": " << f.problem;
    EXPECT_EQ(f.line, 1) << name;  // (a RoboSim statement short of values: its letter's line)
    EXPECT_NE(f.problem.find(name), std::string::npos) << f.problem;
  }
}

// A student mends every line at once: a protocol program is read to its end, and the error
// names each line that cannot be read, in order (the first as line()).
TEST(Programs, AProtocolProgramsErrorNamesEveryLineThatCannotBeRead) {
  try {
    parse_protocol_program("M 0 90 -90\nL 7 3\nG 50\nQ 1\n# fine\nM 0 90\n", "p.arm", mk2());
    FAIL() << "no error";
  } catch (const ProgramError& e) {
    ASSERT_EQ(e.problems().size(), 3u);
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.problems()[0].line, 2);
    EXPECT_EQ(e.problems()[1].line, 4);
    EXPECT_EQ(e.problems()[2].line, 6);
    EXPECT_TRUE(e.problems()[0].other_arm);  // error:6, a joint the MK2 has not
    EXPECT_NE(e.problems()[1].problem.find("'Q 1': error:2"), std::string::npos) << e.problems()[1].problem;
    const std::string what = e.what();
    EXPECT_EQ(what.substr(0, what.find('\n')), "p.arm:2: " + e.problems()[0].problem);
    EXPECT_NE(what.find("\np.arm:4: 'Q 1'"), std::string::npos) << what;
    EXPECT_NE(what.find("\np.arm:6: 'M 0 90'"), std::string::npos) << what;
  }
  // one bad line: the message is that line's alone, as before
  EXPECT_EQ(error_of("M 0 90 -90\nQ 1\n", mk2(), false).find('\n'), std::string::npos);
}
