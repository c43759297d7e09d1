// host/lib/timeline.h - a program's time line, as the studio plays it: every action from the
// pose before it to its own in its own time, back to back, and the arm at any instant. The
// prediction (predict.h: the firmware) times a robot with motors; a robot without motors moves at
// JointTiming's speeds, the same rule the physics (host/physics/sim.h) moves it by.
#ifndef ARTICULA_HOST_TIMELINE_H
#define ARTICULA_HOST_TIMELINE_H

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "predict.h"
#include "program.h"
#include "robot.h"
#include "run.h"

namespace articula::host {

// How a robot without motors moves (no controller times it): each move at a joint speed, a
// gripper action in its settle time.
struct JointTiming {
  double speed_deg = 60;          // revolute joints, deg/s
  double speed_mm = 100;          // prismatic joints, mm/s
  double gripper_settle_s = 0.3;  // a gripper action

  // Seconds from q_from to q_to (model units: rad, mm): the largest change at its joint's speed.
  double move_s(const Robot& robot, const double* q_from, const double* q_to) const;
};

// One statement on the time line (a rejected one takes no time and changes nothing).
struct TimelineAction {
  int line = 0;
  std::string command;
  Status reply = kOk;
  std::string error;  // what the reply means (the core's status table), "" when ok
  std::string note;
  double start_s = 0, end_s = 0;
  std::vector<double> q;            // joint values after it, deg or mm (the steps' values)
  std::vector<double> q_ideal;      // from the exact commanded angles (= q without motors)
  Vec3<double> tool{0, 0, 0};       // tool position at q, mm
  Vec3<double> tool_ideal{0, 0, 0};  // at q_ideal
  double error_mm = 0;              // |tool - tool_ideal|
  std::vector<int32_t> steps;       // per motor, after it (none without motors)
  int gripper_percent = -1;         // -1: no gripper action yet
  // A straight line (T): where each of its segments ends, and when; the arm goes through
  // them (each segment straight in steps), not straight from the start to q.
  std::vector<double> via_s;
  std::vector<std::vector<double>> via_q;
  // Predicted: the tool (mm) after every step of its moves, as the arm spreads them; and for
  // a straight line the line it follows (from the tool where it began to the point asked for)
  // and its worst distance from it at any step.
  std::vector<Vec3<double>> path;
  bool straight = false;
  Vec3<double> line_from{0, 0, 0}, line_to{0, 0, 0};
  double line_error_mm = 0;
};

// The arm at an instant of the time line.
struct TimelinePose {
  double t = 0;
  int line = 0;                  // the statement running (or last ended) at t
  std::vector<double> q;         // deg or mm: joint values linear in time within an action
  std::vector<double> q_ideal;   // the ghost's
  std::vector<int32_t> steps;    // of the last action ended (none before the first)
  double error_mm = 0;           // of the last action ended
  int gripper_percent = -1;      // of the last gripper action ended, -1 none
};

class Timeline {
 public:
  // A prediction, from power-up (every motor at its zero angle).
  static Timeline of(const Robot& robot, const Prediction& prediction);
  // A run of `program` on the kinematic model (its records, one a statement) from start_q (deg
  // or mm), timed by `timing` as the physics times such a robot.
  static Timeline of(const Robot& robot, const Program& program, const std::vector<RunRecord>& records,
                     const std::vector<double>& start_q, const JointTiming& timing = {});

  // The arm at time t (clamped to 0 .. duration): each action moves from the pose before it to
  // its own in its time, joint values linear in time (a drawing of the move, not the motors'
  // speed profile).
  TimelinePose at(double t) const;

  // A program on the robot: predicted (a robot with motors, from power-up) or run on the
  // kinematic model from start_q (without motors). Throws ProgramError naming the line.
  static Timeline of_program(const Robot& robot, const Program& program, const std::vector<double>& start_q,
                             const JointTiming& timing = {});

  double duration() const { return duration_; }
  bool predicted() const { return predicted_; }
  const std::vector<TimelineAction>& actions() const { return actions_; }
  const std::vector<double>& start_q() const { return start_q_; }
  // The tool at start_q, mm (where a drawn path begins).
  const Vec3<double>& start_tool() const { return start_tool_; }

 private:
  std::vector<double> start_q_;
  Vec3<double> start_tool_{0, 0, 0};
  std::vector<TimelineAction> actions_;
  double duration_ = 0;
  bool predicted_ = false;
};

// The JSON forms the bindings hand out: {start_q, duration, summary: {commands, rejected,
// worst_error_mm (predicted only)}, records: [{line, command, reply,
// code, error, note, start_s, end_s, q, q_ideal, tool, tool_ideal, error_mm, steps, gripper}]}
// and a pose {t, line, q, q_ideal, steps, error_mm, gripper}. Records' steps and gripper are
// null where there are none.
nlohmann::json timeline_json(const Timeline& tl);

// The path the arm takes, for plots and CSV: the time line sampled at every action's start and
// end (and a straight line's every segment end), and evenly between, about `per_s` samples a
// second (at most `max_samples` in all); at each, at(t)'s joint values and the tool there
// (forward kinematics of them: a move between two points is a curve, not the line joining
// them). Column by column: {t: [...], line: [...], q: [[joint 0...], ...], tool: [[x...], [y...],
// [z...]]}, seconds, deg or mm, mm.
nlohmann::json timeline_samples_json(const Robot& robot, const Timeline& tl, double per_s = 50, size_t max_samples = 4000);
nlohmann::json timeline_pose_json(const TimelinePose& p);

}  // namespace articula::host

#endif  // ARTICULA_HOST_TIMELINE_H
