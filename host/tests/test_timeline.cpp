// host/lib/timeline.h: a program's time line as the studio plays it, and the arm at any t.
#include <gtest/gtest.h>

#include <cmath>

#include "predict.h"
#include "program.h"
#include "robot_file.h"
#include "robot_view.h"
#include "timeline.h"

using namespace articula::host;

namespace {

const Robot& robot(const char* name) {
  static const Robot mk2 = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  static const Robot puma = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/puma560.json");
  return std::string(name) == "mk2plus" ? mk2 : puma;
}

}  // namespace

TEST(Timeline, APredictionIsTheControllersTimesAndSteps) {
  const Robot& r = robot("mk2plus");
  const Program p = parse_program("L 0 30\nL 1 150\nL 2 -20\n", "t.arm", r);
  const Prediction pred = predict_program(r, p);
  const Timeline tl = Timeline::of_program(r, p, home_pose(r));
  ASSERT_EQ(tl.actions().size(), 3u);
  EXPECT_DOUBLE_EQ(tl.duration(), pred.total_s());
  EXPECT_EQ(tl.actions()[1].reply, pred.records[1].reply);  // refused: takes no time
  EXPECT_EQ(tl.actions()[1].start_s, tl.actions()[1].end_s);
  // at the end, the last record's steps and joints; before the start, power-up
  const TimelinePose end = tl.at(1e9);
  EXPECT_EQ(end.steps, pred.records[2].steps);
  EXPECT_EQ(end.q, pred.records[2].joints);
  EXPECT_EQ(end.line, 3);
  EXPECT_EQ(tl.at(-5).q, tl.start_q());
  // half-way through the first move, the base half-way (linear in time)
  const TimelineAction& a = tl.actions()[0];
  const TimelinePose mid = tl.at((a.start_s + a.end_s) / 2);
  EXPECT_EQ(mid.line, 1);
  EXPECT_NEAR(mid.q[0], (tl.start_q()[0] + a.q[0]) / 2, 1e-9);
  EXPECT_NEAR(mid.q_ideal[0], (tl.start_q()[0] + a.q_ideal[0]) / 2, 1e-9);
}

TEST(Timeline, ARobotWithoutMotorsMovesAtTheJointSpeedsAsThePhysicsMovesIt) {
  const Robot& r = robot("puma560");
  const std::vector<double> start = home_pose(r);
  std::vector<double> q = start;
  q[0] += 30;  // 30 deg at 60 deg/s: 0.5 s
  std::string line = "M";
  for (double v : q) line += " " + std::to_string(v);
  const Program p = parse_program(line + "\n", "t.arm", r);
  const Timeline tl = Timeline::of_program(r, p, start);
  ASSERT_EQ(tl.actions().size(), 1u);
  EXPECT_NEAR(tl.duration(), 30.0 / JointTiming{}.speed_deg, 1e-6);
  EXPECT_FALSE(tl.predicted());
}

TEST(Timeline, AGripperActionTakesTheSettleTimeWhateverItsCase) {
  const Robot& r = robot("puma560");
  for (const char* text : {"G 50\n", "g 50\n", "S 1\n"}) {
    const Program p = parse_program(text, "t.arm", r);
    ASSERT_EQ(p.statements.size(), 1u);
    EXPECT_TRUE(is_gripper_statement(p.statements[0])) << text;
  }
  const Program m = parse_program("M 0 0 0 0 0 0\n", "t.arm", r);
  EXPECT_FALSE(is_gripper_statement(m.statements[0]));
}

// D waits on a robot without motors too: the time line and the physics both pause.
TEST(Timeline, AWaitPausesARobotWithoutMotors) {
  const Robot& r = robot("puma560");
  const Program p = parse_program("D 2\n", "t.arm", r);
  const Timeline tl = Timeline::of_program(r, p, home_pose(r));
  ASSERT_EQ(tl.actions().size(), 1u);
  EXPECT_NEAR(tl.duration(), 2.0, 1e-9);
}

TEST(Timeline, AStraightLineIsPlayedThroughItsSegments) {
  // The line from (300, -100, 150) to (300, 100, 150): as one move the tool would bow
  // millimetres off it; played through its segments it stays within the chord tolerance and a
  // step or two of it at every instant.
  const Robot& r = robot("mk2plus");
  const Program p = parse_program("P 300 -100 150\nT 300 100 150 50\n", "t.arm", r);
  const Timeline tl = Timeline::of_program(r, p, home_pose(r));
  ASSERT_EQ(tl.actions().size(), 2u);
  const TimelineAction& a = tl.actions()[1];
  ASSERT_EQ(a.reply, articula::kOk);
  ASSERT_GT(a.via_s.size(), 3u);
  const articula::Vec3<double> A = tl.actions()[0].tool, B = articula::make_vec3(300.0, 100.0, 150.0);
  double worst = 0, worst_one_move = 0;
  for (int k = 1; k < 100; ++k) {
    const double t = a.start_s + (a.end_s - a.start_s) * k / 100.0;
    const TimelinePose pose = tl.at(t);
    std::vector<double> q(pose.q.size()), q1(pose.q.size());
    const double f = double(k) / 100.0;
    for (size_t j = 0; j < q.size(); ++j) {
      q[j] = joint_to_model(r, int(j), pose.q[j]);
      q1[j] = joint_to_model(r, int(j), tl.actions()[0].q[j] + f * (a.q[j] - tl.actions()[0].q[j]));
    }
    auto off = [&](const articula::Vec3<double>& x) {
      const articula::Vec3<double> ab = B - A;
      const double s = std::clamp(articula::dot(x - A, ab) / articula::dot(ab, ab), 0.0, 1.0);
      return articula::norm(x - (A + s * ab));
    };
    worst = std::max(worst, off(articula::tool_position(r.model, q.data())));
    worst_one_move = std::max(worst_one_move, off(articula::tool_position(r.model, q1.data())));
  }
  EXPECT_LT(worst, 2.0);
  EXPECT_GT(worst_one_move, 5.0);
}
