// Tests `articula sim` end to end: the real binary, its outputs, messages and exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {

struct Result {
  int code;
  std::string out;  // stdout
  std::string err;  // stderr
};

Result run(const std::string& args) {
  // One file per process: ctest runs these tests side by side, each in its own process.
  const std::string err_file = testing::TempDir() + "articula_sim_err_" + std::to_string(getpid()) + ".txt";
  const std::string cmd = std::string(ARTICULA_CLI) + " sim " + args + " 2>" + err_file;
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int status = pclose(p);
  std::stringstream ss;
  ss << std::ifstream(err_file).rdbuf();
  std::remove(err_file.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, ss.str()};
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(CliSim, GraspAndLiftCsvAndEvents) {
  const std::string events = testing::TempDir() + "sim_events.jsonl";
  const Result r = run("mk2plus programs/grasp-and-lift.arm --scene grasp-and-lift --sample 100 --events " + events);
  EXPECT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header.substr(0, 47), "t_s,base_deg,shoulder_deg,elbow_deg,tool_x,tool");
  EXPECT_NE(header.find("block_z"), std::string::npos);
  int rows = 0;
  while (std::getline(lines, row)) ++rows;
  EXPECT_GE(rows, 30);  // > 3 s at 100 ms
  std::ifstream ev(events);
  std::string line;
  int grasps = 0, releases = 0;
  while (std::getline(ev, line)) {
    const auto j = nlohmann::json::parse(line);
    grasps += j["kind"] == "grasp";
    releases += j["kind"] == "release";
    EXPECT_TRUE(j.contains("t") && j.contains("line"));
  }
  EXPECT_EQ(grasps, 1);
  EXPECT_EQ(releases, 1);
  EXPECT_NE(r.err.find("x real time"), std::string::npos) << r.err;
}

TEST(CliSim, JsonLinesTrajectory) {
  const Result r = run("mk2plus programs/push.arm --scene push --json --sample 500");
  EXPECT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  double first_y = 0, last_y = 0;
  int n = 0;
  while (std::getline(lines, line)) {
    const auto j = nlohmann::json::parse(line);
    ASSERT_EQ(j["joints"].size(), 3u);
    const double y = j["objects"]["box"]["xyz_mm"][1];
    if (n++ == 0) first_y = y;
    last_y = y;
  }
  EXPECT_GE(n, 6);
  EXPECT_GT(last_y - first_y, 50) << "the box was pushed";
  EXPECT_NE(r.err.find("contact_started: box / finger"), std::string::npos) << r.err;
}

TEST(CliSim, BlockedMotionExitsOne) {
  const Result r = run("mk2plus " + write_temp("self.arm", "M 0 130 -43\n") + " --sample 0");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("self_collision"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("steps_lost"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("off its counted steps"), std::string::npos) << r.err;
}

TEST(CliSim, ErrorsAreOneLineWithExitCodeTwo) {
  const std::string bad = write_temp("bad_scene.json", R"({"objects": [{"type": "box", "size": [1, -2, 3]}]})");
  Result r = run("mk2plus programs/demo.arm --scene " + bad);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "articula sim: " + bad + ": /objects/0/size/1: must be > 0 (got -2) (see: articula sim --help)\n");
  r = run("mk2plus programs/none.arm");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("cannot read the program file"), std::string::npos);
  r = run("mk2plus programs/demo.arm --scene no-such-scene");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no-such-scene.json: file not found"), std::string::npos) << r.err;
  r = run("mk2plus programs/demo.arm --dt 50");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--dt"), std::string::npos);
  r = run("mk2plus");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no program given"), std::string::npos);
  r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--scene"), std::string::npos);
}

}  // namespace
