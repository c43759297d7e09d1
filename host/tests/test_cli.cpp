// Tests the `articula` command line end to end: exit codes, error messages, and the
// figures of info, fk and quantize against values computed here by hand.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Result {
  int code;
  std::string out;  // stdout and stderr together
};

// Runs the CLI; stdout and stderr together, or stdout only (stderr discarded).
Result run(const std::string& args, bool with_stderr = true) {
  const std::string cmd = std::string(ARTICULA_CLI) + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null");
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

Result run_stdout(const std::string& args) { return run(args, false); }

}  // namespace

TEST(Cli, NoArgumentsPrintsUsageAndFails) {
  const Result r = run("");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("usage: articula <command>"), std::string::npos) << r.out;
}

TEST(Cli, HelpListsEveryCommand) {
  const Result r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"info", "fk", "quantize", "import-legacy", "configure", "draw"}) EXPECT_NE(r.out.find(c), std::string::npos) << c;
}

TEST(Cli, UnknownCommandIsNamed) {
  const Result r = run("bogus");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("unknown command 'bogus'"), std::string::npos) << r.out;
}

TEST(Cli, EveryCommandHasHelp) {
  for (const char* c : {"info", "fk", "quantize", "draw"}) {
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

// ---- predict and run ----

#include <articula/motion.h>

namespace {
std::string program_path(const std::string& name) { return std::string(ARTICULA_SOURCE_DIR) + "/programs/" + name; }

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  FILE* f = std::fopen(path.c_str(), "w");
  std::fputs(text.c_str(), f);
  std::fclose(f);
  return path;
}

// RFC 4180 fields of one CSV line (quotes doubled inside quoted fields).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') out.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else out.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  for (size_t start = 0; start < text.size();) {
    const size_t end = text.find('\n', start);
    out.push_back(text.substr(start, end - start));
    start = end == std::string::npos ? text.size() : end + 1;
  }
  return out;
}
}  // namespace

TEST(Cli, HelpListsPredictAndRun) {
  const Result r = run("--help");
  for (const char* c : {"predict", "run"}) EXPECT_NE(r.out.find(std::string("  ") + c + " "), std::string::npos) << c;
  for (const char* c : {"predict", "run"}) {
    const Result h = run(std::string(c) + " --help");
    EXPECT_EQ(h.code, 0) << c;
    EXPECT_NE(h.out.find("ROBOT PROGRAM"), std::string::npos) << h.out;
  }
}

TEST(Cli, PredictDemoTableAndSummary) {
  const Result r = run("predict mk2plus " + program_path("demo.arm"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("10 commands, 0 rejected, worst quantization error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("L 0 30"), std::string::npos);
  EXPECT_EQ(r.out.find("# base"), std::string::npos) << "comments are not part of the command column";
  EXPECT_NE(r.out.find("95 0 0"), std::string::npos) << r.out;  // 30 deg / 0.31667 = 94.7 -> 95 steps
}

TEST(Cli, PredictJsonIsOneDocument) {
  const Result r = run_stdout("predict mk2plus " + program_path("demo.arm") + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["records"].size(), 10u);
  EXPECT_EQ(j["settings"]["$0"], 600);
  const auto& l0 = j["records"][1];
  EXPECT_EQ(l0["command"], "L 0 30");
  EXPECT_EQ(l0["steps"], nlohmann::json::array({95, 0, 0}));
  EXPECT_NEAR(l0["joints"][0].get<double>(), 95 * 360.0 * 19 / (200 * 108), 1e-9);
  // The default settings ($0 600 steps/s, $1 2000 steps/s^2) at 2 MHz.
  const articula::MotionSettings defaults = {2000000, 600, 2000};
  EXPECT_EQ(l0["ticks"].get<uint64_t>(), articula::profile_duration_ticks(95, defaults));
  double end = 0;
  for (const auto& rec : j["records"]) {
    EXPECT_NEAR(rec["start_s"].get<double>(), end, 1e-12);
    end = rec["end_s"].get<double>();
  }
  EXPECT_NEAR(j["summary"]["total_s"].get<double>(), end, 1e-12);
  EXPECT_EQ(j["summary"]["rejected"], 0);
}

// One arm of a cell: its waits end as the other arm's outputs change (alone, each of the
// right arm's waits would run out after its 30 s), and the wrong arm or option is named.
TEST(Cli, PredictOneArmOfACell) {
  const Result r = run_stdout("predict shared-zone right --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_GE(j["records"].size(), 3u);
  int waits = 0;
  for (const auto& rec : j["records"])
    if (rec["command"].get<std::string>()[0] == 'W') {
      ++waits;
      EXPECT_LT(rec["seconds"].get<double>(), 29.0) << rec["command"];
      EXPECT_NE(rec["note"].get<std::string>().find("a wire drives"), std::string::npos) << rec["note"];
    }
  EXPECT_GE(waits, 1);
  const Result text = run("predict shared-zone right");
  EXPECT_EQ(text.code, 0) << text.out;
  EXPECT_NE(text.out.find("rejected, worst quantization error"), std::string::npos) << text.out;
  const Result no_arm = run("predict shared-zone middle");
  EXPECT_EQ(no_arm.code, 2);
  EXPECT_NE(no_arm.out.find("the cell \"Shared zone\" has no arm \"middle\" (its arms: left, right)"), std::string::npos)
      << no_arm.out;
  const Result none = run("predict shared-zone");
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.out.find("name the arm of Shared zone to predict (its arms: left, right)"), std::string::npos) << none.out;
  const Result stream = run("predict shared-zone left --sender stream");
  EXPECT_EQ(stream.code, 2);
  EXPECT_NE(stream.out.find("--sender"), std::string::npos) << stream.out;
}

TEST(Cli, PredictAStraightLineWithThePathAtEveryStep) {
  // T: the text says how far the tool strays from the line; --json --path gives the tool after
  // every step of each move, the straight line's worst distance the largest of them.
  const std::string p = write_temp("line.arm", "P 300 -100 150\nT 300 100 150 50\nT 250 0 100 50\n");
  const Result text = run("predict mk2plus " + p);
  EXPECT_EQ(text.code, 1) << text.out;  // the last line is refused
  EXPECT_NE(text.out.find("the tool at every step stays within"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("cannot be reached at"), std::string::npos) << text.out;
  const Result r = run_stdout("predict mk2plus " + p + " --json --path");
  const auto j = nlohmann::json::parse(r.out);
  const auto& line = j["records"][1];
  ASSERT_EQ(line["reply"], "ok");
  EXPECT_EQ(line["path_mm"].size(), line["dominant_steps"].get<size_t>());
  EXPECT_EQ(j["records"][0]["path_mm"].size(), j["records"][0]["dominant_steps"].get<size_t>());
  EXPECT_GT(line["segments"].size(), 3u);
  const double ax = 300, ay = -100, bx = 300, by = 100;  // the line, at z 150 (from P's ideal tool)
  double worst = 0;
  for (const auto& q : line["path_mm"]) {
    const double x = q[0], y = q[1], z = q[2];
    const double t = std::clamp(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)), 0.0, 1.0);
    worst = std::max(worst, std::hypot(x - (ax + t * (bx - ax)), y - (ay + t * (by - ay)), z - 150));
  }
  EXPECT_NEAR(worst, line["line_error_mm"].get<double>(), 0.01);
  EXPECT_EQ(run("predict mk2plus " + p + " --path").code, 2);  // --path needs --json
}

TEST(Cli, PredictCsvHasAHeaderAndOneRowPerCommand) {
  const Result r = run_stdout("predict mk2plus " + program_path("demo.arm") + " --csv");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::vector<std::string> lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 11u);
  const std::vector<std::string> head = csv_fields(lines[0]);
  EXPECT_EQ(head[0], "line");
  EXPECT_EQ(head[1], "command");
  for (size_t i = 1; i < lines.size(); ++i) EXPECT_EQ(csv_fields(lines[i]).size(), head.size()) << lines[i];
  // The row of "L 0 0.1": a comment-free command and a note with a comma, quoted.
  const std::vector<std::string> row = csv_fields(lines[9]);
  EXPECT_EQ(row[1], "L 0 0.1");
  EXPECT_NE(row.back().find("nothing is queued"), std::string::npos) << lines[9];
}

TEST(Cli, PredictSettingsAreHonoured) {
  const auto total = [](const std::string& extra) {
    const Result r = run_stdout("predict mk2plus " + program_path("demo.arm") + " --json" + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    return nlohmann::json::parse(r.out);
  };
  const auto slow = total("");
  const auto fast = total(" --settings 0=800,1=3000,5=100");
  EXPECT_EQ(fast["settings"]["$0"], 800);
  EXPECT_EQ(fast["settings"]["$5"], 100);
  EXPECT_LT(fast["summary"]["total_s"].get<double>(), slow["summary"]["total_s"].get<double>());
  EXPECT_EQ(fast["records"][0]["ticks"], 100 * 2000);  // G: the settle time
  const Result bad = run("predict mk2plus " + program_path("demo.arm") + " --settings 0=9000");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("--settings: '0=9000': $0 takes a whole number from 1 to 4000"), std::string::npos) << bad.out;
  const Result unknown = run("predict mk2plus " + program_path("demo.arm") + " --settings 8=1");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.out.find("no such setting"), std::string::npos) << unknown.out;
}

TEST(Cli, PredictRejectedCommandsExitOne) {
  const std::string p = write_temp("rejected.arm", "L 0 10\nL 1 50   # past the shoulder's limit\nL 0 -10\n");
  const Result r = run("predict mk2plus " + p);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("error:9"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("line 2: target beyond a joint limit, nothing changes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 commands, 1 rejected"), std::string::npos) << r.out;
}

TEST(Cli, PredictAndRunErrorsAreClear) {
  for (const char* cmd : {"predict", "run"}) {
    const std::string c = cmd;
    Result r = run(c + " mk2plus /no/such/program.arm");
    EXPECT_EQ(r.code, 2) << c;
    EXPECT_NE(r.out.find("articula " + c + ": cannot read the program file '/no/such/program.arm'"), std::string::npos)
        << r.out;
    r = run(c + " mk2plus");
    EXPECT_EQ(r.code, 2) << c;
    EXPECT_NE(r.out.find("no program given"), std::string::npos) << r.out;
    const std::string bad = write_temp("bad.arm", "L 0 10\n# fine\nL 0 1e3\n");
    r = run(c + " mk2plus " + bad);
    EXPECT_EQ(r.code, 2) << c;
    EXPECT_NE(r.out.find("bad.arm:3: 'L 0 1e3': error:3"), std::string::npos) << r.out;
    const std::string bad_robosim = write_temp("bad.robosim", "m\n0\n90\n-90\na\n200\n");
    r = run(c + " mk2plus " + bad_robosim);
    EXPECT_EQ(r.code, 2) << c;
    EXPECT_NE(r.out.find("bad.robosim:5: a (target coordinate): 3 values expected, 1 given"), std::string::npos)
        << r.out;
    r = run(c + " mk2plus " + program_path("demo.arm") + " --json --csv");
    EXPECT_EQ(r.code, 2) << c;
  }
  const Result r = run("predict thesis-example " + program_path("robosim-example.robosim"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("has no motors"), std::string::npos) << r.out;
}

TEST(Cli, RunPrintsThePoseAfterEachCommand) {
  Result r = run("run mk2plus " + program_path("robosim-example.robosim"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("reached"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("14 commands, 0 rejected"), std::string::npos) << r.out;
  r = run_stdout("run mk2plus " + program_path("demo.arm") + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["records"].size(), 10u);
  // L 0 30 on the exact model: the base at exactly 30 deg, the tool at radius 235 mm.
  EXPECT_DOUBLE_EQ(j["records"][1]["joints"][0].get<double>(), 30);
  EXPECT_NEAR(j["records"][1]["tool"]["position"][1].get<double>(), 235 * std::sin(M_PI / 6), 1e-9);
  EXPECT_EQ(j["records"][6]["ik_status"], "reached");  // P 200 -150 150
}

TEST(Cli, RunSavesToAFile) {
  const std::string out = testing::TempDir() + "/run.csv";
  std::remove(out.c_str());
  const Result r = run("run mk2plus " + program_path("thesis-repeatability.arm") + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(r.out.empty()) << r.out;
  std::FILE* f = std::fopen(out.c_str(), "r");
  ASSERT_NE(f, nullptr);
  std::string text;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) text.append(buf, n);
  std::fclose(f);
  const std::vector<std::string> lines = lines_of(text);
  ASSERT_EQ(lines.size(), 7u);  // a header and six commands: CSV from the file's extension
  const std::vector<std::string> head = csv_fields(lines[0]);
  EXPECT_EQ(head[4], "base_deg");
  for (size_t i = 1; i < lines.size(); ++i) EXPECT_EQ(csv_fields(lines[i]).size(), head.size()) << lines[i];
}

TEST(Cli, RunWorksWithoutMotors) {
  const std::string p = write_temp("thesis.robosim", "m\n0\n0\n10\n0\n20\n0\n30\n0\nz\n1.5\n");
  const Result r = run("run thesis-example " + p);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("2 commands, 0 rejected"), std::string::npos) << r.out;
}

TEST(Cli, IkReachesAPointAndSaysWhyNot) {
  // The tool at home is (235, 0, 213): IK from another pose finds it again.
  const Result r = run_stdout("ik mk2plus --target 235,0,213 --from 20,60,-70 --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "reached");
  EXPECT_EQ(j["solver"], "closed");
  EXPECT_LT(j["position_error_mm"].get<double>(), 0.01);
  EXPECT_NEAR(j["q"][1].get<double>(), 90, 1e-6);
  // Far beyond the reach: not reached, exit 1, and the distance it stays away.
  const Result far = run_stdout("ik mk2plus --target 1000,0,100 --json");
  EXPECT_EQ(far.code, 1);
  const auto k = nlohmann::json::parse(far.out);
  EXPECT_NE(k["status"], "reached");
  EXPECT_GT(k["position_error_mm"].get<double>(), 600);
  // The thesis's method on request.
  const auto jt = nlohmann::json::parse(run_stdout("ik mk2plus --target 235,0,213 --solver jt --json").out);
  EXPECT_EQ(jt["solver"], "jt");
}

TEST(Cli, IkBatchPrintsOneJsonLineEach) {
  const std::string file = testing::TempDir() + "/targets.txt";
  std::ofstream(file) << "# x,y,z\n235,0,213\n200,50,150\n\n1000,0,0\n";
  const Result r = run_stdout("ik mk2plus --targets " + file);
  EXPECT_EQ(r.code, 1);  // one of three is out of reach
  std::istringstream in(r.out);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    EXPECT_TRUE(j.contains("solve_us"));
    ++n;
  }
  EXPECT_EQ(n, 3);
}

TEST(Cli, IkErrorPaths) {
  Result r = run("ik mk2plus");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("give either --target or --targets"), std::string::npos) << r.out;
  r = run("ik mk2plus --target 1,2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("x,y,z (mm) or x,y,z,roll,pitch,yaw"), std::string::npos) << r.out;
  r = run("ik mk2plus --target 1,2,3 --solver magic");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("'magic' is not auto, lm, jt or closed"), std::string::npos) << r.out;
  r = run("ik panda --target 1,2,3 --solver closed");
  EXPECT_EQ(r.code, 2) << r.out;
  r = run("ik mk2plus --targets /nonexistent/t.txt");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cannot read /nonexistent/t.txt"), std::string::npos) << r.out;
}

TEST(Cli, ExportUrdfWritesAFileCheckUrdfAccepts) {
  const std::string out = testing::TempDir() + "/mk2.urdf";
  const Result r = run("export-urdf mk2plus -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("note: row 4: a linked parameter of 2 joints"), std::string::npos) << r.out;
  EXPECT_EQ(std::system(("check_urdf " + out + " > /dev/null").c_str()), 0);
  EXPECT_EQ(run("export-urdf").code, 2);
}

TEST(Cli, ConfigurePrintsTheLinesForANano) {
  const Result r = run_stdout("configure mk2plus --dry-run");
  EXPECT_EQ(r.code, 0);
  std::istringstream in(r.out);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 57u) << r.out;  // 54 settings, the name, the commit
  EXPECT_EQ(lines[0], "$100=200.000");
  EXPECT_EQ(lines[lines.size() - 2], "N MK2 Plus");
  EXPECT_EQ(lines.back(), "$199=21232.000");
  // --header: the firmware's built-in configuration, as the repository holds it
  std::ifstream f(std::string(ARTICULA_SOURCE_DIR) + "/firmware/src/builtin_config.h");
  std::stringstream held;
  held << f.rdbuf();
  EXPECT_EQ(run_stdout("configure mk2plus --header").out, held.str());
  // and the build for a CNC shield's: the MK2 on A4988s
  std::ifstream fc(std::string(ARTICULA_SOURCE_DIR) + "/firmware/src/builtin_config_cnc.h");
  std::stringstream held_cnc;
  held_cnc << fc.rdbuf();
  EXPECT_EQ(run_stdout("configure mk2plus-cnc --header").out, held_cnc.str());
  // and the servo build's: the meArm
  std::ifstream fs(std::string(ARTICULA_SOURCE_DIR) + "/firmware/src/builtin_config_servo.h");
  std::stringstream held_servo;
  held_servo << fs.rdbuf();
  EXPECT_EQ(run_stdout("configure mearm --header").out, held_servo.str());
}

TEST(Cli, WiringListsEveryPinOfTheBoardTheFileNames) {
  Result r = run_stdout("wiring mk2plus-cnc");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("on an Arduino Uno on a CNC Shield V3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("firmware: articula-cnc.hex"), std::string::npos) << r.out;
  for (const char* row : {"D2   socket X (A4988)  STEP    base", "D7   socket Z (A4988)  DIR     elbow",
                          "D8   drivers           EN", "A3   gripper servo     signal"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
  r = run_stdout("wiring mk2plus --json");
  ASSERT_EQ(r.code, 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["board"], "nano");
  EXPECT_TRUE(j["given"].get<bool>());
  int inputs = 0;
  for (const auto& w : j["wires"]) inputs += w["signal"].get<std::string>().rfind("IN", 0) == 0;
  EXPECT_EQ(inputs, 12);  // three L298Ns, four inputs each
  // what the wires alone do not say (issue 55, 4): a CNC shield's jumpers for the file's 1/8
  // step and its motor supply; a servo arm's 5 V supply for the stall current and one ground
  r = run_stdout("wiring mk2plus-cnc");
  EXPECT_NE(r.out.find("Each A4988 (base, shoulder and elbow motors): 1/8 step, its microstep jumpers on: MS1 and MS2; its current limit"),
            std::string::npos) << r.out;
  EXPECT_NE(r.out.find("12 to 24 V to its power terminal"), std::string::npos) << r.out;
  // ... and the top rate its 1/8 step needs (issue 55, 5: the page never said $0=4000)
  EXPECT_NE(r.out.find("At 1/8 step a motor turn is 1600 steps: at the firmware's default top rate ($0, 600 steps/s) a turn "
                       "takes 2.7 s. Once the arm is connected, send $0=4000"), std::string::npos) << r.out;
  r = run_stdout("wiring mearm --json");
  const nlohmann::json servo = nlohmann::json::parse(r.out);
  ASSERT_EQ(servo["supply"].size(), 2u);
  EXPECT_EQ(servo["supply"][0].get<std::string>().rfind("The servos' + to a 5 V supply that gives 2.6 A: each of the 4 servos", 0), 0u);
  EXPECT_NE(servo["supply"][1].get<std::string>().find("one common ground"), std::string::npos);
  r = run("wiring panda");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cannot wire Franka Emika Panda: the robot has no motors"), std::string::npos) << r.out;
}

TEST(Cli, ConfigureRefusesWithTheReason) {
  Result r = run("configure thesis-example --dry-run");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cannot configure a Nano for Thesis example"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("has no motors"), std::string::npos) << r.out;
  r = run("configure mk2plus");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("give exactly one of --port DEV, --dry-run and --header"), std::string::npos) << r.out;
  r = run("configure mk2plus --port /nonexistent/tty --wait 0");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cannot open /nonexistent/tty"), std::string::npos) << r.out;
}

TEST(Cli, PredictAStopSentWhileTheArmMoves) {
  // A 60 degree turn as 20 moves, streamed; '!' 0.1 s after the first step (near the top of the
  // ramp): the arm decelerates along its path, so it ends past where it was, short of 60
  // degrees; the line waiting for room then is answered error:15, the queued ones never run,
  // and the lines after it start from where the arm came to rest.
  std::string text = "M 0 90 0\n";
  for (int a = 3; a <= 60; a += 3) text += "M " + std::to_string(a) + " 90 0\n";
  text += "M 0 90 0\n";
  const std::string p = write_temp("stop.arm", text);
  const Result r = run_stdout("predict mk2plus " + p + " --sender stream --stop-at 0.1 --json");
  const auto j = nlohmann::json::parse(r.out);
  const auto& recs = j["records"];
  size_t stop = 0, stopped = 0, dropped = 0;
  for (size_t k = 0; k < recs.size(); ++k) {
    if (recs[k].value("stop", false)) stop = k;
    if (recs[k]["code"] == 15) ++stopped;
    if (recs[k].value("cut", false) && recs[k]["dominant_steps"] == 0) ++dropped;
  }
  ASSERT_GT(stop, 0u) << r.out;
  EXPECT_EQ(recs[stop]["reply"], "none");
  EXPECT_EQ(stopped, 1u);  // the line that waited for room
  EXPECT_GT(dropped, 5u);
  const int rest = recs[stop]["steps"][0];
  EXPECT_GT(rest, 20);
  EXPECT_LT(rest, 189);  // 60 degrees is 189 steps
  EXPECT_EQ(recs[stop]["stop_at_tick"].get<uint64_t>(), j["summary"]["first_step_tick"].get<uint64_t>() + 200000);
  ASSERT_LT(stop + 1, recs.size());
  const auto& next = recs[stop + 1];  // read once the arm is at rest: from the steps reached
  EXPECT_EQ(next["dominant_steps"].get<int>(), std::abs(next["steps"][0].get<int>() - rest));
  EXPECT_EQ(recs[recs.size() - 1]["steps"][0], 0);
  // A bad time is a usage error naming it.
  const Result bad = run("predict mk2plus " + p + " --sender stream --stop-at 0.5,x");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("'x' is not a time"), std::string::npos) << bad.out;
}

TEST(Cli, DrawWritesAProgramThePredictionTakes) {
  const std::string out = testing::TempDir() + "draw-hello.arm";
  const std::string svg = testing::TempDir() + "draw-hello.svg";
  const Result r = run("draw mk2plus --text Hello --width 60 --at 250,0 --z 0 --pen 120 -o " + out + " --svg-out " + svg);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("\"Hello\": 60.0 mm wide, 18.5 mm high, centred at (250.0, 0.0) mm, 7 strokes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reach: the pen reaches all"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("prediction: 58 lines, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("on the paper the pen stays within "), std::string::npos) << r.out;
  std::ifstream f(svg);
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_NE(text.str().find("<g id=\"ideal\""), std::string::npos);
  EXPECT_NE(text.str().find("<g id=\"predicted\""), std::string::npos);
  // the program it wrote, predicted on its own: every line taken
  const Result p = run("predict mk2plus " + out);
  ASSERT_EQ(p.code, 0) << p.out;
  EXPECT_NE(p.out.find("58 commands, 0 rejected"), std::string::npos) << p.out;
}

TEST(Cli, DrawSaysWhichWayToMoveADrawingThatDoesNotFit) {
  Result r = run("draw mk2plus --shape square --width 40 --at 120,0 --z 0 --pen 120 -o /dev/null");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("articula draw: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mm toward +x (away from the base)"), std::string::npos) << r.out;
  r = run("draw mk2plus --text \"H\xC3\xA9llo\" --width 40 --at 250,0 --z 0 --pen 120");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("has no '\xC3\xA9' (U+00E9)"), std::string::npos) << r.out;
  r = run("draw mk2plus --shape square --width 40 --at 250 --z 0");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("--at takes x,y (mm), not 1 numbers"), std::string::npos) << r.out;
  r = run("draw mk2plus --width 40 --at 250,0 --z 0");
  EXPECT_NE(r.out.find("give one of an SVG file, --text and --shape"), std::string::npos) << r.out;
}

// Issue 41: an icon set's invisible frame is not drawn (the plus fills the 60 mm, its two
// strokes only), and a file in which nothing shows is refused by name.
TEST(Cli, DrawWhatAnSvgShowsAndRefuseOneWithNothingVisible) {
  const std::string icon = testing::TempDir() + "plus.svg";
  std::ofstream(icon) << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"24\" height=\"24\" viewBox=\"0 0 24 24\" "
                         "fill=\"none\" stroke=\"currentColor\"><path stroke=\"none\" d=\"M0 0h24v24H0z\" fill=\"none\"/>"
                         "<path d=\"M4 12h16M12 4v16\"/></svg>";
  Result r = run("draw mk2plus " + icon + " --width 60 --at 260,0 --z 0 --pen 120 -o " + testing::TempDir() + "plus.arm");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("plus.svg: 60.0 mm wide, 60.0 mm high, centred at (260.0, 0.0) mm, 2 strokes"), std::string::npos)
      << r.out;
  const std::string hidden = testing::TempDir() + "hidden.svg";
  std::ofstream(hidden) << "<svg xmlns=\"http://www.w3.org/2000/svg\"><style>.f{display:none}</style>"
                           "<rect class=\"f\" width=\"9\" height=\"9\"/><path d=\"M0 0h24\" style=\"stroke:none;fill:none\"/></svg>";
  r = run("draw mk2plus " + hidden + " --width 60 --at 260,0 --z 0 --pen 120");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("hidden.svg: nothing in it shows: its 2 shapes are invisible"), std::string::npos) << r.out;
  // what <defs> keeps: drawn where a <use> shows it, and only there
  const std::string used = testing::TempDir() + "used.svg";
  std::ofstream(used) << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 24 24\"><defs><path id=\"bar\" stroke=\"black\" "
                         "d=\"M2 12 h20\"/><path id=\"far\" stroke=\"black\" d=\"M200 200 h20\"/></defs><use href=\"#bar\"/></svg>";
  r = run("draw mk2plus " + used + " --width 60 --at 260,0 --z 0 --pen 120 -o " + testing::TempDir() + "used.arm");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("used.svg: 60.0 mm wide, 0.0 mm high, centred at (260.0, 0.0) mm, 1 stroke"), std::string::npos) << r.out;
}

TEST(Cli, DrawAnSvgFileAndRefuseAHostileOne) {
  Result r = run(std::string("draw mk2plus ") + ARTICULA_SOURCE_DIR + "/examples/drawings/bicycle.svg --width 50 --at 260,0 --z 0 "
                 "--pen 120 -o " + testing::TempDir() + "bicycle.arm");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("bicycle.svg: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("on the paper the pen stays within "), std::string::npos) << r.out;
  const std::string bad = testing::TempDir() + "hostile.svg";
  std::ofstream(bad) << "<svg xmlns=\"http://www.w3.org/2000/svg\" onload=\"alert(1)\"><path d=\"M0 0 L1 1\"/></svg>";
  r = run("draw mk2plus " + bad + " --width 50 --at 260,0 --z 0 --pen 120");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("has an event handler (onload): a drawing never runs code"), std::string::npos) << r.out;
  r = run("draw mk2plus /nonexistent.svg --width 50 --at 260,0 --z 0");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("cannot read /nonexistent.svg"), std::string::npos) << r.out;
}
