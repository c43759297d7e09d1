// host/lib/firmware_session.h - the firmware on its virtual clock as a live session drives it
// (the physics: a program sent line by line, commands as they come): lines in; the coil steps,
// the actions it began and its replies out, each at its tick.
//
// The firmware is firmware/src itself, the host's eight-motor build (firmware/sitl), powered up
// with the robot's arm and the settings as predict_program() powers it up. It runs ahead of
// the caller only as far as a reply needs (a line waits for it), so a line sent while the arm
// moves is planned into the moves ahead as on the Nano; run_to() brings it to the caller's time.
// Each session is a Nano of its own (sitl::Machine): sessions and predictions run side by side,
// each on its own firmware, in one thread by turns or in threads of their own (one thread at a
// time for one session).
//
//   FirmwareSession fw(robot, settings);
//   fw.send("M 0 90 0", 1, now, FirmwareSession::kAtRest);  // its reply (Status)
//   fw.run_to(until);
//   for (const FirmwareSession::Event& e : fw.take(until)) ...   // in tick order
#ifndef ARTICULA_HOST_FIRMWARE_SESSION_H
#define ARTICULA_HOST_FIRMWARE_SESSION_H

#include <articula/motion.h>
#include <articula/status.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "predict.h"
#include "program.h"
#include "robot.h"

namespace sitl {
class Machine;
}

namespace articula::host {

class InverseKinematics;

// A program's statements as the lines the host sends for them: a protocol line as it is
// ('!' alone: the realtime stop; a '!' or '?' inside a line is not sent with it), RoboSim's
// as the protocol commands that do the same (thesis appendix B; programs/README.md): m -> M,
// a -> IK from `commanded()` (the firmware's plan when the line goes) then M, h -> G,
// s -> $0 scaled from `base_rate`. The host-only ones (l: `robot`'s link lengths, w, z; a line
// the protocol cannot parse; an a without a solution) give no line.
class StatementLines {
 public:
  StatementLines(Robot& robot, uint32_t base_rate, std::function<std::vector<Millideg>()> commanded);
  ~StatementLines();
  // The record of `st` (its line, text, protocol, command, a reply of the host's own, notes);
  // true when it is to be sent as `line`.
  bool begin(const Statement& st, PredictRecord& r, std::string& line);

 private:
  void robosim(const Statement& st, PredictRecord& r);
  Robot& robot_;  // its model changes with RoboSim's l
  uint32_t base_rate_;
  std::function<std::vector<Millideg>()> commanded_;
  std::vector<double> weights_;
  std::unique_ptr<InverseKinematics> ik_;
};

class FirmwareSession {
 public:
  // What the firmware did.
  struct Event {
    enum Kind {
      kStep,   // the coils made a step: `mask` a bit per motor, `negative` those towards fewer steps
      kBegin,  // it took an action off its queue and began it
      kIdle,   // its step timer stopped: the action running (if any) ended
      kReply,  // it answered a line
    };
    Kind kind = kStep;
    uint64_t tick = 0;
    uint8_t mask = 0, negative = 0;  // kStep
    int line = 0;                    // kBegin: the line that queued it; kReply: the line answered
    enum Action { kMove, kGripper, kHome, kDwell, kOutput, kWaitIn } action = kMove;  // kBegin (queue::Kind)
    std::vector<int32_t> delta;      // kBegin, kMove and kHome: its steps from the plan before it
    MotionSettings motion{};         // kBegin: $0 and $1 when it began
    int percent = -1;                // kBegin, kGripper: the aperture, whole percent
    uint64_t settle_ticks = 0;       // kBegin, kGripper and kDwell: its pause
    std::vector<int32_t> counted;    // kBegin, kIdle; kReply to Z: the firmware's step counts then
    Status status = kOk;             // kReply
    std::string text;                // kReply: the line
    int pin = -1, level = -1;        // kBegin, kOutput and kWaitIn: the header pin and its level
  };

  enum Sender {
    kAtRest,    // once the arm is at rest after the reply before (a program, as the harness sends)
    kStreamed,  // as soon as the reply before is off the wire (GRBL's simple sender)
  };

  // Throws PredictError for a robot without motors, or one the firmware cannot drive.
  FirmwareSession(const Robot& robot, const ControllerSettings& settings = {});
  ~FirmwareSession();
  FirmwareSession(const FirmwareSession&) = delete;
  FirmwareSession& operator=(const FirmwareSession&) = delete;

  // Sends `text` (a protocol line, or '!' alone: the realtime stop, never answered) no earlier
  // than `tick`, as `sender` sends; runs the firmware until it answers. Returns the reply
  // (kOk for a '!').
  Status send(const std::string& text, int line, uint64_t tick, Sender sender);
  // Runs the firmware up to `tick` (nothing if it is there already).
  void run_to(uint64_t tick);
  // Runs it until the arm is at rest; the tick it got there.
  uint64_t run_to_rest();
  // The events up to `tick` not taken yet, in order.
  std::vector<Event> take(uint64_t tick);
  // The firmware's clock, and whether its arm is at rest then with nothing queued.
  uint64_t now() const { return now_; }
  bool at_rest();
  // Events not taken yet.
  bool pending() const { return !events_.empty(); }
  // The controller's plan now: its commanded angles, millidegrees (for RoboSim's a).
  std::vector<Millideg> commanded();

  // A program sent as the clock runs, not ahead of it (a cell's arms, whose waits depend on
  // each other): whenever the arm is at rest after the reply to the line before, `next` is
  // asked at that tick for the next line (its text and its line number); false: no more.
  // Its replies are kReply events. Nothing else may be sent until it is over.
  using Feed = std::function<bool(uint64_t tick, std::string& text, int& line)>;
  void feed(Feed next);
  // The feed still has lines to send or replies to wait for, or the arm is not at rest after
  // its last line; when it is over, the tick it was (the arm at rest after its last reply).
  bool feeding() const { return static_cast<bool>(feed_); }
  uint64_t feed_ended() const { return feed_ended_; }

  // Inputs driven from outside (a cell's wires): header pins `driven` (a bit per pin) read
  // what `levels(tick)` gives at the tick the firmware reads them, asked then (it may run
  // other machines up to that tick; never this one).
  void drive_inputs(uint32_t driven, std::function<uint32_t(uint64_t tick)> levels);
  // Header pin `pin`'s level as this machine drove it at `tick` (not after its clock): an
  // output's, or its pull-up's (high) before it was ever set.
  bool output_level(int pin, uint64_t tick);
  // Header pin `pin`'s level as the firmware reads it at `tick`: an output's, what drives an
  // input on a wire (`levels`), else its pull-up's (high). (Asked for a tick the machine has
  // run to: what its own read then saw.)
  bool input_level(int pin, uint64_t tick);
  // Where the machine's clock is, even in the middle of running (a wire's reader asks).
  uint64_t clock();
  // The input wait the firmware is in now (W), if any: its header pin and the level it waits for.
  struct InputWait {
    int pin = -1, level = 0;
  };
  std::optional<InputWait> waiting();

 private:
  struct Sent {
    std::string text;
    int line;
    uint64_t at;   // when its first byte went on the wire
    bool at_once;  // all its bytes in at `at` (the first line, a line at rest), or byte after byte
  };
  void put(const Sent& x);  // its bytes to the machine (its clock at x.at)
  void wait_reply(size_t replies);
  void harvest();      // the machine's new log entries into events_
  void run_feeding(uint64_t until);  // the machine's clock to `until`, sending the feed's lines
  bool feed_next();                  // at rest after the last reply: the next line sent

  Robot robot_;
  ControllerSettings settings_;
  std::unique_ptr<sitl::Machine> nano_;  // its own firmware (firmware/sitl/machine.h)
  bool sent_any_ = false;         // a line was sent (the first goes in at once)
  std::deque<Sent> unanswered_;  // the lines still waiting for their reply, in order
  uint64_t now_ = 0;             // the machine's clock (counted from power-up)
  uint64_t wire_ = 0;            // when the last reply is off the wire
  std::deque<Event> events_;
  // Where the harvest is in the machine's logs.
  size_t coils_ = 0, actions_ = 0, replies_ = 0, queued_ = 0, next_begin_ = 0;
  std::vector<int> line_of_;     // each queued action's line (by its place in the machine's log)
  uint64_t t0_ = 0;              // the machine's clock at power-up
  std::function<uint32_t(uint64_t tick)> levels_;  // drive_inputs'
  Feed feed_;                    // the program being fed (empty: none, or it has no more)
  size_t feed_answers_ = 0;      // the machine's reply count that means the last fed line is answered (0: none waited for)
  uint64_t feed_ended_ = 0;
};

}  // namespace articula::host

#endif  // ARTICULA_HOST_FIRMWARE_SESSION_H
