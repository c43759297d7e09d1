// Tests the `articula` command line end to end: exit codes, error messages, and the
// figures of info, fk and quantize against values computed here by hand.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

struct Result {
  int code;
  std::string out;  // stdout and stderr together
};

Result run(const std::string& args) {
  const std::string cmd = std::string(ARTICULA_CLI) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

Result run_stdout(const std::string& args) { return run(args + " 2>/dev/null"); }

}  // namespace

TEST(Cli, NoArgumentsPrintsUsageAndFails) {
  const Result r = run("");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("usage: articula <command>"), std::string::npos) << r.out;
}

TEST(Cli, HelpListsEveryCommand) {
  const Result r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"info", "fk", "quantize", "import-legacy"}) EXPECT_NE(r.out.find(c), std::string::npos) << c;
}

TEST(Cli, UnknownCommandIsNamed) {
  const Result r = run("bogus");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("unknown command 'bogus'"), std::string::npos) << r.out;
}

TEST(Cli, EveryCommandHasHelp) {
  for (const char* c : {"info", "fk", "quantize"}) {
    const Result r = run(std::string(c) + " --help");
    EXPECT_EQ(r.code, 0) << c;
    EXPECT_NE(r.out.find("ROBOT"), std::string::npos) << c << ": " << r.out;
  }
}

TEST(Cli, InfoShowsTheMk2Table) {
  const Result r = run("info mk2plus");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("135.000"), std::string::npos);
  EXPECT_NE(r.out.find("-shoulder - elbow"), std::string::npos) << r.out;  // the level-keeping row
  // Base resolution 360 * 19 / (200 * 108) deg per full step.
  EXPECT_NE(r.out.find("0.3167"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.7277"), std::string::npos) << r.out;
}

TEST(Cli, InfoJsonIsOneDocument) {
  const Result r = run_stdout("info mk2plus --json");
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["joints"].size(), 3u);
  EXPECT_NEAR(j["motors"][0]["deg_per_step"].get<double>(), 360.0 * 19 / (200 * 108), 1e-12);
  // No pose reaches further than all links in a line (135 + 147 + 88 mm); the pose with the
  // shoulder at its lowest limit (36 deg) and the forearm level reaches 135 cos36 + 147 + 88.
  EXPECT_LE(j["reach"]["horizontal_mm"].get<double>(), 135 + 147 + 88 + 1e-9);
  EXPECT_GT(j["reach"]["horizontal_mm"].get<double>(), 135 * std::cos(36 * M_PI / 180) + 147 + 88 - 5);
}

TEST(Cli, MissingRobotFileIsNamed) {
  const Result r = run("info no_such_robot");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("no_such_robot"), std::string::npos) << r.out;
}

TEST(Cli, FkAtHomeGivesTheToolByHand) {
  // Home: upper arm vertical (135 mm above the 78 mm shoulder), forearm horizontal (147 mm),
  // gripper 88 mm further: tool at (235, 0, 213).
  const Result r = run_stdout("fk mk2plus --q 0,90,-90 --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["tool"]["position"][0].get<double>(), 235, 1e-9);
  EXPECT_NEAR(j["tool"]["position"][1].get<double>(), 0, 1e-9);
  EXPECT_NEAR(j["tool"]["position"][2].get<double>(), 213, 1e-9);
  // The base yaw turns the tool about z: at 30 deg, (235 cos30, 235 sin30, 213).
  const auto k = nlohmann::json::parse(run_stdout("fk mk2plus --q 30,90,-90 --json").out);
  EXPECT_NEAR(k["tool"]["position"][0].get<double>(), 235 * std::cos(M_PI / 6), 1e-9);
  EXPECT_NEAR(k["tool"]["rpy"][2].get<double>(), 30, 1e-9);
}

TEST(Cli, FkRejectsBadJointLists) {
  Result r = run("fk mk2plus --q 1,2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("3 joint variables, 2 values given"), std::string::npos) << r.out;
  r = run("fk mk2plus --q 1,x,3");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("entry 2"), std::string::npos) << r.out;
  r = run("fk mk2plus --q 1,nan,3");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("not a finite number"), std::string::npos) << r.out;
}

TEST(Cli, QuantizeShowsStepsAndTheErrorTheyLeave) {
  const Result r = run_stdout("quantize mk2plus \"L 0 10\" --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  // 10 deg / (360*19/(200*108)) = 31.58 steps -> 32, which is 10.1333 deg.
  const double step = 360.0 * 19 / (200 * 108);
  EXPECT_EQ(j["steps"].get<int>(), 32);
  EXPECT_NEAR(j["reached_deg"].get<double>(), 32 * step, 1e-9);
  // The tool turns about the base axis at radius 235 mm: the chord of the angle error.
  const double err = 2 * 235 * std::sin((32 * step - 10) * M_PI / 180 / 2);
  EXPECT_NEAR(j["tool_error_mm"].get<double>(), err, 1e-9);
}

TEST(Cli, QuantizeRejectsBeyondLimitsAndMovesNothing) {
  // The shoulder starts at 90 deg; +100 would pass its 130 deg limit.
  const Result r = run_stdout("quantize mk2plus \"L 1 100\" \"L 0 10\" \"L 7 1\" --json");
  EXPECT_EQ(r.code, 1);
  std::vector<nlohmann::json> lines;
  size_t start = 0;
  while (start < r.out.size()) {
    const size_t end = r.out.find('\n', start);
    lines.push_back(nlohmann::json::parse(r.out.substr(start, end - start)));
    start = end + 1;
  }
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0]["code"].get<int>(), 9);
  EXPECT_EQ(lines[0]["all_steps"], nlohmann::json::array({0, 0, 0}));
  EXPECT_EQ(lines[1]["all_steps"], nlohmann::json::array({32, 0, 0}));
  EXPECT_EQ(lines[2]["code"].get<int>(), 6);  // no such joint
}

TEST(Cli, QuantizeReportsCommandsItDoesNotSimulate) {
  // M, P, G, H, Z, I and $ are parsed and checked, then reported; they move nothing and do not
  // count as rejected (exit code 0), while their malformed forms are rejected as the firmware
  // would reject them.
  Result r = run_stdout("quantize mk2plus \"M 0 90 0\" \"L 0 10\" \"G 50\" H '$1=5' --json");
  EXPECT_EQ(r.code, 0) << r.out;
  std::vector<nlohmann::json> lines;
  for (size_t start = 0; start < r.out.size();) {
    const size_t end = r.out.find('\n', start);
    lines.push_back(nlohmann::json::parse(r.out.substr(start, end - start)));
    start = end + 1;
  }
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0]["note"], "not simulated by quantize");
  EXPECT_EQ(lines[0]["reply"], "ok");
  EXPECT_EQ(lines[0]["all_steps"], nlohmann::json::array({0, 0, 0}));
  EXPECT_FALSE(lines[1].contains("note"));
  EXPECT_EQ(lines[1]["all_steps"], nlohmann::json::array({32, 0, 0}));
  for (int i : {2, 3, 4}) {
    EXPECT_EQ(lines[i]["note"], "not simulated by quantize") << i;
    EXPECT_EQ(lines[i]["all_steps"], nlohmann::json::array({32, 0, 0})) << i;
  }
  r = run("quantize mk2plus \"M 0 90\" \"G 101\" P");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("3 lines, 3 rejected"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error:4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error:8"), std::string::npos) << r.out;
  r = run("quantize mk2plus \"L 0 1?0\" I");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("2 lines, 0 rejected, 1 not simulated"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("'I': ok, not simulated by quantize"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("10.1333"), std::string::npos) << r.out;  // the '?' dropped: L 0 10, 32 steps
}

TEST(Cli, ImportLegacyWritesALoadableRobotAndListsTheRest) {
  const std::string out = testing::TempDir() + "/imported.json";
  const Result r = run("import-legacy " + std::string(ARTICULA_SOURCE_DIR) +
                       "/docs/examples/thesis-example.legacy.txt --scale 10 -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("have no place in a robot file"), std::string::npos);
  EXPECT_NE(r.out.find("hand model path 'Models/hand1.obj'"), std::string::npos);
  // What it wrote is a robot the other commands take: row 2's a = 6 units = 60 mm.
  const Result info = run_stdout("info " + out + " --json");
  ASSERT_EQ(info.code, 0) << info.out;
  EXPECT_EQ(nlohmann::json::parse(info.out)["dh"][1]["a"], "60.000");
  const Result bad = run("import-legacy " + std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("mk2plus.json:1: set 1 (number of arms)"), std::string::npos) << bad.out;
}
