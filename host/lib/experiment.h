// host/lib/experiment.h - the numbers of the thesis's sim-vs-real experiment (section 5,
// appendices I and K), in one place: per-axis errors and their per cent (Table 4, Figs.
// 30-32), Table 4's maximum and average per joint and axis, the distances of repeatability
// (Table 5) and of the tool sent to points, and the questions a typed measurement raises
// before it is used. The harness's
// report (hil/harness/report.py, through Python) and the studio's Experiment panel (through
// the web engine) both call these, so they agree to the digit on the same measurements.
#ifndef ARTICULA_HOST_EXPERIMENT_H
#define ARTICULA_HOST_EXPERIMENT_H

#include <articula/transform.h>

#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

// A per-axis % needs a coordinate at least this far from 0 (the thesis divides by it).
constexpr double kPctMinMm = 1.0;

// |value - reference| per axis, mm, and as a share of |reference| in per cent (NaN where
// |reference| < kPctMinMm: no per cent).
struct AxisErrors {
  double mm[3] = {0, 0, 0};
  double pct[3] = {0, 0, 0};
};
AxisErrors axis_errors(const Vec3<double>& value, const Vec3<double>& reference);

// One pose of a single-joint test: the joint that moved, and a position against its reference
// (quantized against ideal, measured against quantized, or measured against ideal).
struct JointPoint {
  int joint = 0;
  Vec3<double> value{0, 0, 0};
  Vec3<double> reference{0, 0, 0};
};

// Table 4: per joint and axis, the largest per cent (NaN: no coordinate far enough from 0),
// the largest and the average error in mm.
struct Table4Cell {
  double max_pct = 0, max_mm = 0, avg_mm = 0;
};
struct Table4Row {
  int joint = 0;
  int poses = 0;
  Table4Cell axis[3];
};
// Rows in ascending joint order, one per joint that has a point.
std::vector<Table4Row> table4(const std::vector<JointPoint>& points);

// The distance between two positions, mm (Table 5's destination and return errors).
double distance_mm(const Vec3<double>& a, const Vec3<double>& b);

// One repeatability chain (thesis 5.3): moves out from a start to a destination, and the same
// moves back. The model's tool positions (whole steps; the destination's exact angles too),
// and where the student measured the tool, when they did.
struct ChainPoses {
  int chain = 0, moves = 0, back_moves = 0;
  Vec3<double> start{0, 0, 0};  // before the chain's first move
  Vec3<double> dest_quant{0, 0, 0}, dest_ideal{0, 0, 0};
  bool has_back = false;
  Vec3<double> back_quant{0, 0, 0};
  bool start_measured = false, dest_measured = false, back_measured = false;
  Vec3<double> start_m{0, 0, 0}, dest_m{0, 0, 0}, back_m{0, 0, 0};
};

// A plan's repeatability chains, from its commands in order (each its line and, for a move of
// a chain, the chain's number and whether it goes out or back): per chain, in ascending
// order, how many moves out and back, the line before its first move (-1: none, the arm at
// power-up), and its last move out and back (-1: none). A chain without a move out is left
// out. The studio's Experiment panel and the harness report group chains here.
struct PlanStep {
  int line = 0;
  int chain = -1;  // -1: not a move of a chain
  bool back = false;
};
struct RepeatChain {
  int chain = 0, moves = 0, back_moves = 0;
  int line_before = -1, line_out = -1, line_back = -1;
};
std::vector<RepeatChain> repeat_chains(const std::vector<PlanStep>& steps);

// Table 5, a row per chain: the destination's quantization error (whole steps against the
// exact angles), the model's return error (back against start), and with measurements the
// destination measured against the model (and against the exact angles) and the return
// measured against the start (the
// measured start when there is one, else the model's). NaN where there is nothing to compare.
struct Table5Row {
  int chain = 0, moves = 0, back_moves = 0;
  double dest_error_mm = 0, return_error_mm = 0;
  double measured_dest_mm = 0, measured_dest_ideal_mm = 0, measured_return_mm = 0;
  bool return_from_measured_start = false;
};
std::vector<Table5Row> table5(const std::vector<ChainPoses>& chains);

// The tool sent to a point (P): the target, the model's tool there (whole steps, and the
// closed form's exact angles), and where the student measured it, when they did.
struct TargetPoses {
  int line = 0;
  Vec3<double> target{0, 0, 0}, quant{0, 0, 0}, ideal{0, 0, 0};
  bool measured = false;
  Vec3<double> m{0, 0, 0};
};
// Per point: how far the model's tool is from the target (whole steps; exact angles, the closed
// form's own error), and the measured tool from the target and from the model (NaN: not
// measured).
struct TargetRow {
  int line = 0;
  double model_from_target_mm = 0, ideal_from_target_mm = 0;
  double measured_from_target_mm = 0, measured_from_model_mm = 0;
};
std::vector<TargetRow> tool_points(const std::vector<TargetPoses>& points);

// A joint's verdict (the Experiment panel's and the harness report's): its measured error
// against the model (whole steps) within kVerdictMm on every axis is what a ruler and a
// printed arm's play account for; beyond it, the robot file or the arm needs a look. From the
// single-joint poses: the model's tool (quant), the exact angles' (ideal), the measurement.
constexpr double kVerdictMm = 5;
struct VerdictPoint {
  int joint = 0;
  Vec3<double> ideal{0, 0, 0}, quant{0, 0, 0};
  bool measured = false;
  Vec3<double> m{0, 0, 0};
};
struct JointVerdict {
  int joint = 0;
  bool measured = false;       // any pose of it measured
  double worst_mm = 0;         // the largest measured-vs-model error on any axis
  double quant_mm = 0;         // the largest the whole steps alone leave on any axis
  bool within = false;         // measured and worst_mm <= kVerdictMm
  std::string text;            // what it means, in a sentence (after "joint N: ")
};
// Per joint, in ascending order.
std::vector<JointVerdict> joint_verdicts(const std::vector<VerdictPoint>& points);

// What a typed measurement raises before it is used, as a question to the student; "" when
// it looks right. `predicted` is where the prediction puts the tool; `reach_mm` how far the
// robot reaches from its base (InverseKinematics::reach_bound). Checked in order: not a number;
// far beyond the arm's reach; typed in cm (ten times it lies much nearer the prediction);
// far from the prediction (more than `far_mm`).
inline constexpr double kMeasurementFarMm = 50;
std::string measurement_question(const Vec3<double>& measured, const Vec3<double>& predicted, double reach_mm,
                                 double far_mm = kMeasurementFarMm);

}  // namespace articula::host

#endif  // ARTICULA_HOST_EXPERIMENT_H
