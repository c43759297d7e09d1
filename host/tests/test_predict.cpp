// Tests host/lib/predict.cpp, the host's model of the controller: steps against quantization
// worked out here by hand, tool positions from the MK2's geometry (not through the DH
// chain), durations from motion.h with the settings written out here, the queue's timeline,
// rejected commands, P, H, Z, settings, the gripper, and the RoboSim mapping.
#include <gtest/gtest.h>

#include <articula/motion.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "firmware_session.h"
#include "nano_config.h"
#include "predict.h"
#include "program.h"
#include "records_json.h"
#include "robot_file.h"
#include "test_robots.h"

using namespace articula;
using namespace articula::host;

namespace {

std::string mk2_text() {
  std::ifstream f(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// The MK2 with an upper arm RoboSim's `l` may change (100 .. 200 mm).
Robot mk2_adjustable() {
  std::string t = mk2_text();
  const std::string from = "{\"a\": 135,";
  const size_t at = t.find(from);
  EXPECT_NE(at, std::string::npos);
  t.replace(at, from.size(), "{\"a\": {\"value\": 135, \"min\": 100, \"max\": 200},");
  return parse_robot(t, "mk2-adjustable.json");
}

// The defaults of docs/protocol.md, written out: $0 600 steps/s, $1 2000 steps/s^2, 2 MHz.
const MotionSettings kDefaultMotion = {2000000, 600, 2000};
constexpr uint64_t kSettleTicks = 300 * 2000;  // $5 = 300 ms at 2 MHz

// Degrees per step: base 360 * 19 / (200 * 108), shoulder and forearm 360 * 19 / (200 * 47).
constexpr double kBaseDeg = 360.0 * 19 / (200 * 108);
constexpr double kArmDeg = 360.0 * 19 / (200 * 47);

double rad(double deg) {
  return deg * M_PI / 180;
}

// The MK2's tool point from its actuator angles (base yaw, upper-arm elevation, forearm
// elevation), by its geometry: shoulder 78 mm up, links 135 and 147 mm, gripper 88 mm level.
Vec3<double> mk2_tool(double base, double upper, double fore) {
  const double r = 135 * std::cos(rad(upper)) + 147 * std::cos(rad(fore)) + 88;
  const double z = 78 + 135 * std::sin(rad(upper)) + 147 * std::sin(rad(fore));
  return make_vec3(r * std::cos(rad(base)), r * std::sin(rad(base)), z);
}

void expect_near(const Vec3<double>& a, const Vec3<double>& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Statement robosim(Statement::Kind kind, std::vector<double> values, int line = 1) {
  Statement s;
  s.kind = kind;
  s.values = std::move(values);
  s.line = line;
  return s;
}

// How far half a step on every motor can move the MK2's tool at most: each motor's half
// step (rad) times the longest lever it turns (the base: the whole reach).
double half_step_reach_mm() {
  return 0.5 * (rad(kBaseDeg) * 370 + rad(kArmDeg) * 135 + rad(kArmDeg) * 147);
}

}  // namespace

// The records of `lines`, each sent once the arm is at rest after the one before: the
// firmware's (predict_run.cpp).
std::vector<PredictRecord> run(const Robot& r, const std::string& lines, const ControllerSettings& s = {}) {
  return predict_program(r, parse_protocol_program(lines, "test", r), s).records;
}
// The same for statements (RoboSim's among them).
std::vector<PredictRecord> run(const Robot& r, const std::vector<Statement>& statements) {
  Program p;
  p.source = "test";
  p.statements = statements;
  return predict_program(r, p).records;
}
Statement line(const std::string& text) { return Statement{Statement::Kind::kProtocol, {}, text, 1}; }

TEST(Predict, PowersUpAtStepZeroWithTheFirmwareHome) {
  const ConfiguredArm<kFirmwareMotors> arm = firmware_arm(mk2());
  EXPECT_TRUE(arm.has_point);
  EXPECT_EQ(std::vector<Millideg>(arm.home, arm.home + 3), (std::vector<Millideg>{0, 90000, 0}));
  const std::vector<PredictRecord> r = run(mk2(), "I\nZ\n");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].reply, kOk);
  EXPECT_EQ(r[0].steps, (std::vector<int32_t>{0, 0, 0}));
  EXPECT_EQ(r[0].commanded, (std::vector<Millideg>{0, 90000, 0}));
  EXPECT_EQ(r[0].end_tick, 0u);
  EXPECT_EQ(r[1].steps, (std::vector<int32_t>{0, 0, 0}));  // Z at the home pose: its steps
}

TEST(Predict, RelativeMoveQuantizesByHand) {
  const PredictRecord r = predict_program(mk2(), parse_protocol_program("\n\nL 0 10\n", "test", mk2())).records.back();
  ASSERT_EQ(r.reply, kOk);
  EXPECT_EQ(r.line, 3);
  // 10 deg / 0.31667 deg = 31.58 -> step 32, at 32 * 0.31667 = 10.1333 deg.
  EXPECT_EQ(r.steps, (std::vector<int32_t>{32, 0, 0}));
  EXPECT_EQ(r.commanded, (std::vector<Millideg>{10000, 90000, 0}));
  EXPECT_NEAR(r.joints[0], 32 * kBaseDeg, 1e-12);
  EXPECT_NEAR(r.joints[0], 10.1333, 1e-4);
  EXPECT_NEAR(r.joints[1], 90, 1e-12);
  EXPECT_NEAR(r.joints[2], -90, 1e-12);  // DH elbow = forearm elevation - upper arm
  EXPECT_NEAR(r.joints_ideal[0], 10, 1e-12);
  expect_near(r.tool_ideal, mk2_tool(10, 90, 0), 1e-9);
  expect_near(r.tool_quantized, mk2_tool(32 * kBaseDeg, 90, 0), 1e-9);
  // The base turns 0.1333 deg too far at a radius of 235 mm: a chord of 0.547 mm.
  EXPECT_NEAR(r.error_mm, 2 * 235 * std::sin(rad(32 * kBaseDeg - 10) / 2), 1e-9);
  EXPECT_NEAR(r.error_mm, 0.547, 1e-3);
}

TEST(Predict, DurationsAreTheProfileOfTheDominantMotor) {
  const std::vector<PredictRecord> r = run(mk2(), "L 0 10\nM -0.1 60 -20\n");
  const PredictRecord& a = r[0];
  EXPECT_TRUE(a.queued);
  EXPECT_EQ(a.dominant_steps, 32u);
  EXPECT_EQ(a.ticks, profile_duration_ticks(32, kDefaultMotion));
  EXPECT_EQ(a.start_tick, 0u);
  EXPECT_EQ(a.end_tick, a.ticks);
  EXPECT_DOUBLE_EQ(a.seconds(), double(a.ticks) / 2e6);
  // All three at once: the base has 10 deg -> -32 steps, the shoulder 30 deg -> round(41.2)
  // = 41 steps, the forearm -20 deg -> round(-27.48) = -27 steps; the shoulder dominates.
  const PredictRecord& b = r[1];
  ASSERT_EQ(b.reply, kOk);
  EXPECT_EQ(b.steps, (std::vector<int32_t>{0, -41, -27}));
  EXPECT_EQ(b.dominant_steps, 41u);
  EXPECT_EQ(b.ticks, profile_duration_ticks(41, kDefaultMotion));
  EXPECT_EQ(b.start_tick, a.end_tick);  // back to back, from rest to rest
  EXPECT_EQ(b.end_tick, a.end_tick + b.ticks);
  expect_near(b.tool_quantized, mk2_tool(0, 90 - 41 * kArmDeg, -27 * kArmDeg), 1e-9);
  expect_near(b.tool_ideal, mk2_tool(-0.1, 60, -20), 1e-9);
}

TEST(Predict, RejectedLinesChangeNothing) {
  const char* const bad[] = {"L 1 50", "M 0 131 0", "M 91 90 0", "P 1000 0 0", "$0=5000", "$0=600.5", "$9=1",
                             "L 0 1000000"};
  std::string program = "L 0 10\n";
  for (const char* line : bad) program += std::string(line) + "\n";
  program += "L 0 0.1\nL 0 10\n";
  const std::vector<PredictRecord> r = run(mk2(), program);
  ASSERT_EQ(r.size(), 11u);
  for (size_t k = 1; k <= 8; ++k) {
    EXPECT_NE(r[k].reply, kOk) << r[k].text;
    EXPECT_FALSE(r[k].queued) << r[k].text;
    EXPECT_EQ(r[k].ticks, 0u) << r[k].text;
    EXPECT_EQ(r[k].steps, (std::vector<int32_t>{32, 0, 0})) << r[k].text;
    EXPECT_EQ(r[k].commanded, (std::vector<Millideg>{10000, 90000, 0})) << r[k].text;
    EXPECT_EQ(r[k].end_tick, r[0].end_tick) << r[k].text;
  }
  EXPECT_EQ(r[1].reply, kJointLimit);
  // its note names the motor, where it would go and its range (what a student needs to fix it)
  EXPECT_NE(r[1].note.find("the shoulder motor to 140 deg is beyond its range,"), std::string::npos) << r[1].note;
  EXPECT_EQ(r[4].reply, kUnreachable);
  EXPECT_EQ(r[5].reply, kValueOutOfRange);
  EXPECT_EQ(r[7].reply, kSettingUnknown);
  EXPECT_EQ(r[8].reply, kValueOutOfRange);  // beyond 1,000,000 deg
  // And the next good line continues from where the arm was.
  EXPECT_EQ(r[9].commanded[0], 10100);
  EXPECT_EQ(r[9].steps[0], 32);
  EXPECT_FALSE(r[9].queued);  // the same step: only the commanded angle changes
  EXPECT_NE(r[9].note.find("same steps"), std::string::npos);
  // $0 is still 600: the last move takes the default profile.
  EXPECT_EQ(r[10].ticks, profile_duration_ticks(r[10].dominant_steps, kDefaultMotion));
}

TEST(Predict, PointEndsWithinAStepsWorth) {
  const Vec3<double> points[] = {make_vec3(200.0, -150.0, 150.0), make_vec3(250.0, 100.0, 120.0),
                                 make_vec3(180.0, 0.0, 200.0), make_vec3(20.0, 230.0, 140.0)};
  std::string program;
  for (const Vec3<double>& p : points) {
    char line[64];
    std::snprintf(line, sizeof line, "P %.3f %.3f %.3f\n", p.x, p.y, p.z);
    program += line;
  }
  const std::vector<PredictRecord> recs = run(mk2(), program);
  for (size_t k = 0; k < 4; ++k) {
    const PredictRecord& r = recs[k];
    const Vec3<double>& p = points[k];
    ASSERT_EQ(r.reply, kOk) << r.text;
    EXPECT_TRUE(r.has_target);
    expect_near(r.target, p, 1e-12);
    // The commanded angles reach the point (to their 0.001 deg) ...
    expect_near(r.tool_ideal, p, 0.01);
    // ... and the steps within half a step on every motor.
    EXPECT_LT(r.target_error_mm, half_step_reach_mm()) << r.text;
    EXPECT_NEAR(r.target_error_mm, norm(r.tool_quantized - p), 1e-12);
    expect_near(r.tool_quantized, mk2_tool(r.actuator_deg[0], r.actuator_deg[1], r.actuator_deg[2]), 1e-9);
  }
}

TEST(Predict, PointTakesTheSolutionNearestThePlannedPose) {
  // The MK2's limits leave one pose for most points; an arm of the same shape with an elbow
  // that bends both ways has two for (200, 0, 200), elbow up and elbow down. The firmware
  // takes the one nearer the pose the queue has reached.
  const Robot arm = parse_robot(R"({"name": "two elbows", "dh": [
      {"a": 0, "alpha": 0, "d": 78, "theta": {"joint": "base", "min": -170, "max": 170}},
      {"a": 0, "alpha": 90, "d": 0, "theta": {"joint": "shoulder", "min": -30, "max": 180}},
      {"a": 135, "alpha": 0, "d": 0, "theta": {"joint": "elbow", "min": -160, "max": 160}},
      {"a": 147, "alpha": 0, "d": 0, "theta": {"linked": {"shoulder": -1, "elbow": -1}, "offset": 0}}],
    "tool": {"xyz": [88, 0, 0], "rpy": [-90, 0, 0]},
    "motors": [
      {"name": "base", "steps_per_rev": 200, "microsteps": 16, "gear": [1, 1],
       "direction": 1, "zero": 0, "min": -170, "max": 170},
      {"name": "shoulder", "steps_per_rev": 200, "microsteps": 16, "gear": [1, 1],
       "direction": 1, "zero": 90, "min": -30, "max": 180},
      {"name": "elbow", "steps_per_rev": 200, "microsteps": 16, "gear": [1, 1],
       "direction": -1, "zero": -90, "min": -160, "max": 160}],
    "home": {"base": 0, "shoulder": 90, "elbow": -90}})",
                                "two-elbows.json");
  ASSERT_TRUE(firmware_arm(arm).has_point);
  const std::vector<PredictRecord> up = run(arm, "M 0 120 -120\nP 200 0 200\n");
  const std::vector<PredictRecord> down = run(arm, "M 0 -10 100\nP 200 0 200\n");
  EXPECT_EQ(up[0].reply, kOk);
  EXPECT_EQ(down[0].reply, kOk);
  const PredictRecord& a = up[1];
  const PredictRecord& b = down[1];
  ASSERT_EQ(a.reply, kOk);
  ASSERT_EQ(b.reply, kOk);
  EXPECT_LT(a.commanded[2], 0);  // elbow up: the elbow bent down relative to the upper arm
  EXPECT_GT(b.commanded[2], 0);
  EXPECT_GT(a.commanded[1], b.commanded[1]);
  for (const PredictRecord* r : {&a, &b}) {
    expect_near(r->tool_ideal, make_vec3(200.0, 0.0, 200.0), 0.01);
    EXPECT_LT(r->target_error_mm, 0.5);  // 1/16 steps: a fine arm
  }
}

TEST(Predict, GripperActionsTakeTheSettleTime) {
  const std::vector<PredictRecord> r = run(mk2(), "S 1\nG 100\nG 49.5\n");
  EXPECT_EQ(r[0].reply, kOk);
  EXPECT_TRUE(r[0].queued);
  EXPECT_EQ(r[0].ticks, kSettleTicks);
  EXPECT_EQ(r[0].gripper_percent, 0);
  EXPECT_NE(r[0].note.find("2091 us"), std::string::npos) << r[0].note;  // docs/protocol.md
  EXPECT_EQ(r[1].gripper_percent, 100);
  EXPECT_EQ(r[1].start_tick, kSettleTicks);
  EXPECT_NE(r[1].note.find("1472 us"), std::string::npos) << r[1].note;
  EXPECT_EQ(r[2].gripper_percent, 50);  // whole percent, a half up
  EXPECT_EQ(r[2].end_tick, 3 * kSettleTicks);
}

TEST(Predict, DwellWaitsInTheQueue) {
  const std::vector<PredictRecord> r = run(mk2(), {line("L 0 10"), line("D 1.5"), line("L 0 -10"), line("D 600.5")});
  const PredictRecord& move = r[0];
  EXPECT_EQ(r[1].reply, kOk);
  EXPECT_TRUE(r[1].queued);
  EXPECT_EQ(r[1].start_tick, move.end_tick);
  EXPECT_EQ(r[1].ticks, 3u * kStepTickHz / 2);
  EXPECT_EQ(r[1].steps, move.steps);  // nothing moves
  EXPECT_EQ(r[2].start_tick, r[1].end_tick);
  EXPECT_EQ(r[3].reply, kValueOutOfRange);
  EXPECT_FALSE(r[3].queued);  // a refused wait adds nothing
}

// The program's times are the firmware's (predict_run.cpp): D 0.5 pauses 1,000,000 ticks. The
// same program with one line of the firmware changed: host.ChangedFirmware.
TEST(Predict, ProgramDwellIsTheFirmwares) {
  for (SenderModel::Kind kind : {SenderModel::kRest, SenderModel::kStream}) {
    SenderModel sender;
    sender.kind = kind;
    const Prediction p = predict_program(mk2(), parse_protocol_program("D 0.5\nL 0 10\n", "test", mk2()), {}, sender);
    ASSERT_EQ(p.records.size(), 2u);
    EXPECT_EQ(p.records[0].end_tick - p.records[0].start_tick, 1000000u) << sender_name(kind);
    EXPECT_EQ(p.records[1].start_tick, p.records[0].end_tick) << sender_name(kind);
  }
}

TEST(Predict, SettingsLinesChangeLaterMoves) {
  const std::vector<PredictRecord> r =
      run(mk2(), {line("$0=800"), line("$1 = 3000"), line("$1=3000"), line("$5=0"), line("L 1 30"), line("S 1")});
  EXPECT_EQ(r[0].reply, kOk);
  EXPECT_EQ(r[1].reply, kMissingArgument);  // the codec: no blanks around '='
  EXPECT_EQ(r[2].reply, kOk);
  EXPECT_EQ(r[3].reply, kOk);
  EXPECT_EQ(r[4].ticks, profile_duration_ticks(r[4].dominant_steps, MotionSettings{2000000, 800, 3000}));
  EXPECT_NE(r[4].ticks, profile_duration_ticks(r[4].dominant_steps, kDefaultMotion));
  EXPECT_EQ(r[5].ticks, 0u);  // no settle time
}

TEST(Predict, SettingsTextIsCheckedAsTheFirmwareDoes) {
  ControllerSettings s;
  apply_settings_text(s, "0=800, $1=3000,5=0", 3);
  EXPECT_EQ(s.value[0], 800u);
  EXPECT_EQ(s.value[1], 3000u);
  EXPECT_EQ(s.value[5], 0u);
  EXPECT_EQ(s.value[2], 2000u);  // untouched
  for (const char* bad : {"0=5000", "9=1", "0=600.5", "x", "0=", "", "3=8", "0=800,,1=1"}) {
    ControllerSettings t;
    EXPECT_THROW(apply_settings_text(t, bad, 3), std::invalid_argument) << bad;
  }
  try {
    apply_settings_text(s, "0=5000", 3);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("from 1 to 4000"), std::string::npos) << e.what();
  }
  // Given settings hold from power-up.
  ControllerSettings fast;
  apply_settings_text(fast, "0=800,1=3000", 3);
  const PredictRecord r = run(mk2(), "L 0 30\n", fast)[0];
  EXPECT_EQ(r.ticks, profile_duration_ticks(95, MotionSettings{2000000, 800, 3000}));
}

TEST(Predict, HomeMovesBackAndZeroDeclaresHome) {
  const std::vector<PredictRecord> r = run(mk2(), "L 0 10\nL 2 -5.5\nH\nH\nL 0 10\nZ\nL 0 -10\n");
  const PredictRecord& h = r[2];
  EXPECT_EQ(h.reply, kOk);
  EXPECT_EQ(h.steps, (std::vector<int32_t>{0, 0, 0}));
  EXPECT_EQ(h.commanded, (std::vector<Millideg>{0, 90000, 0}));
  EXPECT_EQ(h.ticks, profile_duration_ticks(32, kDefaultMotion));
  // H at home still takes its (empty) place in the queue.
  EXPECT_TRUE(r[3].queued);
  EXPECT_EQ(r[3].ticks, 0u);

  // Z where the arm is: the controller counts from here, the arm has not moved.
  const PredictRecord& z = r[5];
  EXPECT_EQ(z.reply, kOk);
  EXPECT_FALSE(z.queued);
  EXPECT_EQ(z.steps, (std::vector<int32_t>{0, 0, 0}));
  EXPECT_EQ(z.commanded, (std::vector<Millideg>{0, 90000, 0}));
  EXPECT_NEAR(z.joints[0], 32 * kBaseDeg, 1e-12);  // where the base really is
  expect_near(z.tool_quantized, mk2_tool(32 * kBaseDeg, 90, 0), 1e-9);
  // A move after it counts from the new zero: L 0 -10 is step -32, the base back at 0.
  const PredictRecord& back = r[6];
  EXPECT_EQ(back.steps[0], -32);
  EXPECT_NEAR(back.joints[0], 0, 1e-12);
  EXPECT_NEAR(back.joints_ideal[0], 32 * kBaseDeg - 10, 1e-12);
}

TEST(Predict, EndstopsMeanAlarmUntilHomed) {
  ControllerSettings s;
  apply_settings_text(s, "3=2", 3);  // a switch on the shoulder (motor 1), at its 36 deg minimum
  const std::vector<PredictRecord> r = run(mk2(), "L 0 10\nP 235 0 213\nG 50\nH\nL 0 10\n", s);
  EXPECT_EQ(r[0].reply, kNotHomed);
  EXPECT_EQ(r[1].reply, kNotHomed);
  EXPECT_EQ(r[2].reply, kOk);  // the gripper works in Alarm
  const PredictRecord& h = r[3];
  ASSERT_EQ(h.reply, kOk);
  // The shoulder seeks down from step 0 to the step of 36 deg, ceil(-54 / 0.7277) = -74,
  // one homing interval (1 / 200 s) per step and one more to see the switch; then the
  // shoulder stays at its minimum (36 deg) and nothing else moves.
  EXPECT_EQ(h.steps, (std::vector<int32_t>{0, -74, 0}));
  EXPECT_EQ(h.commanded, (std::vector<Millideg>{0, 36000, 0}));
  EXPECT_EQ(h.ticks, 75u * 10000);
  EXPECT_EQ(h.start_tick, r[2].end_tick);
  EXPECT_NE(h.note.find("switch"), std::string::npos);
  EXPECT_EQ(r[4].reply, kOk);
}

TEST(Predict, RoboSimJointsGoThroughTheCoupling) {
  // m: DH joint values; the forearm's elevation is shoulder + elbow = 60 - 80 = -20.
  // The elbow's DH box allows -150 but the forearm motor does not (-60 < -43): M refuses it.
  const std::vector<PredictRecord> rs = run(
      mk2(), {robosim(Statement::Kind::kJoints, {10, 60, -80}, 7), robosim(Statement::Kind::kJoints, {0, 90, -150})});
  const PredictRecord& r = rs[0];
  ASSERT_EQ(r.reply, kOk);
  EXPECT_EQ(r.line, 7);
  EXPECT_EQ(r.text, "m 10 60 -80");
  EXPECT_EQ(r.protocol, "M 10.000 60.000 -20.000");
  EXPECT_EQ(r.commanded, (std::vector<Millideg>{10000, 60000, -20000}));
  EXPECT_EQ(r.steps, (std::vector<int32_t>{32, -41, -27}));
  EXPECT_NEAR(r.joints_ideal[2], -80, 1e-9);
  EXPECT_EQ(r.ticks, profile_duration_ticks(41, kDefaultMotion));
  const PredictRecord& bad = rs[1];
  EXPECT_EQ(bad.reply, kJointLimit);
  EXPECT_EQ(bad.steps, r.steps);
  EXPECT_FALSE(bad.queued);
}

TEST(Predict, RoboSimTargetSolvesAndMovesLikeM) {
  const Vec3<double> p = make_vec3(200.0, 200.0, 160.0);
  const std::vector<PredictRecord> rs =
      run(mk2(), {robosim(Statement::Kind::kTarget, {p.x, p.y, p.z}), robosim(Statement::Kind::kTarget, {900, 0, 0})});
  const PredictRecord& r = rs[0];
  ASSERT_EQ(r.reply, kOk);
  EXPECT_EQ(r.ik_status, "reached");
  EXPECT_EQ(r.protocol.substr(0, 2), "M ");
  expect_near(r.tool_ideal, p, 0.01);
  EXPECT_LT(r.target_error_mm, half_step_reach_mm());
  // The protocol line it stands for gives exactly the same steps.
  const PredictRecord same = run(mk2(), r.protocol + "\n")[0];
  EXPECT_EQ(same.steps, r.steps);
  EXPECT_EQ(same.ticks, r.ticks);
  // Out of reach: refused as P would be, nothing moves.
  const PredictRecord& far = rs[1];
  EXPECT_EQ(far.reply, kUnreachable);
  EXPECT_EQ(far.steps, r.steps);
  EXPECT_FALSE(far.queued);
  EXPECT_NE(far.ik_status, "reached");
}

TEST(Predict, RoboSimWeightsFreezeAJoint) {
  // Straight down in the plane of the base: reachable with the base kept at 30 deg.
  const Vec3<double> now = mk2_tool(30, 70, -20);
  const std::vector<PredictRecord> rs =
      run(mk2(), {robosim(Statement::Kind::kJoints, {30, 70, -90}), robosim(Statement::Kind::kWeights, {0, 1, 1}),
                  robosim(Statement::Kind::kTarget, {now.x, now.y, now.z - 30})});
  ASSERT_EQ(rs[2].reply, kOk) << rs[2].note;
  EXPECT_EQ(rs[2].commanded[0], 30000);
}

TEST(Predict, RoboSimHandAndSpeedAsDocumented) {
  EXPECT_EQ(robosim_hand_to_aperture(0.0), 100000);
  EXPECT_EQ(robosim_hand_to_aperture(0.25), 50000);
  EXPECT_EQ(robosim_hand_to_aperture(0.5), 0);
  EXPECT_EQ(robosim_hand_to_aperture(0.1), 80000);
  EXPECT_EQ(robosim_speed_to_rate(82, 600), 600u);
  EXPECT_EQ(robosim_speed_to_rate(41, 600), 300u);
  EXPECT_EQ(robosim_speed_to_rate(1, 600), 7u);  // round(600 / 82) = 7
  EXPECT_EQ(robosim_speed_to_rate(1, 40), 1u);   // never below 1

  const std::vector<PredictRecord> rs =
      run(mk2(), {robosim(Statement::Kind::kHand, {0.5}), robosim(Statement::Kind::kHand, {0.0}),
                  robosim(Statement::Kind::kSpeed, {41}), robosim(Statement::Kind::kJoints, {10, 90, -90}),
                  robosim(Statement::Kind::kSpeed, {82}), line("$$"), robosim(Statement::Kind::kZoom, {2})});
  EXPECT_EQ(rs[0].protocol, "G 0.000");
  EXPECT_EQ(rs[0].gripper_percent, 0);
  EXPECT_EQ(rs[0].ticks, kSettleTicks);
  EXPECT_EQ(rs[1].protocol, "G 100.000");
  EXPECT_EQ(rs[1].gripper_percent, 100);

  EXPECT_EQ(rs[2].protocol, "$0=300");
  EXPECT_EQ(rs[3].ticks, profile_duration_ticks(32, MotionSettings{2000000, 300, 2000}));
  EXPECT_EQ(rs[3].motion.max_rate, 300u);
  // Always scaled from the rate the program started with, not the last one.
  EXPECT_EQ(rs[4].protocol, "$0=600");

  const PredictRecord& z = rs[6];
  EXPECT_EQ(z.reply, kOk);
  EXPECT_FALSE(z.queued);
  EXPECT_NE(z.note.find("no effect"), std::string::npos);
}

TEST(Predict, RoboSimLengthsChangeOnlyTheHostModel) {
  const Robot r = mk2_adjustable();
  const std::vector<PredictRecord> rs =
      run(r, {line("L 0 10"), robosim(Statement::Kind::kLinkLengths, {150}), line("P 235 0 213")});
  const PredictRecord& before = rs[0];
  const PredictRecord& l = rs[1];
  ASSERT_EQ(l.reply, kOk);
  EXPECT_NE(l.note.find("real arm"), std::string::npos);
  EXPECT_EQ(l.steps, before.steps);
  EXPECT_FALSE(l.queued);
  // The upper arm is vertical at 90 deg: 15 mm longer raises the tool by 15 mm.
  EXPECT_NEAR(l.tool_quantized.z - before.tool_quantized.z, 15, 1e-9);
  // The firmware's P keeps the arm as built: (235, 0, 213) is still its home point.
  const PredictRecord& p = rs[2];
  ASSERT_EQ(p.reply, kOk);
  EXPECT_EQ(p.steps, (std::vector<int32_t>{0, 0, 0}));
}

TEST(Predict, ProgramSummaryAddsUp) {
  const Program prog = parse_protocol_program("G 100\nL 0 10\nL 1 50 # refused\nM 0 60 -20\nS 1\n", "t.arm", mk2());
  const Prediction p = predict_program(mk2(), prog);
  ASSERT_EQ(p.records.size(), 5u);
  EXPECT_EQ(p.rejected, 1);
  EXPECT_EQ(p.records[2].reply, kJointLimit);
  EXPECT_EQ(p.records[2].line, 3);
  uint64_t sum = 0;
  double worst = 0;
  for (const auto& r : p.records) {
    EXPECT_EQ(r.start_tick, sum) << r.text;
    sum += r.ticks;
    worst = std::max(worst, r.error_mm);
  }
  EXPECT_EQ(p.total_ticks, sum);
  EXPECT_EQ(p.total_ticks,
            2 * kSettleTicks + profile_duration_ticks(32, kDefaultMotion) + profile_duration_ticks(41, kDefaultMotion));
  EXPECT_DOUBLE_EQ(p.worst_error_mm, worst);
}

TEST(Predict, ShippedProgramsRun) {
  for (const char* name : {"demo.arm", "thesis-repeatability.arm", "robosim-example.robosim"}) {
    const Program prog = load_program(std::string(ARTICULA_SOURCE_DIR) + "/programs/" + name, mk2());
    const Prediction p = predict_program(mk2(), prog);
    EXPECT_EQ(p.rejected, 0) << name;
    EXPECT_GT(p.total_ticks, 0u) << name;
    EXPECT_LT(p.worst_error_mm, half_step_reach_mm()) << name;
  }
}

TEST(Predict, RobotWithoutMotorsIsRefused) {
  const Robot r = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/thesis-example.json");
  try {
    predict_program(r, parse_protocol_program("L 0 10\n", "t.arm", r));
    FAIL() << "no error";
  } catch (const PredictError& e) {
    EXPECT_NE(std::string(e.what()).find("has no motors"), std::string::npos) << e.what();
  }
}

// A record says which command it is, so the physics replays it without reading its text again.
TEST(Predict, EachRecordNamesItsCommand) {
  const Prediction p = predict_program(mk2(), parse_program("M 0 90 0\nG 50\nD 0.5\nS 1\n$0=500\nT 235 0 213 20\nH\n", "k.arm", mk2()));
  std::vector<CommandType> kinds;
  for (const PredictRecord& r : p.records) kinds.push_back(r.command);
  EXPECT_EQ(kinds, (std::vector<CommandType>{kCmdMoveAbsolute, kCmdAperture, kCmdDwell, kCmdGripper, kCmdSetSetting, kCmdLine,
                                             kCmdHome}));
  // RoboSim's as the protocol line each stands for: m a move, h the gripper, s the top rate
  const Prediction rs = predict_program(mk2(), parse_program("m\n0\n90\n-110\nh\n0.25\ns\n41\nz\n1\n", "k.robosim", mk2()));
  ASSERT_EQ(rs.records.size(), 4u);
  EXPECT_EQ(rs.records[0].command, kCmdMoveAbsolute);
  EXPECT_EQ(rs.records[1].command, kCmdAperture);
  EXPECT_EQ(rs.records[2].command, kCmdSetSetting);
  EXPECT_EQ(rs.records[3].command, kCmdNone);  // z: for a viewer
  // a refused line is no command the arm runs
  const Prediction bad = predict_program(mk2(), parse_program("L 0 500\n", "b.arm", mk2()));
  EXPECT_NE(bad.records[0].reply, kOk);
}

namespace {
// An arm of `n` yaw joints, one stepper each: the Nano drives three, the host's build of the
// firmware eight.
std::string chain_arm(int n) {
  std::string dh, motors, home;
  for (int i = 0; i < n; ++i) {
    const std::string name = "j" + std::to_string(i);
    dh += std::string(i ? ", " : "") + R"({"a": 50, "alpha": 0, "d": 0, "theta": {"joint": ")" + name +
          R"(", "min": -90, "max": 90}})";
    motors += std::string(i ? ", " : "") + R"({"name": ")" + name + R"(", "steps_per_rev": 200, "microsteps": )" +
              (i % 2 ? "16" : "1") + R"(, "gear": [1, 1], "direction": 1, "zero": 0, "min": -90, "max": 90})";
    home += std::string(i ? ", " : "") + "\"" + name + "\": 0";
  }
  return R"({"name": "chain", "dh": [)" + dh + R"(], "motors": [)" + motors + R"(], "home": {)" + home + "}}";
}
}  // namespace

// A robot the Nano cannot take (five motors, some at 1/16 steps) runs on the host's eight-motor
// build of the firmware, which times it: from rest, each move lasts motion.h's profile of its
// dominant motor's steps (the firmware made those steps for those motors). Nine motors are more
// than that build drives: refused, saying so.
TEST(Predict, ArmsTheNanoCannotTakeRunOnTheHostsFirmware) {
  const Robot five = parse_robot(chain_arm(5), "chain5.json");
  const std::string program = "M 10 -20 30 -40 50\nL 4 -25.5\nD 0.2\nM 0 0 0 0 0\n";
  for (SenderModel::Kind kind : {SenderModel::kRest, SenderModel::kStream}) {
    SenderModel sender;
    sender.kind = kind;
    const Prediction p = predict_program(five, parse_protocol_program(program, "chain.arm", five), {}, sender);
    ASSERT_EQ(p.records.size(), 4u);
    for (const PredictRecord& r : p.records) EXPECT_EQ(r.reply, kOk) << r.text;
    EXPECT_EQ(p.records[0].dominant_steps, 356u);  // j3's 40 degrees in 1/16 steps of 1.8 degrees: 355.6
    for (const PredictRecord& r : p.records) {
      if (kind != SenderModel::kRest || r.action != PredictRecord::Action::kMove) continue;
      EXPECT_EQ(r.end_tick - r.start_tick, profile_duration_ticks(r.dominant_steps, ControllerSettings().motion()))
          << r.text;
    }
    EXPECT_EQ(p.records[2].end_tick - p.records[2].start_tick, 400000u);  // D 0.2
    EXPECT_EQ(p.total_ticks, p.records.back().end_tick);
    EXPECT_EQ(p.records.back().steps, std::vector<int32_t>(5, 0));
  }
  const Robot nine = parse_robot(chain_arm(9), "chain9.json");
  try {
    predict_program(nine, parse_protocol_program("L 0 10\n", "chain.arm", nine));
    FAIL() << "nine motors predicted";
  } catch (const PredictError& e) {
    EXPECT_NE(std::string(e.what()).find("9 motors: the firmware drives at most 8"), std::string::npos) << e.what();
  }
}

// Each prediction and each live session runs on a Nano of its own (sitl::Machine), not one
// machine shared under a lock: predictions made in threads at the same time give the records
// that one after the other gives, and a session's firmware goes on from where it was whatever
// ran in between.
TEST(Predict, PredictionsInThreadsGiveTheRecordsOfOneAfterTheOther) {
  const Robot r = mk2();
  const std::vector<std::string> programs = {
      "M 10 80 -10\nG 50\nL 0 -30\nD 0.2\nP 250 0 150\nM 0 90 0\n",
      "$0=900\nM -40 100 -20\nL 1 -25\nG 0\nM 30 70 5\nM 5 95 -5\n",
      "T 250 40 120 30\nT 250 -40 120 30\nM 0 90 0\nD 0.1\n",
  };
  // (Each 40 times over: runs long enough for the threads' to overlap.)
  const auto records = [&](size_t k) {
    std::string text;
    for (int n = 0; n < 40; ++n) text += programs[k];
    const Program p = parse_protocol_program(text, "t" + std::to_string(k), r);
    const Prediction got = predict_program(r, p);
    for (const PredictRecord& rec : got.records) EXPECT_EQ(rec.reply, kOk) << text << " line " << rec.line;
    return prediction_json(r, p, got).dump();
  };
  std::vector<std::string> alone;
  for (size_t k = 0; k < programs.size(); ++k) alone.push_back(records(k));
  for (size_t k = 0; k < programs.size(); ++k) EXPECT_NE(alone[k].find("\"end_tick\""), std::string::npos) << alone[k];

  // Three at a time, each program twice over, in six threads.
  std::vector<std::string> got(2 * programs.size());
  std::vector<std::thread> threads;
  for (size_t i = 0; i < got.size(); ++i) threads.emplace_back([&, i] { got[i] = records(i % programs.size()); });
  for (std::thread& t : threads) t.join();
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], alone[i % programs.size()]) << "thread " << i;

  // A session with a prediction in the middle of its run: the same events as one alone.
  const auto session = [&](bool interrupted) {
    FirmwareSession fw(r);
    std::string out;
    const auto log = [&](uint64_t until) {
      for (const FirmwareSession::Event& e : fw.take(until))
        out += std::to_string(e.kind) + "@" + std::to_string(e.tick) + " ";
    };
    EXPECT_EQ(fw.send("M 20 100 0", 1, 0, FirmwareSession::kStreamed), kOk);
    EXPECT_EQ(fw.send("M -20 80 -10", 2, 0, FirmwareSession::kStreamed), kOk);
    fw.run_to(3 * kStepTickHz / 10);
    log(fw.now());
    if (interrupted) records(1);
    EXPECT_EQ(fw.send("G 80", 3, fw.now(), FirmwareSession::kStreamed), kOk);
    log(fw.run_to_rest());
    return out;
  };
  const std::string alone_session = session(false);
  EXPECT_GT(alone_session.size(), 100u) << alone_session;  // steps, begins, replies
  EXPECT_EQ(session(true), alone_session);
}
