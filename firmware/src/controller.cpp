// firmware/src/controller.cpp - the firmware's entry points (firmware.h): reads lines, runs
// commands, answers each line once, sends reports, feeds the motion queue, handles '!'.
//
// Every line ends in exactly one reply, and only reply() sends one. A line is checked at
// once, and a bad one answered at once. A good one that must wait (a queued command while
// the queue is full; Z and $n=v until the queue is empty and the arm at rest) is held,
// parsed, as the *pending* line, and run when it can; meanwhile bytes are still read until
// one more complete line is in (the *held* line), then reading stops until the pending one
// is answered. Realtime bytes never wait: the receive interrupt hands them to on_realtime(),
// which only raises a flag; the next poll() sends the report or handles the stop.
#include "firmware.h"

#include <articula/protocol.h>

#include "coils.h"
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

typedef BasicCommand<3> Command;  // P's three numbers; M's one per motor (at most three)

struct SerialSink {
  void put(char c) { hal::serial_write(c); }
};

LineAssembler g_line;
Command g_pending;
bool g_has_pending;
LineEvent g_held;            // a complete line behind the pending one, still in g_line
robot::State g_planned;      // commanded angles and steps once the queue has run
bool g_homed;                // position known: moves allowed
volatile uint8_t g_report;   // '?' seen
bool g_stop_flushed;         // the queue and waiting lines of the current stop are dealt with
bool g_was_busy;             // busy at the last pass
uint32_t g_idle_since;       // millis() at the first pass at rest

void reply(uint8_t status) {
  char buf[10];
  const uint8_t n = format_reply(buf, sizeof buf, Status(status));
  for (uint8_t i = 0; i < n; ++i) hal::serial_write(buf[i]);
}

bool busy() { return stepper::busy() || !queue::empty(); }

MachineState machine_state() {
  if (stepper::stop_requested()) return kStateStop;
  if (stepper::homing()) return kStateHome;
  if (busy()) return kStateRun;
  return g_homed ? kStateIdle : kStateAlarm;
}

void send_status() {
  StatusReport<kJ> r;
  r.state = machine_state();
  r.num_joints = kJ;
  stepper::read_positions(r.steps);
  for (uint8_t i = 0; i < kJ; ++i) r.millideg[i] = steps_to_millideg(robot::motor(i), r.steps[i]);
  r.gripper = stepper::gripper_percent();
  r.free_slots = queue::free_slots();
  r.coils = coils::on();
  r.warning = settings::take_warning();
  SerialSink out;
  write_status(out, r);
}

void send_info() {
  InfoReport r;
  for (uint8_t i = 0; i < 3; ++i) r.version[i] = kVersion[i];
  r.protocol = kProtocolVersion;
  r.num_joints = kJ;
  const char* name = ARTICULA_ROBOT_NAME;
  uint8_t n = 0;
  for (; name[n] != '\0' && n < kMaxRobotName; ++n) r.name[n] = name[n];
  r.name[n] = '\0';
  r.warning = settings::take_warning();
  SerialSink out;
  write_info(out, r);
}

// After a stop or a failed homing: the commanded angles become those of the steps the
// motors really reached (the A field of a status report).
void rederive_planned() {
  stepper::read_positions(g_planned.steps);
  for (uint8_t i = 0; i < kJ; ++i) g_planned.commanded[i] = steps_to_millideg(robot::motor(i), g_planned.steps[i]);
}

// P: the tool point (micrometres) to actuator angles, the in-limits solution nearest the
// planned pose (least sum of squared actuator differences).
Status solve_point(robot::State& next, const int32_t* um) {
  if (!robot::has_ik || kJ != 3) return kUnreachable;
  // ypp_solve(..., polish = false) without its search for the nearest pose when nothing is
  // within the limits: the firmware only refuses such a point.
  YppResult<float> r;
  const int in_limits =
      ypp_closed_form(r, robot::arm, make_vec3(float(um[0]) * 0.001f, float(um[1]) * 0.001f, float(um[2]) * 0.001f));
  if (in_limits == 0) return kUnreachable;
  Millideg best[kJ];
  float best_d2 = -1;
  for (uint8_t k = 0; k < in_limits; ++k) {  // the in-limits solutions come first
    float act[3];
    ypp_actuated(act, robot::arm, r.solutions[k].q);
    Millideg t[kJ];
    float d2 = 0;
    for (uint8_t i = 0; i < kJ; ++i) {
      const MotorSpec& m = robot::motor(i);
      if (!to_millideg(t[i], rad_to_deg(act[i]))) return kUnreachable;
      t[i] = clamp(t[i], m.min, m.max);  // in limits in float: at most a rounding beyond
      d2 += square(float(t[i] - g_planned.commanded[i]));
    }
    if (best_d2 < 0 || d2 < best_d2) {
      best_d2 = d2;
      for (uint8_t i = 0; i < kJ; ++i) best[i] = t[i];
    }
  }
  return move_absolute(next, robot::actuation, best);
}

bool is_queued(CommandType t) { return t <= kCmdHome && t != kCmdNone; }

// What a valid line still waits for: room in the queue, or (Z, $n=v) the arm at rest with
// nothing queued.
bool must_wait(const Command& c) {
  if (is_queued(c.type)) return queue::full();
  return (c.type == kCmdSetZero || c.type == kCmdSetSetting) && busy();
}

// Commands that go through the queue: validated against the planned state (which nothing
// but this line changes while it waits), then queued when there is room.
uint8_t queue_command(const Command& c) {
  robot::State next = g_planned;
  queue::Action a;
  a.kind = queue::kMove;
  a.mask = 0;
  Status s = kOk;
  switch (c.type) {
    case kCmdRotate:
    case kCmdMoveAbsolute:
    case kCmdMoveTool:
      if (!g_homed) return kNotHomed;
      s = c.type == kCmdRotate         ? move_relative(next, robot::actuation, uint8_t(c.arg[0]), c.arg[1])
          : c.type == kCmdMoveAbsolute ? move_absolute(next, robot::actuation, c.arg)
                                       : solve_point(next, c.arg);
      if (s != kOk) return s;
      break;
    case kCmdGripper:
    case kCmdAperture: {
      if (queue::full()) return kWait;
      const int32_t aperture = c.type == kCmdAperture ? c.arg[0] : (c.arg[0] ? 0 : 100000L);
      a.kind = queue::kGripper;
      a.grip.pulse_us = gripper::pulse_us(aperture);
      a.grip.percent = uint8_t((aperture + 500) / 1000);
      a.grip.settle_ticks = settings::value[settings::kSettleMs] * (hal::kTickHz / 1000);
      queue::push(a);
      return kOk;
    }
    case kCmdHome: {
      // Switch motors end at their minimum angle, the others at the home pose.
      const uint8_t mask = uint8_t(settings::value[settings::kEndstops]);
      for (uint8_t i = 0; i < kJ; ++i) {
        const MotorSpec& m = robot::motor(i);
        next.commanded[i] = (mask & (1u << i)) ? m.min : robot::home[i];
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
  if (a.kind == queue::kHome) g_homed = true;  // until the search fails
  bool moves = a.kind == queue::kHome;
  for (uint8_t i = 0; i < kJ; ++i) {
    a.target[i] = next.steps[i];
    moves = moves || next.steps[i] != g_planned.steps[i];
  }
  if (moves) queue::push(a);  // a move within the same steps changes only the commanded angles
  g_planned = next;
  return kOk;
}

uint8_t execute(const Command& c) {
  SerialSink out;
  switch (c.type) {
    case kCmdNone:
      return kOk;
    case kCmdInfo:
      send_info();
      return kOk;
    case kCmdListSettings:
      for (uint8_t n = 0; n < settings::kCount; ++n) write_setting(out, n, int32_t(settings::value[n]) * 1000);
      return kOk;
    case kCmdSetSetting: {
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
        g_planned.commanded[i] = robot::home[i];
        g_planned.steps[i] = robot::home_steps[i];
      }
      stepper::set_positions(g_planned.steps);
      g_homed = true;
      return kOk;
    default:
      return queue_command(c);
  }
}

void run_line(LineEvent ev) {
  if (ev == kLineTooLongEnded) {
    reply(kLineTooLong);
    return;
  }
  const Status s = parse_line(g_pending, g_line, kJ);
  if (s != kOk) {
    reply(s);
    return;
  }
  const uint8_t r = execute(g_pending);
  if (r == kWait) {
    g_has_pending = true;
    return;
  }
  reply(r);
}

// Reads bytes until a line is complete (kept in g_held) or none are waiting.
void read_ahead() {
  while (g_held == kLineNone) {
    const int16_t c = hal::serial_read();
    if (c < 0) return;
    g_held = g_line.feed(char(c));
  }
}

void service_lines() {
  if (g_has_pending) {
    // Valid when first run; what it waits for is checked cheaply (P's inverse kinematics
    // runs again only once there is room).
    if (must_wait(g_pending)) {
      read_ahead();
      return;
    }
    reply(execute(g_pending));
    g_has_pending = false;
  }
  read_ahead();
  if (g_held != kLineNone && !stepper::stop_requested()) {  // a line after a '!' waits for rest
    const LineEvent ev = g_held;
    g_held = kLineNone;
    run_line(ev);
  }
}

// '!': empty the queue and answer the waiting lines at once; once the arm is at rest, take
// the position it reached and read lines again.
void service_stop() {
  if (!g_stop_flushed) {
    queue::clear();
    stepper::cut_pause();
    if (g_has_pending) {  // and the line read behind it, if any
      reply(kStopped);
      if (g_held != kLineNone) reply(kStopped);
      g_has_pending = false;
      g_held = kLineNone;
    }
    g_stop_flushed = true;
  }
  if (!stepper::busy()) {
    rederive_planned();
    g_stop_flushed = false;
    stepper::clear_stop();
  }
}

}  // namespace

namespace firmware {

void setup() {
  robot::setup();
  settings::load();
  coils::setup();
  queue::clear();
  stepper::setup();
  g_line.clear();
  g_has_pending = false;
  g_held = kLineNone;
  g_report = 0;
  g_stop_flushed = false;
  reset(g_planned, robot::actuation);
  g_homed = settings::value[settings::kEndstops] == 0;
  g_was_busy = false;
  g_idle_since = hal::millis();
}

void poll() {
  if (stepper::take_fault()) {  // homing failed: position unknown, nothing queued runs
    queue::clear();
    rederive_planned();
    g_homed = false;
  }
  if (stepper::stop_requested()) service_stop();
  if (g_report) {
    g_report = 0;
    send_status();
  }
  if (!stepper::stop_requested()) {
    service_lines();
    stepper::kick();
  }
  const uint32_t now = hal::millis();
  const uint32_t release = settings::value[settings::kReleaseMs];
  if (busy()) {
    g_was_busy = true;
  } else if (g_was_busy) {  // the first pass at rest: the idle time starts
    g_was_busy = false;
    g_idle_since = now;
  } else if (coils::on() && release != 0 && now - g_idle_since >= release) {
    coils::release();
  }
}

uint32_t on_step_timer() { return stepper::on_timer(); }

void on_realtime(char c) {
  const RealtimeCommand r = realtime_command(c);
  if (r == kRealtimeStatus) g_report = 1;
  if (r == kRealtimeStop) stepper::request_stop();
}

}  // namespace firmware
