// firmware/src/controller.cpp - the firmware's entry points (firmware.h): reads lines, runs
// commands, answers each line once, sends reports, feeds the motion queue, handles '!'.
//
// Every line ends in exactly one reply, and only reply() sends one. A line is checked at
// once, and a bad one answered at once. A good one that must wait (a queued command while
// the queue is full; Z and $n=v until the queue is empty and the arm at rest) is held,
// parsed, as the *pending* line, and run when it can; meanwhile bytes are still read until
// one more complete line is in (the *held* line), then reading stops until the pending one
// is answered. Realtime bytes never wait: '!' raises the stop flag from the receive
// interrupt (on_realtime), which the step interrupt and the next poll() act on; '?' has the
// HAL build a status report with status_line() in interrupt context and send it at the next
// line boundary, whatever the main loop is doing (a P's inverse kinematics takes ms).
#include "firmware.h"

#include <articula/line.h>
#include <articula/planner.h>
#include <articula/protocol.h>

#include "coils.h"
#include "controller.h"
#include "gripper.h"
#include "hal.h"
#include "queue.h"
#include "robot.h"
#include "settings.h"
#include "stepper.h"

using namespace articula;

namespace {

const uint8_t kJ = robot::kJoints;
const uint8_t kVersion[3] = {0, 1, 0};
// execute()'s answer for "not yet": not a status code.
const uint8_t kWait = 0xFF;

using controller::Command;

// Every report is written by the protocol's write_* into a buffer of the size the protocol
// gives for it (status_report_size, kInfoReportSize, kSettingLineSize: the longest line
// of its kind, so no check per character), then sent. One sink type: the Nano holds one copy
// of each writer, and a character costs a store, not a call (the status report is built in
// an interrupt, character by character).
struct LineSink {
  char* p;
  void put(char c) { *p++ = c; }
};

void write_line(const char* buf, const LineSink& end) {
  for (const char* c = buf; c != end.p; ++c) hal::serial_write(*c);
}

// The controller's state (controller.h), in the firmware's (state.h).
inline controller::Ram& ctl() { return controller::ram(); }

void reply(uint8_t status) {
  char buf[kReplySize];
  LineSink out = {buf};
  write_reply(out, Status(status));
  write_line(buf, out);
  hal::replied(status);
}

bool busy() { return stepper::busy() || !queue::empty(); }

// Not inlined (nor list_settings()): their line buffers are then on the stack only while
// they run, not under every command (P's is the main loop's deepest path).
__attribute__((noinline)) void send_info() {
  InfoReport r;
  for (uint8_t i = 0; i < 3; ++i) r.version[i] = kVersion[i];
  r.protocol = kProtocolVersion;
  r.num_joints = robot::count();
  for (uint8_t n = 0; n <= kMaxRobotName; ++n) r.name[n] = robot::config().name[n];
  r.checksum = robot::checksum();
  r.warning = settings::take_warning();
  char buf[kInfoReportSize];
  LineSink out = {buf};
  write_info(out, r);
  write_line(buf, out);
}

__attribute__((noinline)) void list_settings() {
  for (uint8_t n = 0; n < settings::kCount; ++n) {
    char buf[kSettingLineSize];
    LineSink out = {buf};
    write_setting(out, n, int32_t(settings::value()[n]) * 1000);
    write_line(buf, out);
  }
}

// After a stop or a failed homing: the commanded angles become those of the steps the
// motors really reached (the A field of a status report).
void rederive_planned() {
  ctl().last_steps = 0;
  stepper::read_positions(ctl().planned.steps);
  for (uint8_t i = 0; i < kJ; ++i) ctl().planned.commanded[i] = steps_to_millideg(robot::motor(i), ctl().planned.steps[i]);
}

// As at power-up: the motors at step 0, homed unless endstops are fitted.
void reset_position() {
  ctl().last_steps = 0;
  for (uint8_t i = 0; i < kJ; ++i) ctl().planned.steps[i] = 0;  // the motors a configuration leaves unused too
  reset(ctl().planned, robot::actuation());
  stepper::set_positions(ctl().planned.steps);
  ctl().homed = settings::value()[settings::kEndstops] == 0;
}

// P's and T's closed form (articula/line.h, ypp_point_angles: a tool point in mm to the
// in-limits actuator angles nearest `near`) and T's forward kinematics, through the Nano's
// one copy of each. solve() is not inlined: the inverse kinematics' frame (its four
// solutions and more, ~120 B) is off the stack again before move_absolute() runs, the
// deepest path of the main loop, on top of which a status report and the step interrupt
// may come.
struct Solver {
  __attribute__((noinline)) Status solve(Millideg* out, const float* p, const Millideg* near) const {
    return ypp_point_angles(out, robot::config().arm, robot::config().actuation.motors, make_vec3(p[0], p[1], p[2]), near);
  }
  void tool(float* p, const Millideg* act) const { ypp_tool_at(p, robot::config().arm, act); }
};

// Micrometres (or thousandths of mm/s) to mm (mm/s).
void to_mm(float* out, const int32_t* um, uint8_t n) {
  for (uint8_t k = 0; k < n; ++k) out[k] = float(um[k]) * 0.001f;
}

Status solve_point(robot::State& next, const int32_t* um) {
  if (!robot::config().has_point) return kNoClosedForm;
  Millideg best[kJ];
  float p[3];
  to_mm(p, um, 3);
  const Status s = Solver().solve(best, p, ctl().planned.commanded);
  return s != kOk ? s : move_absolute(next, robot::actuation(), best);
}

// The commands that take a place in the queue (D too: held while the queue is full, it
// waited with no room and was answered error:255).
bool is_queued(CommandType t) { return (t <= kCmdHome && t != kCmdNone) || (t >= kCmdDwell && t != kCmdName); }

// What a valid line still waits for: room in the queue, or (Z, $n=v) the arm at rest with
// nothing queued.
// The robot configuration's `$1xx=` only stage (config.h): they do not wait; its commit
// `$199=` does.
bool must_wait(const Command& c) {
  if (is_queued(c.type)) return queue::full();
  const bool settles = c.type == kCmdSetSetting && (c.arg[0] < 100 || c.arg[0] == kCommitSetting);
  return (c.type == kCmdSetZero || settles) && busy();
}

// A configuration put in use: the coils, the step constants, the position as at power-up.
// The pins O and W may use: inputs with their pull-ups (after the servos took theirs).
void free_pins_to_inputs() { hal::io_inputs(~robot::kept_pins() & board::kAllHeaderPins); }

void adopt_configuration() {
  coils::setup();
  free_pins_to_inputs();
  stepper::update_constants();
  reset_position();
}

// `$1xx=v`, `$199=crc`: the robot configuration. Not inlined: a commit reads the staged
// configuration into a copy (about 250 B), which would otherwise sit in execute()'s frame under
// every command (a T's inverse kinematics is the deepest path).
__attribute__((noinline)) uint8_t configure(int32_t n, int32_t v) {
  if (n != kCommitSetting) return robot::stage(uint16_t(n), v);
  if (v < 0 || v % 1000 != 0) return kConfigChecksum;
  if (busy()) return kWait;
  const Status s = robot::commit(v / 1000);
  if (s != kOk) return s;
  adopt_configuration();
  return kOk;
}

// Into the queue, planned (articula/planner.h): a move's junction level with the move queued
// before it (none when the arm is at rest with nothing queued, or after another action),
// kept below the cruise levels of both (a T segment's own cruise: the segment lasts `ticks4`
// at its tool speed, articula/line.h; 0: $0's), then the reverse pass, then the move under
// way told how fast it may end.
// Not inlined: its frame (and the junction's) is not on the stack under P's inverse kinematics.
__attribute__((noinline)) void push_planned(queue::Action& a, uint32_t ticks4 = 0) {
  a.plan.steps = 0;
  a.plan.max_entry = a.plan.entry = 0;
  a.plan.cruise4 = 0;
  if (a.kind == queue::kMove) {
    int32_t delta[kJ];
    uint32_t n = 0;
    for (uint8_t i = 0; i < kJ; ++i) {
      delta[i] = a.target[i] - ctl().planned.steps[i];
      n = max_of(n, uint32_t(delta[i] < 0 ? -delta[i] : delta[i]));
    }
    a.plan.steps = uint16_t(min_of(n, uint32_t(0xFFFF)));
    a.plan.cruise4 = segment_cruise4(n, ticks4);
    const uint32_t cruise = stepper::constants().cruise;
    const uint16_t cap = cruise_level_cap(stepper::motion_settings(), cruise, block_cruise(a.plan, cruise));
    if (ctl().last_steps != 0 && busy())
      a.plan.max_entry = min_of(min_of(cap, ctl().last_cap),
                                junction_level<kJ>(ctl().last_delta, ctl().last_steps, delta, n, kJ, settings::value()[settings::kJunction]));
    for (uint8_t i = 0; i < kJ; ++i) ctl().last_delta[i] = delta[i];
    ctl().last_steps = n;
    ctl().last_cap = cap;
  } else {
    ctl().last_steps = 0;
  }
  hal::action_queued(a);
  queue::push(a);
  queue::replan();
  stepper::raise_exit();
}

// A move (or Home) to `next` into the queue, planned; `ticks4`: a T segment's duration at its
// speed (0: not a segment). A move within the same steps changes only the commanded angles.
void queue_action(queue::Action& a, const robot::State& next, uint32_t ticks4 = 0) {
  bool moves = a.kind == queue::kHome;
  for (uint8_t i = 0; i < kJ; ++i) {
    a.target[i] = next.steps[i];
    moves = moves || next.steps[i] != ctl().planned.steps[i];
  }
  if (moves) push_planned(a, ticks4);
  ctl().planned = next;
}

// Commands that go through the queue: validated against the planned state (which nothing
// but this line changes while it waits), then queued when there is room.
uint8_t queue_command(const Command& c) {
  robot::State next = ctl().planned;
  queue::Action a;
  a.kind = queue::kMove;
  a.mask = 0;
  Status s = kOk;
  switch (c.type) {
    case kCmdRotate:
    case kCmdMoveAbsolute:
    case kCmdMoveTool:
      if (!ctl().homed) return kNotHomed;
      s = c.type == kCmdRotate         ? move_relative(next, robot::actuation(), uint8_t(c.arg[0]), c.arg[1])
          : c.type == kCmdMoveAbsolute ? move_absolute(next, robot::actuation(), c.arg)
                                       : solve_point(next, c.arg);
      if (s != kOk) return s;
      break;
    case kCmdGripper:
    case kCmdAperture: {
      if (queue::full()) return kWait;
      const int32_t aperture = command_aperture(c);
      a.kind = queue::kGripper;
      a.grip.pulse_us = gripper::pulse_us(aperture);
      a.grip.percent = aperture_percent(aperture);
      a.grip.settle_ticks = settings::value()[settings::kSettleMs] * (hal::kTickHz / 1000);
      push_planned(a);
      return kOk;
    }
    case kCmdDwell:  // the parser checked its range
      if (queue::full()) return kWait;
      a.kind = queue::kDwell;
      a.grip.settle_ticks = uint32_t(c.arg[0]) * (hal::kTickHz / 1000);
      push_planned(a);
      return kOk;
    case kCmdOutput:
    case kCmdWaitInput:  // O pin level, W pin level seconds (the parser checked the ranges)
      if (robot::kept_pins() & (uint32_t(1) << c.arg[0])) return kPinUnavailable;
      if (queue::full()) return kWait;
      a.kind = c.type == kCmdOutput ? queue::kOutput : queue::kWaitIn;
      a.mask = uint8_t(c.arg[0]);
      a.grip.percent = uint8_t(c.arg[1]);
      a.grip.settle_ticks = uint32_t(c.arg[2]);  // W's milliseconds
      push_planned(a);
      return kOk;
    case kCmdHome: {
      // Switch motors end at their minimum angle, the others at the home pose.
      const uint8_t mask = uint8_t(settings::value()[settings::kEndstops]);
      for (uint8_t i = 0; i < kJ; ++i) {
        const MotorSpec& m = robot::motor(i);
        next.commanded[i] = (mask & (1u << i)) ? m.min : robot::config().home[i];
        next.steps[i] = quantize_within_limits(m, next.commanded[i]);
      }
      a.kind = queue::kHome;
      a.mask = mask;
      break;
    }
    default:
      return kUnknownCommand;  // not reached: execute() routes the others
  }
  if (queue::full()) return kWait;
  if (a.kind == queue::kHome) ctl().homed = true;  // until the search fails
  queue_action(a, next);
  return kOk;
}

// T: the tool along a straight line (articula/line.h). The first time, the whole line is cut
// once to check it (nothing queued: a line the arm cannot follow is refused before anything
// moves); then again, its segments queued as there is room (the line waits as a pending one
// while the queue is full) and answered once the last is in.
void start_line(const Command& c) {
  float from[3], to[4];  // x, y, z in mm, and the speed in mm/s
  to_mm(to, c.arg, 4);
  Solver().tool(from, ctl().planned.commanded);
  ctl().cut.start(from, to, ctl().planned.commanded, kJ,
              float(int32_t(settings::value()[settings::kChord])) * 0.001f);
  ctl().cut_speed = to[3];
}

uint8_t line_command(const Command& c) {
  if (!ctl().homed) return kNotHomed;
  if (!robot::config().has_point) return kNoClosedForm;
  Millideg end[kJ];
  if (!ctl().cutting) {
    start_line(c);
    while (!ctl().cut.done()) {
      const Status s = ctl().cut.next(Solver(), end);
      if (s != kOk) return s;
    }
    start_line(c);
    ctl().cutting = true;
  }
  while (!ctl().cut.done()) {
    if (queue::full()) return kWait;
    ctl().cut.next(Solver(), end);  // as it was when checked
    robot::State next = ctl().planned;
    move_absolute(next, robot::actuation(), end);  // within the limits: checked
    queue::Action a;
    a.kind = queue::kMove;
    a.mask = 0;
    queue_action(a, next, segment_ticks4(ctl().cut.segment_length(), ctl().cut_speed, hal::kTickHz));
  }
  ctl().cutting = false;
  return kOk;
}

uint8_t execute(const Command& c) {
  switch (c.type) {
    case kCmdNone:
      return kOk;
    case kCmdInfo:
      send_info();
      return kOk;
    case kCmdListSettings:
      list_settings();
      return kOk;
    case kCmdName:  // the text is in the line just read: a name never waits
      return robot::stage_name(ctl().line.line() + c.arg[0], uint8_t(c.arg[1]));
    case kCmdSetSetting: {
      if (c.arg[0] >= 100) return configure(c.arg[0], c.arg[1]);
      const Status s = settings::check(c.arg[0], c.arg[1]);
      if (s != kOk) return s;
      if (busy()) return kWait;
      settings::set(c.arg[0], c.arg[1]);
      stepper::update_constants();
      return kOk;
    }
    case kCmdSetZero:
      if (busy()) return kWait;
      for (uint8_t i = 0; i < kJ; ++i) {
        ctl().planned.commanded[i] = robot::config().home[i];
        ctl().planned.steps[i] = robot::home_steps()[i];
      }
      stepper::set_positions(ctl().planned.steps);
      coils::attach_servos(ctl().planned.steps);  // a servo's pulse is its position: they go home at once
      ctl().homed = true;
      ctl().last_steps = 0;
      return kOk;
    case kCmdLine:
      return line_command(c);
    default:
      return queue_command(c);
  }
}

void run_line(LineEvent ev) {
  if (ev == kLineTooLongEnded) {
    reply(kLineTooLong);
    return;
  }
  const Status s = parse_line(ctl().pending, ctl().line, robot::count());
  if (s != kOk) {
    reply(s);
    return;
  }
  const uint8_t r = execute(ctl().pending);
  if (r == kWait) {
    ctl().has_pending = true;
    return;
  }
  reply(r);
}

// Reads bytes until a line is complete (kept in ctl().held) or none are waiting.
void read_ahead() {
  while (ctl().held == kLineNone) {
    const int16_t c = hal::serial_read();
    if (c < 0) return;
    ctl().held = ctl().line.feed(char(c));
  }
}

void service_lines() {
  if (ctl().has_pending) {
    // Valid when first run; what it waits for is checked cheaply (P's inverse kinematics
    // runs again only once there is room).
    // (A T still queueing its segments waits again when the queue fills.)
    const uint8_t r = must_wait(ctl().pending) ? kWait : execute(ctl().pending);
    if (r == kWait) {
      read_ahead();
      return;
    }
    reply(r);
    ctl().has_pending = false;
  }
  read_ahead();
  if (ctl().held != kLineNone && !stepper::stop_requested()) {  // a line after a '!' waits for rest
    const LineEvent ev = ctl().held;
    ctl().held = kLineNone;
    run_line(ev);
  }
}

// '!': empty the queue and answer the waiting lines at once; once the arm is at rest, take
// the position it reached and read lines again.
void service_stop() {
  if (!ctl().stop_flushed) {
    stepper::cut_pause();
    ctl().cutting = false;
    if (ctl().has_pending) {  // and the line read behind it, if any
      reply(kStopped);
      if (ctl().held != kLineNone) reply(kStopped);
      ctl().has_pending = false;
      ctl().held = kLineNone;
    }
    ctl().stop_flushed = true;
  }
  if (!stepper::busy()) {  // the queue kept the moves a stop at speed runs on into
    queue::clear();
    rederive_planned();
    ctl().stop_flushed = false;
    stepper::clear_stop();
  }
}

}  // namespace

namespace firmware {

// Not inlined into the HAL's interrupt code: its large frame is then set up after the HAL has
// enabled interrupts again, not before.
__attribute__((noinline)) uint8_t status_line(char* buf, uint8_t cap) {
  // In interrupt context (the HAL's '?'), preempting the main loop anywhere: everything the
  // report says is read in one critical section of a few microseconds, so it is one moment's
  // state (the step interrupt changes positions and the queue, the main loop the rest).
  StatusReport<kJ> r;
  const uint8_t s = hal::interrupts_off();
  stepper::read_positions(r.steps);
  const bool stop = stepper::stop_requested(), homing = stepper::homing();
  const bool running = stepper::busy(), homed = ctl().homed;
  const uint8_t queued = queue::count();
  r.gripper = stepper::gripper_percent();
  r.coils = coils::on();
  hal::interrupts_restore(s);
  // (The pins' levels need no critical section: outside it, they keep the step interrupt's
  // deadlines where they were.)
  r.io = int32_t(hal::io_levels() & ~robot::kept_pins() & board::kAllHeaderPins);
  r.state = stop                        ? kStateStop
            : homing                    ? kStateHome
            : (running || queued != 0)  ? kStateRun
            : homed                     ? kStateIdle
                                        : kStateAlarm;
  r.num_joints = robot::count();
  // '!' empties the queue: what a stop at speed still runs on into is not the host's any more.
  r.free_slots = stop ? queue::kSize : uint8_t(queue::kSize - queued);
  for (uint8_t i = 0; i < r.num_joints; ++i) r.millideg[i] = robot::step_angle(i, r.steps[i]);
  r.warning = settings::take_warning();
  if (cap < status_report_size(kJ)) return 0;
  LineSink out = {buf};
  write_status(out, r);
  return uint8_t(out.p - buf);
}

// Not inlined into main(): the set-up's locals (robot::setup's 3 x 4 system, the settings
// image) would take stack for good under the main loop.
__attribute__((noinline)) void setup() {
  robot::setup();
  settings::load();
  coils::setup();
  free_pins_to_inputs();
  queue::clear();
  stepper::setup();
  ctl().line.clear();
  ctl().has_pending = false;
  ctl().held = kLineNone;
  ctl().stop_flushed = false;
  ctl().cutting = false;
  reset_position();
  ctl().was_busy = false;
  ctl().idle_since = hal::millis();
}

void poll() {
  const uint8_t fault = stepper::take_fault();
  if (fault != stepper::kNoFault) {  // nothing queued runs
    queue::clear();
    rederive_planned();
    if (fault == stepper::kHomingFailed)
      ctl().homed = false;  // position unknown
    else
      settings::warn(kInputTimeout);  // (the next report says so)
  }
  if (stepper::stop_requested()) service_stop();
  if (!stepper::stop_requested()) {
    service_lines();
    stepper::kick();
  }
  const uint32_t now = hal::millis();
  const uint32_t release = settings::value()[settings::kReleaseMs];
  if (busy()) {
    ctl().was_busy = true;
  } else if (ctl().was_busy) {  // the first pass at rest: the idle time starts
    ctl().was_busy = false;
    ctl().idle_since = now;
  } else if (coils::on() && release != 0 && now - ctl().idle_since >= release) {
    coils::release();
  }
}

uint32_t on_step_timer() { return stepper::on_timer(); }

void on_realtime(char c) {
  if (realtime_command(c) == kRealtimeStop) stepper::request_stop();
}

// (Only the SITL calls these: on the Nano the linker drops them.)
void configured() { adopt_configuration(); }
const robot::State& planned() { return ctl().planned; }
bool homed() { return ctl().homed; }

}  // namespace firmware
