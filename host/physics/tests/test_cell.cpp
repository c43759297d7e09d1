// Tests host/physics/cell_sim.h and cell_file.h: several arms in one world, each on its own
// firmware; what the cell loader refuses, by name.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "../../tests/mini_schema.h"
#include "cell_file.h"
#include "cell_sim.h"
#include "geometry.h"
#include "predict.h"
#include "program.h"
#include "robot_file.h"

using namespace articula;
using namespace articula::host;
using json = nlohmann::json;

namespace {

const std::string kSrc = ARTICULA_SOURCE_DIR;

std::string cell_error(const json& cell, const std::string& dir = kSrc + "/cells") {
  try {
    parse_cell(cell.dump(), "c.json", dir);
  } catch (const CellError& e) {
    return e.what();
  }
  return "";
}

// A robot file with I/O pins, written where a cell can name it: a shipped robot (the MK2 on a
// CNC shield leaves six pins free) with `io`.
std::string robot_with_io(const std::string& dir, const std::string& name, const json& io,
                          const std::string& robot) {
  json r = json::parse(std::ifstream(kSrc + "/robots/" + robot + ".json"));
  r["io"] = io;
  r["name"] = name;
  const std::string path = dir + "/" + name + ".json";
  std::ofstream(path) << r.dump(2);
  return path;
}

// An arm of a cell, far from the others: `n` arms on a circle 800 mm across.
json arm_on_circle(const std::string& name, const std::string& robot, int i, int n, const json& program) {
  const double a = 2 * M_PI * i / n;
  return {{"name", name},
          {"robot", robot},
          {"base", {{"xyz", {400 * std::cos(a), 400 * std::sin(a), 0}}, {"yaw", a * 180 / M_PI + 180}}},
          {"program", program}};
}

// Each arm's robot and program, for cells of 2, 3 and 4 arms that never meet: the MK2 on L298Ns,
// the meArm on servos, the MK2 on a CNC shield's STEP/DIR drivers, the micro arm on ULN2003s.
const std::vector<std::pair<std::string, json>> kArms = {
    {"mk2plus", {"M 30 70 -20", "G 40", "L 0 -60", "T 250 -80 150 80", "M 0 90 0"}},
    {"mearm", {"M 40 100 -10", "G 0", "M -30 80 10", "G 100"}},
    {"mk2plus-cnc", {"$0=3000", "M -40 110 -10", "P 200 120 160", "M 0 90 0"}},
    {"micro-arm-28byj48", {"L 0 30", "L 1 -20", "M 0 0 0"}},
};

class CellOfN : public ::testing::TestWithParam<int> {};

// With no wire between them, every arm of a cell steps exactly as it does alone: its firmware's
// every step at the same tick as in a cell of that arm alone, and at each of its lines' ends
// the step counts its prediction alone (predict_program, each line at rest) gives, reached at
// that very tick.
TEST_P(CellOfN, EachArmStepsAsItsOwnPredictionAlone) {
  const int n = GetParam();
  json file = {{"name", "cell of " + std::to_string(n)}, {"arms", json::array()}};
  for (int i = 0; i < n; ++i)
    file["arms"].push_back(arm_on_circle("arm" + std::to_string(i), kArms[size_t(i)].first, i, n, kArms[size_t(i)].second));
  const Cell cell = parse_cell(file.dump(), "cell.json", kSrc + "/cells");
  ASSERT_EQ(cell.arms.size(), size_t(n));
  CellSimulation sim(cell);
  for (int i = 0; i < n; ++i) sim.world().driver(i).log_steps(true);
  while (!sim.done()) sim.step();
  for (const SimEvent& e : sim.world().events())
    EXPECT_NE(e.kind, SimEvent::Kind::kCollision) << e.arm << ": " << e.a << " with " << e.b;

  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(cell.arms[size_t(i)].robot.name);
    Cell one = cell;
    one.arms = {cell.arms[size_t(i)]};
    CellSimulation alone(one);
    alone.world().driver(0).log_steps(true);
    while (!alone.done()) alone.step();
    const auto& in_cell = sim.driver(i).step_log();
    const auto& by_itself = alone.driver(0).step_log();
    ASSERT_GT(in_cell.size(), 50u);
    EXPECT_TRUE(in_cell == by_itself) << in_cell.size() << " steps in the cell, " << by_itself.size() << " alone";

    // Against the prediction: the counts at each move's end, and its last step at the tick the
    // prediction ends it (a STEP/DIR build writes its pulses at the step timer's next deadline:
    // the last one up to 1 ms after the move's end, alone as in a cell).
    const Prediction pr = predict_program(cell.arms[size_t(i)].robot, cell.arms[size_t(i)].program);
    const uint64_t staged = arm_drive(cell.arms[size_t(i)].robot) == kDriveStepDir ? uint64_t(kStepTickHz / 1000) : 0;
    std::vector<int32_t> counts(size_t(cell.arms[size_t(i)].robot.actuation.num_motors), 0);
    size_t k = 0;
    int moves = 0;
    for (const PredictRecord& rec : pr.records) {
      ASSERT_EQ(rec.reply, kOk) << rec.text;
      if (rec.action != PredictRecord::Action::kMove || rec.end_tick == 0) continue;
      for (; k < in_cell.size() && in_cell[k].tick <= rec.end_tick + staged; ++k)
        for (size_t m = 0; m < counts.size(); ++m)
          if (in_cell[k].mask & (1u << m)) counts[m] += (in_cell[k].negative & (1u << m)) ? -1 : 1;
      EXPECT_EQ(counts, rec.steps) << "line " << rec.line << " (" << rec.text << ") at tick " << rec.end_tick
                                   << (k < in_cell.size() ? ", the next step at " + std::to_string(in_cell[k].tick) : "");
      ASSERT_GT(k, 0u);
      EXPECT_GE(in_cell[k - 1].tick, rec.end_tick) << "line " << rec.line << ": its last step";
      EXPECT_LE(in_cell[k - 1].tick, rec.end_tick + staged) << "line " << rec.line << ": its last step";
      ++moves;
    }
    EXPECT_GE(moves, 2);
    EXPECT_EQ(sim.arm(i).counted_steps(), pr.records.back().steps);

    // Predicted in the cell, with no wire to the others: as alone, line by line.
    if (!cell.arms[size_t(i)].robot.has_motors) continue;
    const Prediction in = predict_in_cell(cell, cell.arms[size_t(i)].name);
    ASSERT_EQ(in.records.size(), pr.records.size());
    for (size_t r = 0; r < pr.records.size(); ++r) {
      EXPECT_EQ(in.records[r].start_tick, pr.records[r].start_tick) << "line " << pr.records[r].line;
      EXPECT_EQ(in.records[r].end_tick, pr.records[r].end_tick) << "line " << pr.records[r].line;
      EXPECT_EQ(in.records[r].steps, pr.records[r].steps) << "line " << pr.records[r].line;
    }
    EXPECT_EQ(in.total_ticks, pr.total_ticks);
  }
}

INSTANTIATE_TEST_SUITE_P(Arms, CellOfN, ::testing::Values(2, 3, 4));

// Two arms face each other and both reach for the middle: the first step that would put one into
// the other is refused, and the event names both arms and both parts; neither goes through the
// other.
TEST(Cell, ACollisionBetweenArmsNamesBothArmsAndParts) {
  const json file = json::parse(R"({"name": "clash", "arms": [
      {"name": "west", "robot": "mk2plus", "base": {"xyz": [0, 0, 0]}, "program": ["M 0 50 -20"]},
      {"name": "east", "robot": "mk2plus", "base": {"xyz": [560, 0, 0], "yaw": 180}, "program": ["M 0 50 -20"]}]})");
  CellSimulation sim(parse_cell(file.dump(), "clash.json", kSrc + "/cells"));
  while (!sim.done()) sim.step();
  const SimEvent* clash = nullptr;
  for (const SimEvent& e : sim.world().events())
    if (e.kind == SimEvent::Kind::kCollision && !clash) clash = &e;
  ASSERT_NE(clash, nullptr);
  EXPECT_TRUE(clash->arm == "west" || clash->arm == "east") << clash->arm;
  const std::string other = clash->arm == "west" ? "east" : "west";
  EXPECT_EQ(clash->b.rfind(other + ": ", 0), 0u) << clash->b;  // the other arm's part, with its arm's name
  EXPECT_TRUE(clash->a.rfind("link", 0) == 0 || clash->a.rfind("finger", 0) == 0) << clash->a;
  EXPECT_TRUE(clash->has_point);
  // Both ended short of their targets: steps lost, the controller unaware.
  int lost = 0;
  for (int i = 0; i < 2; ++i)
    for (int32_t s : sim.arm(i).lost_steps()) lost += std::abs(s);
  EXPECT_GT(lost, 0);
  // And no part of one is inside the other deeper than the touch tolerance.
  double worst = 0;
  for (const auto& a : sim.arm(0).arm_parts())
    for (const auto& b : sim.arm(1).arm_parts())
      for (dGeomID g = dBodyGetFirstGeom(a.body); g; g = dBodyGetNextGeom(g))
        for (dGeomID h = dBodyGetFirstGeom(b.body); h; h = dBodyGetNextGeom(h)) {
          dContactGeom c[8];
          const int k = dCollide(g, h, 8, c, sizeof(dContactGeom));
          for (int j = 0; j < k; ++j) worst = std::max(worst, c[j].depth * 1000);
        }
  EXPECT_LT(worst, sim.world().options().touch_tolerance_mm + 1.5);
}

// The shipped handover: the giver grasps the block, the taker takes it from the giver's gripper
// and sets it down on its own side; no arm touches the other.
TEST(Cell, TheHandoverPassesTheBlockWithoutACollision) {
  CellSimulation sim(load_cell_file(resolve_cell_path("handover")));
  ASSERT_EQ(sim.num_arms(), 2);
  std::vector<std::string> grasps;
  while (!sim.done()) sim.step();
  for (const SimEvent& e : sim.world().events()) {
    EXPECT_NE(e.kind, SimEvent::Kind::kCollision) << e.arm << " " << e.a << " with " << e.b;
    EXPECT_NE(e.kind, SimEvent::Kind::kRejected) << e.arm << " " << e.a << ": " << e.detail;
    EXPECT_NE(e.kind, SimEvent::Kind::kStepsLost) << e.arm << ": " << e.detail;
    if (e.kind == SimEvent::Kind::kGrasp) grasps.push_back(e.arm);
  }
  EXPECT_EQ(grasps, (std::vector<std::string>{"giver", "taker"}));
  const World& w = sim.world();
  ASSERT_EQ(w.num_objects(), 1);
  EXPECT_EQ(w.object_carrier(0), -1);
  const Transform<double> T = w.object_pose(0);
  EXPECT_GT(T.p.x, 380);   // on the taker's side of the table (its base at x = 590)
  EXPECT_LT(T.p.y, -200);  // where it turned to
  EXPECT_NEAR(T.p.z, 50, 5);  // standing on the table
}

// Two MK2s on CNC shields (their build leaves D12, A0-A2, A4, A5 free), each with an output
// `ready` on A0 and an input `go` on A1, `a.ready` wired to `b.go` and `b.ready` to `a.go`.
Cell wired_pair(const json& program_a, const json& program_b, bool b_first = false) {
  const std::string dir = ::testing::TempDir() + "/cells-wired";
  std::filesystem::create_directories(dir);
  robot_with_io(dir, "mk2-io", json::parse(R"([{"name": "ready", "pin": "A0", "mode": "output"},
                                                {"name": "go", "pin": "A1", "mode": "input_pullup"}])"),
                "mk2plus-cnc");
  json a = {{"name", "a"}, {"robot", "mk2-io.json"}, {"base", {{"xyz", {-300, 0, 0}}}}, {"program", program_a}};
  json b = {{"name", "b"}, {"robot", "mk2-io.json"}, {"base", {{"xyz", {300, 0, 0}}, {"yaw", 180}}}, {"program", program_b}};
  json file = {{"name", "wired"},
               {"arms", b_first ? json::array({b, a}) : json::array({a, b})},
               {"wires", json::parse(R"([{"from": "a.ready", "to": "b.go"}, {"from": "b.ready", "to": "a.go"}])")}};
  return parse_cell(file.dump(), "wired.json", dir);
}

// A wait's end as the firmware makes it: it looks at its pin when it begins and then once a
// millisecond (2,000 ticks), so it ends at the first look at or after the change.
uint64_t first_look(uint64_t began, uint64_t change) {
  const uint64_t ms = kStepTickHz / 1000;
  return change <= began ? began : began + (change - began + ms - 1) / ms * ms;
}

// A handshake: a moves, then signals (ready low) and waits for b's answer; b waits for a's
// signal, moves, answers, and moves on; a moves home once answered. Every wait ends at the first
// look after the other arm's output changed, whichever arm the world steps first.
TEST(Cell, EveryWaitEndsWhenTheOtherArmsOutputChanges) {
  const json pa = {"M 30 80 -10", "O 14 0", "W 15 0 30", "M 0 90 0", "O 14 1"};
  const json pb = {"W 15 0 30", "M -40 100 -20", "O 14 0", "W 15 1 30", "M 0 90 0"};
  std::vector<std::vector<ArmDriver::Signal>> runs[2];
  for (const bool b_first : {false, true}) {
    const Cell cell = wired_pair(pa, pb, b_first);
    CellSimulation sim(cell);
    while (!sim.done()) sim.step();
    EXPECT_EQ(sim.deadlock(), "");
    for (const SimEvent& e : sim.world().events()) {
      EXPECT_NE(e.kind, SimEvent::Kind::kRejected) << e.arm << " " << e.a << ": " << e.detail;
      EXPECT_NE(e.kind, SimEvent::Kind::kCollision) << e.arm << " " << e.a << " with " << e.b;
    }
    const int ia = cell.arm_index("a"), ib = cell.arm_index("b");
    const auto& sa = sim.driver(ia).signals();
    const auto& sb = sim.driver(ib).signals();
    ASSERT_EQ(sa.size(), 3u);  // O, W, O
    ASSERT_EQ(sb.size(), 3u);  // W, O, W
    EXPECT_EQ(sa[0].kind, ArmDriver::Signal::kOutput);
    EXPECT_EQ(sb[0].kind, ArmDriver::Signal::kWait);
    // b waited from the start for a's first signal, a for b's answer, b for a's last.
    const uint64_t a_ready = sa[0].tick, b_ready = sb[1].tick, a_done = sa[2].tick;
    EXPECT_GT(a_ready, kStepTickHz / 2);  // (after a's first move)
    for (const auto* sig : {&sa, &sb})
      for (const ArmDriver::Signal& x : *sig) EXPECT_FALSE(x.waiting()) << "line " << x.line << " never ended";
    EXPECT_EQ(sb[0].end_tick, first_look(sb[0].tick, a_ready)) << "b's first wait";
    EXPECT_EQ(sa[1].end_tick, first_look(sa[1].tick, b_ready)) << "a's wait";
    EXPECT_EQ(sb[2].end_tick, first_look(sb[2].tick, a_done)) << "b's last wait";
    EXPECT_GT(b_ready, sb[0].end_tick + kStepTickHz / 2);  // (after b's move)
    EXPECT_GT(a_done, sa[1].end_tick + kStepTickHz / 2);   // (after a's move home)
    EXPECT_TRUE(sb[0].met && sa[1].met && sb[2].met) << "each wait read its level";
    runs[b_first] = {sa, sb};
  }
  // The same ticks whichever arm comes first in the file (and so is stepped first).
  for (size_t arm = 0; arm < 2; ++arm)
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(runs[0][arm][k].tick, runs[1][arm][k].tick) << arm << " " << k;
      EXPECT_EQ(runs[0][arm][k].end_tick, runs[1][arm][k].end_tick) << arm << " " << k;
    }
}

// Each arm predicted in the cell (predict_in_cell): its records' W lines end, and its O lines
// begin, at the very ticks the cell's simulation gives them; alone, nothing would set its input
// and every W runs out.
TEST(Cell, EachArmIsPredictedInTheCellWithTheOtherArmsSignals) {
  const json pa = {"M 30 80 -10", "O 14 0", "W 15 0 30", "M 0 90 0", "O 14 1"};
  const json pb = {"W 15 0 30", "M -40 100 -20", "O 14 0", "W 15 1 30", "M 0 90 0"};
  const Cell cell = wired_pair(pa, pb);
  CellSimulation sim(cell);
  while (!sim.done()) sim.step();
  for (const std::string name : {"a", "b"}) {
    SCOPED_TRACE(name);
    const int i = cell.arm_index(name);
    const Prediction p = predict_in_cell(cell, name);
    const auto& signals = sim.driver(i).signals();
    ASSERT_EQ(signals.size(), 3u);
    size_t k = 0;
    for (const PredictRecord& r : p.records) {
      EXPECT_EQ(r.reply, kOk) << r.text;
      if (r.text[0] != 'O' && r.text[0] != 'W') continue;
      ASSERT_LT(k, signals.size());
      const ArmDriver::Signal& sig = signals[k++];
      EXPECT_EQ(r.line, sig.line);
      EXPECT_EQ(r.start_tick, sig.tick) << r.text;
      if (sig.kind == ArmDriver::Signal::kWait) {
        EXPECT_EQ(r.end_tick, sig.end_tick) << r.text;
        EXPECT_LT(r.end_tick - r.start_tick, uint64_t(30 * kStepTickHz)) << r.text << ": it ran out";
      }
    }
    EXPECT_EQ(k, signals.size());
    EXPECT_EQ(double(p.total_ticks) / kStepTickHz, sim.driver(i).program_end());
    EXPECT_EQ(sim.arm(i).counted_steps(), p.records.back().steps);
  }
  // Alone, b's first W waits its 30 s out and its program goes on.
  const CellArm& b = cell.arms[size_t(cell.arm_index("b"))];
  const Prediction alone = predict_program(b.robot, b.program);
  EXPECT_EQ(alone.records[0].end_tick - alone.records[0].start_tick, uint64_t(30 * kStepTickHz));
  try {
    predict_in_cell(cell, "c");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "the cell \"wired\" has no arm \"c\" (its arms: a, b)");
  }
}

// Each arm waits for the other before it signals: a deadlock, told in words, until the first
// wait runs out (W:21) and that arm's program goes on: its signal then ends the other's wait.
TEST(Cell, ADeadlockIsToldInWords) {
  const Cell cell = wired_pair({"M 20 80 0", "W 15 0 2", "O 14 0"}, {"W 15 0 4", "O 14 0"});
  CellSimulation sim(cell);
  while (!sim.done()) sim.step();
  EXPECT_EQ(sim.deadlock(), "a waits for `ready` from b (low), which waits for `ready` from a (low)");
  std::vector<double> told;
  for (const SimEvent& e : sim.world().events())
    if (e.kind == SimEvent::Kind::kDeadlock) {
      told.push_back(e.t);
      EXPECT_EQ(e.detail, sim.deadlock());
    }
  const auto& sa = sim.driver(0).signals();
  const auto& sb = sim.driver(1).signals();
  ASSERT_EQ(sa.size(), 2u);  // W (ran out), O
  ASSERT_EQ(sb.size(), 2u);  // W (ended by a's O), O
  ASSERT_EQ(told.size(), 1u);
  EXPECT_NEAR(told[0], double(sa[0].tick) / kStepTickHz, 0.0015);  // (told as a's wait begins)
  EXPECT_EQ(sa[0].end_tick - sa[0].tick, uint64_t(2 * kStepTickHz));  // a's ran out
  EXPECT_EQ(sb[0].end_tick, first_look(sb[0].tick, sa[1].tick));    // and a's O ended b's
  EXPECT_LT(sb[0].end_tick - sb[0].tick, uint64_t(4 * kStepTickHz));
  EXPECT_FALSE(sa[0].met) << "a's wait ran out";
  EXPECT_TRUE(sb[0].met) << "b's read a's signal";

  // The shipped example: the same mistake in the shared zone, told the same way; the left arm's
  // wait runs out and the arms then take their turns without meeting.
  CellSimulation shipped(load_cell_file(resolve_cell_path("shared-zone-deadlock")));
  while (!shipped.done()) shipped.step();
  EXPECT_EQ(shipped.deadlock(), "left waits for `done` from right (low), which waits for `done` from left (low)");
  for (const SimEvent& e : shipped.world().events())
    EXPECT_EQ(e.kind, SimEvent::Kind::kDeadlock) << event_json(e).dump();

  // One arm waits for an arm whose program has ended; one for a pin no wire drives.
  const Cell ended = wired_pair({"M 20 80 0"}, {"W 15 0 5"});
  CellSimulation s2(ended);
  while (!s2.done()) s2.step();
  EXPECT_EQ(s2.deadlock(), "b waits for `ready` from a (low), which has ended its program");
  const Cell loose = wired_pair({"W 16 0 1"}, json::array());
  CellSimulation s3(loose);
  while (!s3.done()) s3.step();
  EXPECT_EQ(s3.deadlock(), "a waits for pin A2 to go low, which no wire drives");
}

// A wait runs out (W:21) after its seconds, and the arm's next lines go on.
TEST(Cell, AWaitThatRunsOutLetsTheArmGoOn) {
  const Cell cell = wired_pair({"W 15 0 0.5", "M 20 80 0"}, json::array());
  CellSimulation sim(cell);
  while (!sim.done()) sim.step();
  EXPECT_EQ(sim.deadlock(), "a waits for `ready` from b (low), which runs no program");
  const auto& s = sim.driver(0).signals();
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].end_tick - s[0].tick, uint64_t(kStepTickHz / 2));
  EXPECT_NEAR(sim.arm(0).joints()[1] * 180 / M_PI, 80, 0.5);  // (the move after it ran)
}

// The shipped shared zone: two wires keep the arms out of each other's way (each enters the
// zone between them only once the other says it is out); the same programs without their O and
// W lines meet there.
TEST(Cell, TheSharedZoneKeepsTheArmsApartAndWithoutItsWiresTheyMeet) {
  const Cell guarded = load_cell_file(resolve_cell_path("shared-zone"));
  ASSERT_EQ(guarded.wires.size(), 2u);
  CellSimulation sim(guarded);
  while (!sim.done()) sim.step();
  int in_zone = 0;
  for (const SimEvent& e : sim.world().events()) ADD_FAILURE() << event_json(e).dump();
  for (int i = 0; i < 2; ++i) {
    const auto& sig = sim.driver(i).signals();
    for (const auto& x : sig) in_zone += x.kind == ArmDriver::Signal::kWait;
    EXPECT_EQ(sim.arm(i).lost_steps(), std::vector<int32_t>(3, 0));
  }
  EXPECT_EQ(in_zone, 3);  // (the left arm waits twice, the right once)
  EXPECT_EQ(sim.deadlock(), "");

  Cell bare = guarded;
  bare.wires.clear();
  for (CellArm& a : bare.arms) {
    Program p;
    for (const Statement& st : a.program.statements)
      if (st.text.empty() || (st.text[0] != 'O' && st.text[0] != 'W')) p.statements.push_back(st);
    ASSERT_EQ(p.statements.size() + (&a == &bare.arms[0] ? 4 : 3), a.program.statements.size());
    a.program = p;
  }
  CellSimulation loose(bare);
  while (!loose.done()) loose.step();
  int collisions = 0;
  for (const SimEvent& e : loose.world().events()) collisions += e.kind == SimEvent::Kind::kCollision;
  EXPECT_GT(collisions, 0);
}

TEST(Cell, ShippedCellsLoadAndRun) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kSrc + "/cells")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "cell.schema.json") continue;
    SCOPED_TRACE(entry.path().string());
    const Cell cell = load_cell_file(entry.path().string());
    EXPECT_GE(cell.arms.size() + cell.devices.size(), 2u);
    CellSimulation sim(cell);
    while (!sim.done()) sim.step();
    for (const SimEvent& e : sim.world().events()) EXPECT_NE(e.kind, SimEvent::Kind::kRejected) << e.arm << " " << e.a;
    ++n;
  }
  EXPECT_GE(n, 2);
}

// The reach bound that lets the world skip arms too far apart to meet is a bound: every corner of
// every box (links and fingers), of a box just inside every capsule and cylinder, and the tool,
// of every shipped robot, at random joint values within their
// limits, lies within it.
TEST(Cell, EveryPartOfEveryArmLiesWithinItsReach) {
  std::mt19937 rng(7);
  for (const auto& entry : std::filesystem::directory_iterator(kSrc + "/robots")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "robot.schema.json") continue;
    const Robot r = load_robot_file(entry.path().string());
    SCOPED_TRACE(r.name);
    Cell one;
    one.name = "one";
    CellArm a;
    a.name = "a";
    a.robot = r;
    one.arms.push_back(a);
    const double reach = CellSimulation(one).arm(0).reach_mm();
    const std::vector<LinkGeometry> links = arm_geometry(r);
    double farthest = 0;
    for (int trial = 0; trial < 300; ++trial) {
      std::vector<double> q(size_t(r.model.num_joints));
      for (int j = 0; j < r.model.num_joints; ++j)
        q[size_t(j)] = std::uniform_real_distribution<double>(r.model.joints[j].lo, r.model.joints[j].hi)(rng);
      HostFrames f;
      forward_kinematics(f, r.model, q.data());
      auto corners = [&](const Transform<double>& T, double x, double y, double z) {
        for (int k = 0; k < 8; ++k) {
          const Vec3<double> p = T * make_vec3((k & 1 ? 0.5 : -0.5) * x, (k & 2 ? 0.5 : -0.5) * y, (k & 4 ? 0.5 : -0.5) * z);
          farthest = std::max(farthest, std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
        }
      };
      for (const LinkGeometry& l : links)
        for (const Shape& s : l.shapes) {
          const Transform<double> T = f.T_base_frame[l.frame] * s.T_frame_shape;
          if (s.type == Shape::Type::kBox) corners(T, s.size[0], s.size[1], s.size[2]);
          if (s.type == Shape::Type::kCapsule || s.type == Shape::Type::kCylinder)  // the box around it
            corners(T, std::sqrt(2.0) * s.size[0], std::sqrt(2.0) * s.size[0], s.size[1]);
        }
      corners(f.T_base_tool, 0, 0, 0);
      if (r.gripper.present)
        for (int side : {1, -1})
          corners(finger_pose(r.gripper, f.T_base_tool, r.gripper.max_opening_mm, side), r.gripper.finger_length_mm,
                  r.gripper.finger_thickness_mm, r.gripper.finger_height_mm);
    }
    EXPECT_LE(farthest, reach);
    EXPECT_GT(farthest, 0.4 * reach);  // a bound, not a wild one
  }
}

// ---- the loader: each bad cell refused by name and place ----

TEST(CellFile, BasesThatOverlapAreRefusedWithBothArms) {
  const json file = json::parse(R"({"name": "x", "arms": [
      {"name": "a", "robot": "mk2plus"},
      {"name": "b", "robot": "mearm", "base": {"xyz": [100, 0, 0]}}]})");
  const std::string e = cell_error(file);
  EXPECT_NE(e.find("c.json: /arms/1/base: the bases of \"b\" and \"a\" overlap"), std::string::npos) << e;
  EXPECT_NE(e.find("100 mm apart"), std::string::npos) << e;
  // The meArm's base plate is 110 x 90 mm: 71 mm to its corners; the MK2's a 50 mm cylinder.
  EXPECT_NEAR(base_footprint_mm(load_robot_file(resolve_robot_path("mearm"))), std::hypot(55.0, 45.0), 1e-9);
  EXPECT_NEAR(base_footprint_mm(load_robot_file(resolve_robot_path("mk2plus"))), 50, 1e-9);
  json apart = file;
  apart["arms"][1]["base"]["xyz"] = {125, 0, 0};  // 50 + 71.1 < 125
  EXPECT_EQ(cell_error(apart), "");
}

TEST(CellFile, WiresAreCheckedAgainstTheArmsPins) {
  const std::string dir = ::testing::TempDir() + "/cells-io";
  std::filesystem::create_directories(dir);
  robot_with_io(dir, "left", json::parse(R"([{"name": "ready", "pin": "D12", "mode": "output"},
                                              {"name": "go", "pin": "A0", "mode": "input_pullup"}])"),
                "mk2plus-cnc");
  robot_with_io(dir, "right", json::parse(R"([{"name": "done", "pin": "D12", "mode": "output"},
                                               {"name": "start", "pin": "A0", "mode": "input"},
                                               {"name": "also", "pin": "A1", "mode": "input"}])"),
                "mk2plus-cnc");
  json file = json::parse(R"({"name": "wired", "arms": [
      {"name": "a", "robot": "left.json"},
      {"name": "b", "robot": "right.json", "base": {"xyz": [400, 0, 0]}}],
      "wires": [{"from": "a.ready", "to": "b.start"}, {"from": "b.done", "to": "a.go"}]})");
  const Cell ok = parse_cell(file.dump(), "wired.json", dir);
  ASSERT_EQ(ok.wires.size(), 2u);
  EXPECT_EQ(ok.wires[0].from_arm, 0);
  EXPECT_EQ(ok.io_name(ok.wires[0].from_arm, ok.wires[0].from_pin), "ready");
  EXPECT_EQ(ok.io_name(ok.wires[0].to_arm, ok.wires[0].to_pin), "start");

  json two_outputs = file;
  two_outputs["wires"][1] = {{"from", "a.ready"}, {"to", "b.done"}};
  EXPECT_NE(cell_error(two_outputs, dir).find("/wires/1: joins two outputs, a.ready and b.done"), std::string::npos)
      << cell_error(two_outputs, dir);
  json via_input = file;  // two outputs joined through an input's net
  via_input["wires"][1] = {{"from", "b.done"}, {"to", "b.start"}};
  EXPECT_NE(cell_error(via_input, dir).find("joins two outputs"), std::string::npos) << cell_error(via_input, dir);
  json no_pin = file;
  no_pin["wires"][0]["to"] = "b.begin";
  EXPECT_EQ(cell_error(no_pin, dir),
            "c.json: /wires/0/to: arm \"b\" has no I/O pin \"begin\" (its pins: done (output), start (input), also (input))");
  json no_arm = file;
  no_arm["wires"][0]["from"] = "c.ready";
  EXPECT_EQ(cell_error(no_arm, dir), "c.json: /wires/0/from: the cell has no arm or device \"c\" (its arms: a, b)");
  json inputs = file;
  inputs["wires"].push_back({{"from", "b.also"}, {"to", "a.go"}});  // fine: a.go's net has b.done
  EXPECT_EQ(cell_error(inputs, dir), "");
  inputs["wires"][2] = {{"from", "b.also"}, {"to", "b.start"}};  // fine too: b.start's net has a.ready
  EXPECT_EQ(cell_error(inputs, dir), "");
  json only_inputs = file;
  only_inputs["wires"] = json::parse(R"([{"from": "b.also", "to": "a.go"}])");
  EXPECT_NE(cell_error(only_inputs, dir).find("/wires/0: joins only inputs"), std::string::npos) << cell_error(only_inputs, dir);
  json bad_end = file;
  bad_end["wires"][0]["from"] = "a";
  EXPECT_NE(cell_error(bad_end, dir).find("/wires/0/from: a wire's end is \"arm.pin\""), std::string::npos);
  json pinless = file;
  pinless["arms"][1]["robot"] = "mearm";
  EXPECT_NE(cell_error(pinless, dir).find("arm \"b\" has no I/O pin \"start\" (its robot, meArm, names none"),
            std::string::npos)
      << cell_error(pinless, dir);
}

TEST(CellFile, EveryOtherMistakeIsRefusedByName) {
  const json good = json::parse(R"({"name": "x", "arms": [{"name": "a", "robot": "mk2plus", "program": ["M 0 80 0"]}]})");
  EXPECT_EQ(cell_error(good), "");
  std::vector<std::tuple<std::string, std::function<void(json&)>, std::string>> cases = {
      {"no arms", [](json& j) { j.erase("arms"); }, "c.json: missing field \"arms\""},
      {"empty arms", [](json& j) { j["arms"] = json::array(); }, "c.json: /arms: must be an array of at least one arm"},
      {"unknown field", [](json& j) { j["robots"] = 1; }, "c.json: /robots: unknown field \"robots\""},
      {"arm field", [](json& j) { j["arms"][0]["colour"] = "red"; }, "c.json: /arms/0/colour: unknown field"},
      {"two names", [](json& j) { j["arms"].push_back(j["arms"][0]); j["arms"][1]["base"] = {{"xyz", {600, 0, 0}}}; },
       "c.json: /arms/1/name: two arms are called \"a\" (/arms/0)"},
      {"bad name", [](json& j) { j["arms"][0]["name"] = "arm 1"; }, "c.json: /arms/0/name: an arm's name is 1 to 16"},
      {"no robot", [](json& j) { j["arms"][0]["robot"] = "robby"; }, "c.json: /arms/0/robot: the robot cannot be used: "},
      {"base xyz", [](json& j) { j["arms"][0]["base"] = {{"xyz", {1, 2}}}; }, "c.json: /arms/0/base/xyz: must be [x, y, z]"},
      {"yaw", [](json& j) { j["arms"][0]["base"] = {{"yaw", "north"}}; }, "c.json: /arms/0/base/yaw: must be a number"},
      {"bad line", [](json& j) { j["arms"][0]["program"] = {"M 0 80 0", "Q 1"}; }, "c.json: /arms/0/program/1: for MK2 Plus: "},
      {"no program file", [](json& j) { j["arms"][0]["program"] = "nowhere.arm"; }, "c.json: /arms/0/program: cannot read the program"},
      {"scene", [](json& j) { j["scene"] = {{"objects", {{{"type", "box"}, {"size", {1, 0, 1}}}}}}; },
       "c.json: /scene/objects/0/size/1: must be > 0"},
      {"scene name", [](json& j) { j["scene"] = "nowhere"; }, "c.json: /scene: "},
      {"io pin not free", [](json& j) { j["arms"][0]["io"] = {{{"name", "go"}, {"pin", "D2"}, {"mode", "input"}}}; },
       "c.json: /arms/0/io: the robot cannot have these I/O pins: "},
      {"io not a list", [](json& j) { j["arms"][0]["io"] = "A0"; }, "c.json: /arms/0/io: the robot cannot have these I/O pins: "},
      {"too many", [](json& j) { for (int i = 0; i < 8; ++i) j["arms"].push_back(j["arms"][0]); },
       "c.json: /arms: at most 8 arms (got 9)"},
  };
  for (auto& [what, change, want] : cases) {
    json doc = good;
    change(doc);
    const std::string e = cell_error(doc);
    EXPECT_EQ(e.rfind(want, 0), 0u) << what << ": " << e;
  }
  EXPECT_NE(cell_error(good).size(), 1u);
  try {
    parse_cell("{\"name\": \"x\",\n \"arms\": [}", "c.json", "");
    ADD_FAILURE() << "no error";
  } catch (const CellError& e) {
    EXPECT_STREQ(e.what(), "c.json: not valid JSON at line 2, column 11");
  }
  Cell cell = parse_cell(good.dump(), "c.json", kSrc + "/cells");
  try {
    set_cell_program(cell, "b", Program{});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "the cell \"x\" has no arm \"b\" (its arms: a)");
  }
}

// The schema and the loader agree: the same fields, the shipped cells valid, what the loader
// refuses for its shape refused by the schema too.
TEST(CellFile, SchemaMatchesTheLoader) {
  const json schema = json::parse(std::ifstream(kSrc + "/cells/cell.schema.json"));
  const auto& fields = cell_file_fields();
  auto keys = [](const json& props) {
    std::set<std::string> out;
    for (const auto& p : props.items()) out.insert(p.key());
    return out;
  };
  EXPECT_EQ(keys(schema["properties"]), std::set<std::string>(fields.at("cell").begin(), fields.at("cell").end()));
  for (const char* kind : {"arm", "base", "wire"})
    EXPECT_EQ(keys(schema["$defs"][kind]["properties"]), std::set<std::string>(fields.at(kind).begin(), fields.at(kind).end()))
        << kind;
  const articula::test::MiniSchema validator(schema);
  for (const auto& entry : std::filesystem::directory_iterator(kSrc + "/cells")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "cell.schema.json") continue;
    const auto errors = validator.errors(json::parse(std::ifstream(entry.path())));
    EXPECT_TRUE(errors.empty()) << entry.path() << ": " << (errors.empty() ? "" : errors[0]);
  }
  const json good = json::parse(R"({"name": "x", "arms": [{"name": "a", "robot": "mk2plus"}]})");
  for (auto change : std::vector<std::function<void(json&)>>{
           [](json& j) { j["arms"][0]["name"] = "arm 1"; }, [](json& j) { j["arms"] = json::array(); },
           [](json& j) { j["wires"] = {{{"from", "a"}, {"to", "b.x"}}}; },
           [](json& j) { j["arms"][0]["base"] = {{"xyz", {1, 2}}}; }, [](json& j) { j.erase("arms"); }}) {
    json doc = good;
    change(doc);
    EXPECT_FALSE(validator.errors(doc).empty()) << doc.dump();
    EXPECT_NE(cell_error(doc), "") << doc.dump();
  }
}

}  // namespace

// A station of the class's lessons (issue 53): a belt the arm runs from an output (through a
// relay), a light barrier across it on an input. The MK2 on a CNC shield leaves D12 and A0 free.
json station(const std::string& dir) {
  robot_with_io(dir, "station-arm", json::parse(R"([{"name": "belt_on", "pin": "D12", "mode": "output"},
                                                     {"name": "part", "pin": "A0", "mode": "input_pullup"}])"),
                "mk2plus-cnc");
  // the belt along the table's y (its own x turned 90 degrees), 600 mm long, its top 10 mm up;
  // the block at its far end; the beam across it at y = 12, 25 mm up
  return json::parse(R"({"name": "station",
    "scene": {"objects": [
      {"name": "belt", "type": "box", "size": [600, 80, 10], "xyz": [600, -250, 5], "rpy": [0, 0, 90], "belt": 100},
      {"name": "block", "type": "box", "size": [24, 24, 40], "xyz": [600, -450, 30], "movable": true, "mass": 0.03}]},
    "arms": [{"name": "a", "robot": "station-arm.json", "program": ["O 12 0", "W 14 0 20", "O 12 1"]}],
    "devices": [{"name": "conveyor", "kind": "belt", "object": "belt"},
                {"name": "gate", "kind": "barrier", "from": [540, 12, 25], "to": [660, 12, 25]}],
    "wires": [{"from": "a.belt_on", "to": "conveyor.run"}, {"from": "gate.beam", "to": "a.part"}]})");
}

TEST(CellDevices, TheArmRunsTheBeltUntilTheBarrierSeesTheBlock) {
  const std::string dir = ::testing::TempDir() + "/cells-station";
  std::filesystem::create_directories(dir);
  const Cell cell = parse_cell(station(dir).dump(), "station.json", dir);
  ASSERT_EQ(cell.devices.size(), 2u);
  ASSERT_EQ(cell.wires.size(), 2u);
  CellSimulation sim(cell);
  const int block = 1;
  // at power-up the arm's D12 is at rest, high: the belt stands until the arm's O 12 0; the
  // beam is clear
  EXPECT_FALSE(sim.belt_running(0));
  EXPECT_TRUE(sim.device_level(1));
  sim.run_until(0.5);
  EXPECT_TRUE(sim.belt_running(0));
  std::vector<std::pair<double, double>> ys;  // (t, the block's y) every 0.1 s
  while (!sim.done() && sim.time() < 15) {
    sim.step();
    if (sim.world().steps_taken() % 100 == 0) ys.emplace_back(sim.time(), sim.world().object_pose(block).p.y);
  }
  ASSERT_TRUE(sim.done());
  // the events: the beam broken by the block, then the belt stands
  double broken_t = -1, stands_t = -1;
  for (const SimEvent& e : sim.world().events()) {
    if (e.kind != SimEvent::Kind::kDevice) continue;
    if (e.a == "gate" && e.detail == "the beam is broken") {
      EXPECT_EQ(e.b, "block");
      if (broken_t < 0) broken_t = e.t;
    }
    if (e.a == "conveyor" && e.detail == "stands" && stands_t < 0) stands_t = e.t;
  }
  ASSERT_GT(broken_t, 0);
  ASSERT_GE(stands_t, broken_t);
  // the W ended at the tick the beam broke: within a physics step and the firmware's 1 ms look
  const auto& sig = sim.driver(0).signals();
  ASSERT_EQ(sig.size(), 3u);
  ASSERT_EQ(sig[1].kind, ArmDriver::Signal::kWait);
  ASSERT_TRUE(sig[1].ended);
  EXPECT_TRUE(sig[1].met) << "the wait read the beam's level";
  const double wait_end = double(sig[1].end_tick) / kStepTickHz;
  EXPECT_GE(wait_end, broken_t - 0.001);
  EXPECT_LE(wait_end, broken_t + 0.002) << "the wait ended " << (wait_end - broken_t) * 1000 << " ms after the beam broke";
  // the block's front face (y + 12) at the beam when it broke it: 450 mm at 100 mm/s, once the
  // belt ran
  double runs_t = -1;
  for (const SimEvent& e : sim.world().events())
    if (e.kind == SimEvent::Kind::kDevice && e.a == "conveyor" && e.detail == "runs" && runs_t < 0) runs_t = e.t;
  ASSERT_GE(runs_t, 0);
  EXPECT_NEAR(broken_t - runs_t, 4.5, 0.3);
  // on the running belt, at its speed (within 5 %, over 2 s)
  auto y_at = [&](double t) {
    for (const auto& p : ys)
      if (p.first >= t - 1e-9) return p.second;
    return ys.back().second;
  };
  const double v = (y_at(3.0) - y_at(1.0)) / 2.0;
  EXPECT_NEAR(v, 100.0, 5.0) << "mm/s on the belt";
  // stopped with it: no creep once the belt stands, on top of it (no sinking)
  EXPECT_LT(std::fabs(y_at(stands_t + 2.0) - y_at(stands_t + 0.3)), 0.5);
  EXPECT_NEAR(sim.world().object_pose(block).p.z, 30.0, 1.0);
  EXPECT_NEAR(sim.world().object_pose(block).p.y, 0.0, 3.0);
  // the state says so
  const json state = cell_state_json(sim);
  ASSERT_EQ(state["devices"].size(), 2u);
  EXPECT_EQ(state["devices"][0]["running"], false);
  EXPECT_EQ(state["devices"][0]["level"], true);
  EXPECT_EQ(state["devices"][1]["broken_by"], "block");
  EXPECT_EQ(state["devices"][1]["level"], false);
}

TEST(CellDevices, WithoutItsRelayTheBlockNeverComesAndTheWaitRunsOut) {
  // the belt runs the wrong way: the block never reaches the beam, and the wait runs out (W:21)
  const std::string dir = ::testing::TempDir() + "/cells-station2";
  std::filesystem::create_directories(dir);
  json file = station(dir);
  file["scene"]["objects"][0]["belt"] = -100;  // the belt runs the other way: the block falls off its end
  file["arms"][0]["program"] = json::parse(R"(["O 12 0", "W 14 0 2", "O 12 1"])");
  CellSimulation sim(parse_cell(file.dump(), "station.json", dir));
  sim.run_until(6);
  bool broken = false;
  for (const SimEvent& e : sim.world().events()) broken = broken || (e.kind == SimEvent::Kind::kDevice && e.a == "gate" && e.detail == "the beam is broken");
  EXPECT_FALSE(broken);
  const auto& sig = sim.driver(0).signals();
  ASSERT_GE(sig.size(), 2u);
  EXPECT_TRUE(sig[1].ended);
  EXPECT_NEAR(double(sig[1].end_tick - sig[1].tick) / kStepTickHz, 2.0, 0.01) << "the W's 2 s";
  EXPECT_FALSE(sig[1].met) << "it ran out";
  EXPECT_LT(sim.world().object_pose(1).p.y, -500);  // carried away from the beam
  EXPECT_TRUE(sim.deadlock().empty()) << "a wait on a barrier is no deadlock: " << sim.deadlock();
}

TEST(CellFile, DevicesAreRefusedByName) {
  const std::string dir = ::testing::TempDir() + "/cells-station3";
  std::filesystem::create_directories(dir);
  const json ok = station(dir);
  EXPECT_EQ(cell_error(ok, dir), "");
  auto with = [&](const std::string& pointer, const json& v) {
    json f = ok;
    f[json::json_pointer(pointer)] = v;
    return cell_error(f, dir);
  };
  EXPECT_EQ(with("/devices/0/object", "block"),
            "c.json: /devices/0/object: the scene has no belt \"block\" (its belts: belt)");
  EXPECT_EQ(with("/devices/0/kind", "relay"), "c.json: /devices/0/kind: must be \"belt\", \"barrier\", \"switch\" or \"feeder\" (got \"relay\")");
  EXPECT_EQ(with("/devices/1/name", "a"), "c.json: /devices/1/name: the cell already has an arm or a device called \"a\"");
  EXPECT_EQ(with("/devices/1/name", "conveyor"),
            "c.json: /devices/1/name: the cell already has an arm or a device called \"conveyor\"");
  EXPECT_EQ(with("/devices/1/name", "<b>x</b>"),
            "c.json: /devices/1/name: a device's name is 1 to 16 letters, digits, _ or -, starting with a letter (got \"<b>x</b>\")");
  EXPECT_EQ(with("/devices/1/to", json::parse("[540, 12, 25]")), "c.json: /devices/1/to: a beam is at least 1 mm long (its ends are 0 mm apart)");
  EXPECT_EQ(with("/devices/1/to/0", nullptr), "c.json: /devices/1/to/0: must be a number");
  EXPECT_EQ(with("/devices/1/object", "belt"), "c.json: /devices/1/object: a barrier has no field \"object\"");
  EXPECT_EQ(with("/wires/0/to", "conveyor.go"), "c.json: /wires/0/to: the belt \"conveyor\" has one pin, \"run\" (got \"go\")");
  EXPECT_EQ(with("/wires/1/to", "conveyor.run"),
            "c.json: /wires/1: joins two outputs, a.belt_on and gate.beam: an output drives a wire, and the other ends must be inputs");
  EXPECT_EQ(with("/wires", json::parse(R"([{"from": "conveyor.run", "to": "a.part"}])")),
            "c.json: /wires/0: joins only inputs (conveyor.run among them): no output drives it");
  // the barrier straight to the belt's relay: it stands while the beam is broken
  EXPECT_EQ(with("/wires", json::parse(R"([{"from": "gate.beam", "to": "conveyor.run"}])")), "");
  json two_belts = ok;
  two_belts["devices"].push_back({{"name", "again"}, {"kind", "belt"}, {"object", "belt"}});
  EXPECT_EQ(cell_error(two_belts, dir), "c.json: /devices/2/object: the belt \"belt\" is already the device \"conveyor\"");
}

// The shipped station (cells/conveyor.json): the belt brings the block to the beam, stands, and
// the MK2 picks the block off it and sets it down beside the belt.
TEST(CellDevices, TheShippedConveyorEndsWithTheBlockPickedOffTheBelt) {
  CellSimulation sim(load_cell_file(kSrc + "/cells/conveyor.json"));
  while (!sim.done()) sim.step();
  int grasps = 0, stands = 0;
  for (const SimEvent& e : sim.world().events()) {
    EXPECT_NE(e.kind, SimEvent::Kind::kCollision) << e.a << " " << e.b;
    EXPECT_NE(e.kind, SimEvent::Kind::kRejected) << e.a;
    grasps += e.kind == SimEvent::Kind::kGrasp;
    stands += e.kind == SimEvent::Kind::kDevice && e.a == "conveyor" && e.detail == "stands";
  }
  EXPECT_EQ(grasps, 1);
  EXPECT_EQ(stands, 1);
  EXPECT_EQ(sim.arm(0).lost_steps(), (std::vector<int32_t>{0, 0, 0}));
  const Vec3<double> p = sim.world().object_pose(1).p;  // off the belt (x 275..335 up to y 150), on the ground
  EXPECT_GT(std::hypot(p.x - 305, std::max(0.0, p.y - 150)), 40) << p.x << " " << p.y;
  EXPECT_LT(p.z, 60);
  EXPECT_TRUE(sim.sensed_by(1).empty()) << "the beam is clear again";
}

// A feeder with no wire puts one out every `every` s at its outlet, waits while the last one
// still stands there, and says when it is empty; its magazine is out of the world until then.
TEST(CellDevices, AFeederPutsOneOutAtATimeWhenItsOutletIsClear) {
  const std::string dir = ::testing::TempDir() + "/cells-feeder";
  std::filesystem::create_directories(dir);
  json file = station(dir);
  file["scene"]["objects"][1]["name"] = "b1";
  file["scene"]["objects"].push_back({{"name", "b2"}, {"type", "box"}, {"size", {24, 24, 40}}, {"xyz", {0, 0, 0}}, {"movable", true}, {"mass", 0.03}});
  file["scene"]["objects"].push_back({{"name", "b3"}, {"type", "box"}, {"size", {24, 24, 40}}, {"xyz", {0, 0, 0}}, {"movable", true}, {"mass", 0.03}});
  // the belt always on (no wire to it), the feeder on its own every 1 s at the belt's far end
  file["devices"] = json::parse(R"([{"name": "conveyor", "kind": "belt", "object": "belt"},
                                    {"name": "feed", "kind": "feeder", "objects": ["b1", "b2", "b3"], "at": [600, -500, 30], "every": 1}])");
  file["wires"] = json::array();
  file["arms"][0]["program"] = json::array();
  CellSimulation sim(parse_cell(file.dump(), "station.json", dir));
  EXPECT_TRUE(sim.world().object_removed(1) && sim.world().object_removed(2) && sim.world().object_removed(3));
  EXPECT_EQ(sim.feeder_left(1), 3);
  sim.run_until(3.5);
  std::vector<std::pair<double, std::string>> put;
  int empty = 0;
  for (const SimEvent& e : sim.world().events())
    if (e.kind == SimEvent::Kind::kDevice && e.a == "feed") {
      if (e.detail == "puts one out") put.emplace_back(e.t, e.b);
      empty += e.detail == "is empty";
    }
  ASSERT_EQ(put.size(), 3u);
  EXPECT_EQ(put[0], (std::pair<double, std::string>{0.0, "b1"}));
  EXPECT_NEAR(put[1].first, 1.0, 1e-9);
  EXPECT_EQ(put[2].second, "b3");
  EXPECT_EQ(empty, 1);
  EXPECT_EQ(sim.feeder_left(1), 0);
  // each rides the belt from the outlet: 100 mm/s, a second apart
  for (int o = 1; o <= 3; ++o) EXPECT_FALSE(sim.world().object_removed(o));
  EXPECT_NEAR(sim.world().object_pose(1).p.y - sim.world().object_pose(2).p.y, 100, 10);
  EXPECT_NEAR(sim.world().object_pose(1).p.z, 30, 1);

  // the belt stands (its relay wired to an arm's output at rest): the first block stays at the
  // outlet, and the feeder waits for it, told once
  json still = file;
  still["wires"] = json::parse(R"([{"from": "a.belt_on", "to": "conveyor.run"}])");
  CellSimulation held(parse_cell(still.dump(), "station.json", dir));
  held.run_until(3.5);
  int out = 0, waits = 0;
  for (const SimEvent& e : held.world().events()) {
    out += e.kind == SimEvent::Kind::kDevice && e.detail == "puts one out";
    waits += e.kind == SimEvent::Kind::kDevice && e.detail == "waits: its outlet is taken";
  }
  EXPECT_EQ(out, 1);
  EXPECT_EQ(waits, 1);
  EXPECT_TRUE(held.world().object_removed(2));
  EXPECT_EQ(held.feeder_left(1), 2);
}

// The shipped station (cells/station.json): the arm asks the feeder for each of three blocks,
// the belt brings it to the barrier, and the arm puts it into the bin: all three in it.
TEST(CellDevices, TheShippedStationPutsThreeBlocksIntoTheBin) {
  CellSimulation sim(load_cell_file(kSrc + "/cells/station.json"));
  while (!sim.done()) sim.step();
  int grasps = 0;
  for (const SimEvent& e : sim.world().events()) {
    EXPECT_NE(e.kind, SimEvent::Kind::kCollision) << e.a << " " << e.b;
    EXPECT_NE(e.kind, SimEvent::Kind::kRejected) << e.a;
    grasps += e.kind == SimEvent::Kind::kGrasp;
  }
  EXPECT_EQ(grasps, 3);
  const World& w = sim.world();
  for (int i = 0; i < w.num_objects(); ++i) {
    if (w.object(i).name.rfind("block", 0) != 0) continue;
    const Vec3<double> p = w.object_pose(i).p;  // inside the bin's walls (x 138..262, y 114..246)
    EXPECT_TRUE(p.x > 138 && p.x < 262 && p.y > 114 && p.y < 246 && p.z < 60) << w.object(i).name << " " << p.x << " " << p.y << " " << p.z;
  }
}

TEST(CellFile, FeedersAreRefusedByName) {
  const std::string dir = ::testing::TempDir() + "/cells-feeder2";
  std::filesystem::create_directories(dir);
  json ok = station(dir);
  ok["devices"].push_back(json::parse(R"({"name": "feed", "kind": "feeder", "objects": ["block"], "at": [600, -450, 30]})"));
  EXPECT_EQ(cell_error(ok, dir), "");
  auto with = [&](const std::string& pointer, const json& v) {
    json f = ok;
    f[json::json_pointer(pointer)] = v;
    return cell_error(f, dir);
  };
  EXPECT_EQ(with("/devices/2/objects/0", "belt"),
            "c.json: /devices/2/objects/0: \"belt\" is not movable: a feeder puts out movable objects");
  EXPECT_EQ(with("/devices/2/objects/0", "nothing"), "c.json: /devices/2/objects/0: the scene has no object \"nothing\"");
  EXPECT_EQ(with("/devices/2/objects", json::parse(R"(["block", "block"])")),
            "c.json: /devices/2/objects/1: \"block\" is twice in this feeder");
  EXPECT_EQ(with("/devices/2/objects", json::array()),
            "c.json: /devices/2/objects: must be the names of 1 to 50 of the scene's movable objects, in the order it puts them out");
  EXPECT_EQ(with("/devices/2/every", 0.1), "c.json: /devices/2/every: a feeder puts one out every 0.5 to 3600 seconds (got 0)");
  EXPECT_EQ(with("/devices/2/from", json::parse("[0, 0, 0]")), "c.json: /devices/2/from: a feeder has no field \"from\"");
  json twice = ok;
  twice["devices"].push_back(json::parse(R"({"name": "feed2", "kind": "feeder", "objects": ["block"], "at": [0, 0, 30]})"));
  EXPECT_EQ(cell_error(twice, dir), "c.json: /devices/3/objects/0: \"block\" is already in the feeder \"feed\"");
}

// A switch: the block on the belt presses it (the arm's wait ends there, and the belt stands, as
// with the barrier), and an arm's own part presses one where it stands.
TEST(CellDevices, ASwitchIsPressedByAnObjectOrAnArmsPart) {
  const std::string dir = ::testing::TempDir() + "/cells-switch";
  std::filesystem::create_directories(dir);
  json file = station(dir);
  file["devices"][1] = json::parse(R"({"name": "gate", "kind": "switch", "at": [600, 22, 25], "size": [60, 20, 30]})");
  // and one around the tool at power-up (235, 0, 213 mm)
  file["devices"].push_back(json::parse(R"({"name": "tip", "kind": "switch", "at": [235, 0, 213], "size": [30, 30, 30]})"));
  file["wires"][1]["from"] = "gate.pressed";
  CellSimulation sim(parse_cell(file.dump(), "station.json", dir));
  EXPECT_FALSE(sim.device_level(2));
  EXPECT_EQ(sim.sensed_by(2).rfind("link ", 0), 0u) << sim.sensed_by(2);  // (the arm's own part)
  EXPECT_TRUE(sim.device_level(1));
  while (!sim.done() && sim.time() < 15) sim.step();
  double pressed_t = -1;
  for (const SimEvent& e : sim.world().events())
    if (e.kind == SimEvent::Kind::kDevice && e.a == "gate" && e.detail == "is pressed" && pressed_t < 0) {
      EXPECT_EQ(e.b, "block");
      pressed_t = e.t;
    }
  ASSERT_GT(pressed_t, 0);
  const auto& sig = sim.driver(0).signals();
  ASSERT_GE(sig.size(), 2u);
  const double wait_end = double(sig[1].end_tick) / kStepTickHz;
  EXPECT_GE(wait_end, pressed_t - 0.001);
  EXPECT_LE(wait_end, pressed_t + 0.002);
  EXPECT_EQ(cell_state_json(sim)["devices"][1]["pressed_by"], "block");
}
