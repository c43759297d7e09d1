// host/lib/predict.h - what the real arm will do with a program, step for step.
//
// predict_program() runs the firmware itself: firmware/src's controller, built for eight motors,
// on a virtual clock (firmware/sitl; predict_run.cpp), fed the program's lines as the sender
// delivers them. Every record is read from what the firmware did: its reply, the plan it left
// (steps and commanded angles), the actions it queued and when each began and ended, the steps
// its coils made, where each '!' left the arm. The host adds RoboSim's statements as protocol
// lines (thesis appendix B: m -> M, a -> IK then M, h -> G, s -> $0; see programs/README.md),
// the tool positions the steps give (the shared core's kinematics) and notes.
//
// The physics runs the same firmware, line by line as it comes (firmware_session.h).
#ifndef ARTICULA_HOST_PREDICT_H
#define ARTICULA_HOST_PREDICT_H

#include <articula/actuation.h>
#include <articula/ik_ypp.h>
#include <articula/motion.h>
#include <articula/planner.h>
#include <articula/settings.h>
#include <articula/status.h>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "ik.h"
#include "program.h"
#include "robot.h"

namespace articula::host {


// The controller's settings, $0 .. $7 (articula/settings.h numbers them and gives their
// ranges and defaults): whole numbers.
struct ControllerSettings {
  static constexpr int kCount = kSettingCount;
  enum Id {
    kMaxRate = kSetMaxRate, kAccel = kSetAccel, kReleaseMs = kSetReleaseMs, kEndstops = kSetEndstops,
    kHomingRate = kSetHomingRate, kSettleMs = kSetSettleMs, kJunction = kSetJunction, kChord = kSetChord
  };
  std::array<uint32_t, kCount> value = defaults();  // the firmware's defaults

  MotionSettings motion() const { return {kStepTickHz, value[kMaxRate], value[kAccel]}; }
  static std::array<uint32_t, kCount> defaults() {
    std::array<uint32_t, kCount> v{};
    for (int n = 0; n < kCount; ++n) v[size_t(n)] = setting_range(uint8_t(n), 3).fallback;
    return v;
  }
};

// The firmware's check of `$n=v` (articula::check_setting for the arm's motors).
Status check_setting(int num_motors, int32_t n, int32_t thousandths);
// The range of a setting, for messages: {min, max}.
std::array<uint32_t, 2> setting_range(int num_motors, int n);

// "0=800,1=3000" (or "$0=800,$1=3000") into `s`, each item read by the protocol codec as a
// `$n=v` line and checked as the firmware checks it. Throws std::invalid_argument with a
// message naming the bad item.
void apply_settings_text(ControllerSettings& s, const std::string& text, int num_motors);

// Why a prediction cannot be made at all (a robot without motors).
class PredictError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What one statement did.
struct PredictRecord {
  int line = 0;      // 1-based line of the statement in its file
  std::string text;  // the statement: the protocol line, or RoboSim's "m 0 90 -90"
  std::string
      protocol;        // RoboSim: the protocol line that does the same on the arm ("M 0.000 90.000 0.000"); "" if none
  Status reply = kOk;  // ok, or the error the controller answers (then nothing changed)
  // The command it is: the protocol line's, or RoboSim's equivalent (m and a: M; h: G; s: $0=).
  // What the physics replays it as, without reading its text again. kCmdNone for a comment,
  // an empty line, a line that did not parse, and RoboSim's l, w and z.
  CommandType command = kCmdNone;
  std::string note;    // what a reader should know (not simulated parts, host-only effects)

  // The state after the statement (unchanged when rejected).
  std::vector<int32_t> steps;            // per motor: the controller's step count (status report S)
  std::vector<Millideg> commanded;       // per motor: the exact commanded angle, millidegrees
  std::vector<double> actuator_deg;      // per motor: the angle the steps really give, degrees
  std::vector<double> joints;            // per joint variable: the value the steps give (deg or mm)
  std::vector<double> joints_ideal;      // per joint variable: from the exact commanded angles
  Vec3<double> tool_ideal{0, 0, 0};      // tool position from the exact commanded angles, mm
  Vec3<double> tool_quantized{0, 0, 0};  // tool position the steps give, mm
  double error_mm = 0;                   // |tool_quantized - tool_ideal|
  int gripper_percent = -1;              // aperture of the last gripper action, whole %; -1 limp (none yet)

  // A target (P, RoboSim a): the point asked for and how far the quantized tool ends from it.
  bool has_target = false;
  Vec3<double> target{0, 0, 0};
  double target_error_mm = 0;
  std::string ik_status;  // RoboSim a: ik.h's status of the solve ("reached", ...)

  // The action in the motion queue; 0 steps and 0 ticks when the statement queued nothing
  // (or a move within the same steps).
  enum class Action { kNone, kMove, kPause, kHome };
  Action action = Action::kNone;
  std::vector<int32_t> delta_steps;  // a move (and Home's final move): per motor
  MotionSettings motion{};           // the settings the action runs with ($0, $1)
  uint32_t junction = 0;             // $6 when it was queued
  bool waits_for_rest = false;       // answered only once the arm was at rest (Z, $n=v while it moves)
  bool queued = false;
  // '!' alone on a line: the realtime stop (never answered). The arm decelerates along its
  // path to rest and empties its queue (the firmware runs it at the tick it arrives); the
  // lines after it wait for rest and start from the steps reached.
  bool stop = false;
  int64_t stop_at = -1;  // a '!' the sender sent at this tick (SenderModel::stop_ticks, after the first step), not after a reply
  uint64_t arrive_tick = 0;  // when the firmware read the line
  // A '!' cut this action short or emptied it from the queue: its steps, delta_steps,
  // dominant_steps and segments are what it really made.
  bool cut = false;
  // T: its segments, each a move of the queue (the record's delta_steps are their sum), and
  // the worst distance of the tool, at every step the motors make, from the straight line.
  struct Segment {
    std::vector<int32_t> delta_steps;
    uint32_t dominant_steps = 0;
    uint16_t cruise4 = 0;  // PlanBlock::cruise4: its own cruise at the tool speed
    uint64_t end_tick = 0;  // when the firmware ended it (as the record's end_tick)
  };
  std::vector<Segment> segments;
  double line_error_mm = -1;  // -1: not a straight line
  // On request (predict_program's path): the tool (mm) after every step of the dominant
  // motor of its moves, the steps spread as the arm spreads them.
  std::vector<Vec3<double>> path;
  uint32_t dominant_steps = 0;  // a move: the most steps any motor makes
  uint64_t ticks = 0;           // duration in 2 MHz ticks
  uint64_t start_tick = 0;      // when the action starts and ends, counted from the first
  uint64_t end_tick = 0;        //   line's arrival (predict_program: the firmware's times)
  double seconds() const { return double(ticks) / kStepTickHz; }
  double start_s() const { return double(start_tick) / kStepTickHz; }
  double end_s() const { return double(end_tick) / kStepTickHz; }
};

// How the lines reach the controller, which decides when each is queued and so how far the
// planner sees ahead (docs/protocol.md, "Timing of moves"). A byte takes 10 bits (8N1) at the
// Nano's real 117,647 baud (it asks for 115,200): firmware/sitl's serial line.
struct SenderModel {
  enum Kind {
    kRest,    // each line once the arm is at rest after the one before (the harness, the
              // page's program runner): every move from rest to rest, as with $6=0
    kStream,  // the next line as soon as the previous one is answered (GRBL's simple sender;
              // a host must wait for each reply: the Nano's receive buffer holds one line)
  };
  Kind kind = kRest;
  // A '!' at each of these ticks after the arm's first step, whatever the lines are doing:
  // a student pressing STOP. A line still waiting to be answered then is answered error:15
  // (Stopped) and does nothing. (From the first step, not the first line: the Nano's own time
  // to read the first lines is not modelled, the steps' times from there on are.)
  std::vector<uint64_t> stop_ticks;
};
const char* sender_name(SenderModel::Kind k);

struct Prediction {
  std::string robot;
  std::string program;
  ControllerSettings settings;  // at power-up
  std::vector<PredictRecord> records;
  int rejected = 0;
  double worst_error_mm = 0;  // largest error_mm of the accepted commands
  uint64_t total_ticks = 0;   // end of the last action
  uint64_t first_step_tick = 0;  // the first step any motor makes (0 if none)
  double total_s() const { return double(total_ticks) / kStepTickHz; }
};

// Inputs driven from outside while the program runs (a cell's wires, cell_predict.h): the
// header pins `pins` (a bit per pin) read `levels(tick)` (ticks from the first line, as the
// records') at each tick the firmware reads them; it may run other arms' firmwares up to that
// tick. None: every input reads its pull-up (or its own output).
struct DrivenInputs {
  uint32_t pins = 0;
  std::function<uint32_t(uint64_t tick)> levels;
};

// Runs a whole program on the firmware (predict_run.cpp), each line as `sender` delivers it,
// the timed '!'s at their ticks after the first step, the arm powered up with `settings`.
// Throws PredictError for a robot without motors or one the firmware cannot drive (more than
// eight motors), std::logic_error if the firmware's own accounts disagree (a bug).
// With `path`, each record that moves keeps the tool at every step (PredictRecord::path).
Prediction predict_program(const Robot& robot, const Program& program, const ControllerSettings& settings = {},
                           const SenderModel& sender = {}, bool path = false, const DrivenInputs& inputs = {});

// RoboSim's h (0.0 open .. 0.5 closed) as G's aperture in thousandths of a percent:
// 100 % - 200 % * h, rounded to a thousandth (h 0 -> 100000, 0.25 -> 50000, 0.5 -> 0).
int32_t robosim_hand_to_aperture(double h);
// RoboSim's s (1 .. 82) as $0: the top step rate scaled, round(base * s / 82), at least 1
// (s 82 is `base`, the $0 the program started with).
uint32_t robosim_speed_to_rate(double s, uint32_t base);

}  // namespace articula::host

#endif  // ARTICULA_HOST_PREDICT_H
