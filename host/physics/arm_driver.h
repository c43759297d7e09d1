// host/physics/arm_driver.h - what moves one arm of the world (world.h): for a robot with
// motors its own firmware, firmware/src on a virtual Nano of its own (firmware_session.h), whose
// coils' steps move the arm's body at their ticks; for a robot without motors the kinematic
// model (run.h), whose actions the body follows as ideal position servos.
#ifndef ARTICULA_PHYSICS_ARM_DRIVER_H
#define ARTICULA_PHYSICS_ARM_DRIVER_H

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "firmware_session.h"
#include "program.h"
#include "run.h"
#include "world.h"

namespace articula::host {

class ArmBody;

class ArmDriver {
 public:
  // The controller powers up with the options' settings; it stays for the arm's life.
  ArmDriver(ArmBody& body, const SimOptions& options);
  ~ArmDriver();
  ArmDriver(const ArmDriver&) = delete;
  ArmDriver& operator=(const ArmDriver&) = delete;

  // The program the arm runs from `now_tick`: each line sent to the firmware once the arm is at
  // rest after the one before (as the harness and the studio's runner send), from where the
  // firmware is; a robot without motors: the kinematic model from where it is (replacing what
  // it queued). Commands refused become kRejected events when the clock reaches them.
  void load_program(const Program& program, uint64_t now_tick);
  // The same, each line sent as the clock comes to it rather than ahead of it (a cell's arms,
  // whose waits depend on one another's outputs): the program's end is known once reached.
  // For a robot without motors, load_program.
  void feed_program(const Program& program, uint64_t now_tick);
  // One protocol line (docs/protocol.md) to the firmware at `now_tick`, or as soon as the reply
  // before is off the wire (a streamed program); its reply. A rejected line changes nothing.
  Status command(const std::string& line, uint64_t now_tick);
  bool busy() const;
  // When the program ends (the arm at rest after its last line); for a program fed as the
  // clock runs, where its firmware's clock is until it has.
  double program_end() const;

  // The controller up to `until` (the end of a world step of dt s, at t_end): the firmware's
  // events at their ticks (steps, actions, the gripper) or the kinematic model's actions.
  void advance(uint64_t until, double t_end, double dt);
  // The refusals whose time has come (t <= t_end), in order.
  void take_rejections(double t_end, std::vector<SimEvent>& out);

  // The firmware's session (null for a robot without motors): its records and clock.
  const FirmwareSession* firmware() const { return firmware_.get(); }
  FirmwareSession* firmware() { return firmware_.get(); }

  // Every step the firmware's coils make, at its tick, once asked for (tests: an arm in a cell
  // steps as it does alone).
  struct StepRecord {
    uint64_t tick;
    uint8_t mask, negative;
    bool operator==(const StepRecord& o) const { return tick == o.tick && mask == o.mask && negative == o.negative; }
  };
  void log_steps(bool on) { log_steps_ = on; }
  const std::vector<StepRecord>& step_log() const { return step_log_; }

  // Every output the firmware set (O) and every input wait (W): when it began and when it
  // ended (the next action began, or the step timer stopped), as the clock reaches them; a
  // cell's timeline and its tests.
  struct Signal {
    enum Kind { kOutput, kWait } kind = kOutput;
    int line = 0;
    int pin = -1, level = 0;  // the header pin and its level (set, or waited for)
    uint64_t tick = 0;        // set; the wait's beginning
    bool ended = false;       // kWait: it ended (it may end at the tick it began), at end_tick
    uint64_t end_tick = 0;
    bool met = false;         // kWait, ended: its input read its level (else it ran out: a fault)
    bool waiting() const { return kind == kWait && !ended; }
  };
  const std::vector<Signal>& signals() const { return signals_; }

 private:
  struct Action;

  void reset_controller();
  void restart(uint64_t now_tick, bool fed);
  void enqueue(const Statement& st, uint64_t now_tick);
  Status send(const Statement& st, uint64_t now_tick, FirmwareSession::Sender sender);
  void rejected(uint64_t tick, int line, const std::string& text, Status s, const std::string& note);
  void motor_events(uint64_t until);
  void joint_follow(double t_end, double dt);
  void begin_action(size_t index);
  void end_action();

  ArmBody& body_;
  const Robot& robot_;
  SimOptions opt_;
  bool motors_ = false;
  int n_joints_ = 0;

  // The firmware itself on its virtual clock (a robot with motors; its lines from a program's
  // statements: lines_, on a copy of the robot that RoboSim's l may change), or the kinematic
  // model and what it has queued so far: where the queue ends, the joints and gripper it leaves.
  std::unique_ptr<FirmwareSession> firmware_;
  Robot lines_robot_;
  std::unique_ptr<StatementLines> lines_;
  std::unique_ptr<KinematicModel> kinematic_;
  uint64_t queue_end_tick_ = 0;
  std::vector<double> queued_q_, q_cmd_;
  int queued_percent_ = -1;

  // The kinematic model's program.
  std::vector<Action> actions_;
  size_t action_ = 0;  // the action running or next
  bool action_running_ = false;
  double program_end_s_ = 0;

  // A program fed as the clock runs (feed_program): its statements, the next one, and the text
  // of each line sent (by line number) for its refusal.
  bool fed_ = false;
  Program fed_program_;
  size_t fed_next_ = 0;
  std::map<int, std::string> fed_text_;

  std::vector<SimEvent> pending_;  // rejected commands, shown when the clock reaches them
  size_t pending_next_ = 0;
  bool log_steps_ = false;
  std::vector<StepRecord> step_log_;
  std::vector<Signal> signals_;
};

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_ARM_DRIVER_H
