// host/lib/records_json.h - the JSON form of what the host library computes: the one place
// that names the fields of `articula predict --json`, `run --json`, `ik --json` and
// `quantize --json`, which the Python package (python/) hands out as the same records.
// Lengths mm, angles deg, as everywhere at the interfaces.
#ifndef ARTICULA_HOST_RECORDS_JSON_H
#define ARTICULA_HOST_RECORDS_JSON_H

#include <nlohmann/json.hpp>

#include <vector>

#include "experiment.h"
#include "ik.h"
#include "nano_config.h"
#include "plan.h"
#include "predict.h"
#include "program.h"
#include "quantize.h"
#include "robot.h"
#include "run.h"

namespace articula::host {

// "ok" or "error:N", as the arm answers.
std::string reply_text(Status s);

// One statement of a prediction (every field: steps, commanded and actuator angles, joints,
// ideal and quantized tool, error, target, timing in ticks and seconds).
nlohmann::json predict_record_json(const PredictRecord& r);
// A whole prediction: robot, program, settings, motors, joints, records and a summary.
nlohmann::json prediction_json(const Robot& robot, const Program& program, const Prediction& p);

nlohmann::json run_record_json(const RunRecord& r);
nlohmann::json run_json(const Robot& robot, const Program& program, const std::vector<RunRecord>& records);

// An IK result: status, solver, q (deg or mm), tool and its rpy, errors, iterations,
// attempts, the limiting joints and motors by name.
nlohmann::json ik_result_json(const Robot& robot, const IkResult& res);

// One line through quantize.h (without "where", which only the command line knows).
nlohmann::json quantize_record_json(const Robot& robot, const QuantizeRecord& q);

// A program as its parser reads it, for editors that show it another way (the studio's
// blocks): {format, statements: [{line, kind, values} for RoboSim (kind its letter: "m",
// "a"...; values in file units), {line, kind: "protocol", text, command, args} for a
// protocol line (command its letter, args its numbers as written: joint indices, degrees,
// mm, percent; a setting's number and value)], comments: [{line, text, whole_line}]}.
nlohmann::json program_json(const Robot& robot, const Program& program, const std::string& text);

// The experiment (experiment.h): per-axis errors {mm: [3], pct: [3] (null: none)}; Table 4's
// rows [{joint, poses, axes: [{max_pct (null: none), max_mm, avg_mm}] for x, y, z}]; and the
// points a binding receives as JSON, [{joint, value: [x, y, z], reference: [x, y, z]}] (throws
// std::invalid_argument naming the entry that is not one).
nlohmann::json axis_errors_json(const AxisErrors& e);
// Table 5: [{"chain", "moves", "back_moves", "dest_error_mm", "return_error_mm", "measured_dest_mm",
// "measured_return_mm" (null: nothing to compare), "return_from_measured_start"}].
nlohmann::json table5_json(const std::vector<Table5Row>& rows);
// Chains from JSON: [{"chain", "moves", "back_moves", "start", "dest_quant", "dest_ideal",
// "back_quant" (or null), "start_measured", "dest_measured", "back_measured" (or null)}]; a
// position is [x, y, z] mm. Throws std::invalid_argument naming the entry.
std::vector<ChainPoses> chain_poses_of_json(const nlohmann::json& chains);
// Tool points: [{"line", "model_from_target_mm", "ideal_from_target_mm", "measured_from_target_mm",
// "measured_from_model_mm" (null: not measured)}], from [{"line", "target", "quant", "ideal",
// "measured" (or null)}].
nlohmann::json tool_points_json(const std::vector<TargetRow>& rows);
std::vector<TargetPoses> target_poses_of_json(const nlohmann::json& points);
// A test plan: {"name", "title", "notes", "commands": [{"line", "text", "expect", "timeout_s"
// (null: the default), "single_joint" ([joint, thesis angle] or null), "repeat" ([chain,
// "out"|"back"] or null), "kind" ("single-joint", "repeat-out", "repeat-back", "target", "")}]}.
nlohmann::json plan_json(const Plan& p);
// A Nano's configuration for a robot: {"name", "checksum", "lines", "has_point"}.
nlohmann::json nano_config_json(const NanoConfig& c);
nlohmann::json table4_json(const std::vector<Table4Row>& rows);
// Verdicts per joint: [{"joint", "measured", "worst_mm", "quant_mm", "within", "text"}], from
// single-joint poses [{"joint", "ideal", "quant", "measured" (or null)}].
nlohmann::json joint_verdicts_json(const std::vector<JointVerdict>& v);
// A plan's repeatability chains: [{"chain", "moves", "back_moves", "line_before", "line_out",
// "line_back"} (null: none)], from its commands [{"line", "repeat": [chain, "out"|"back"] or
// null}] (plan_json's commands).
nlohmann::json repeat_chains_json(const std::vector<RepeatChain>& chains);
std::vector<PlanStep> plan_steps_of_json(const nlohmann::json& commands);

// The experiment as CSV (the studio's Experiment panel exports it): first every measurement in
// the harness's --measured format (`plan,plan_line,x_mm,y_mm,z_mm`: hil/harness/measured.py
// reads this section, so measurements typed in the page make the harness's report), then the
// single-joint poses with their errors, each Table 4, Table 5 and the tool points, a blank
// line between sections; `#` lines are comments. From the project's experiment: {plan, title,
// robot, when, points [{joint, angle, line, command, ideal, quant, measured}], chains
// [{chain, moves, back_moves, line_before, line_out, line_back, start, dest_quant, dest_ideal,
// back_quant, start_measured, dest_measured, back_measured, steps_back}], targets [{line,
// command, target, quant, ideal, measured}]}.
std::string experiment_csv(const nlohmann::json& experiment);
std::vector<VerdictPoint> verdict_points_of_json(const nlohmann::json& points);
std::vector<JointPoint> joint_points_of_json(const nlohmann::json& points);

}  // namespace articula::host

#endif  // ARTICULA_HOST_RECORDS_JSON_H
