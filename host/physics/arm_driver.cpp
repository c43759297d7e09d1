// host/physics/arm_driver.cpp - see arm_driver.h.
#include "arm_driver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "arm_body.h"

namespace articula::host {

// An action of the kinematic model (a robot without motors; the firmware's own actions come
// from its session, FirmwareSession::Event).
struct ArmDriver::Action {
  enum Kind { kGripper, kJoints, kDwell } kind = kJoints;
  int line = 0;
  uint64_t start_tick = 0, end_tick = 0;
  double opening_to = 0;             // kGripper, mm
  std::vector<double> q_from, q_to;  // kJoints, model units
};

ArmDriver::ArmDriver(ArmBody& body, const SimOptions& options)
    : body_(body), robot_(body.robot()), opt_(options), motors_(body.has_motors()),
      n_joints_(body.robot().model.num_joints) {
  reset_controller();  // ready for command() without a program
}

ArmDriver::~ArmDriver() = default;

void ArmDriver::reset_controller() {
  if (motors_) {
    if (!firmware_) {  // one firmware for the arm's life: it goes on from where it is
      firmware_ = std::make_unique<FirmwareSession>(robot_, opt_.settings);
      lines_robot_ = robot_;
      FirmwareSession* fw = firmware_.get();
      lines_ = std::make_unique<StatementLines>(lines_robot_, opt_.settings.value[ControllerSettings::kMaxRate],
                                                [fw] { return fw->commanded(); });
    }
  } else {
    kinematic_ = std::make_unique<KinematicModel>(robot_);
  }
  queued_q_ = body_.joints();
  queued_percent_ = -1;
}

// A new program: what the last one queued and refused forgotten, the controller as it is.
void ArmDriver::restart(uint64_t now, bool fed) {
  fed_ = fed;
  actions_.clear();
  action_ = 0;
  action_running_ = false;
  pending_.clear();
  pending_next_ = 0;
  reset_controller();
  queue_end_tick_ = now;
  body_.hold_grip();
}

void ArmDriver::load_program(const Program& program, uint64_t now) {
  restart(now, false);
  if (motors_) {  // each line once the arm is at rest after the one before, as the harness sends
    for (const Statement& st : program.statements) send(st, now, FirmwareSession::kAtRest);
    program_end_s_ = double(firmware_->run_to_rest()) / kStepTickHz;
    return;
  }
  for (const Statement& st : program.statements) enqueue(st, now);
  program_end_s_ = double(queue_end_tick_) / kStepTickHz;
}

void ArmDriver::feed_program(const Program& program, uint64_t now) {
  if (!motors_) {
    load_program(program, now);
    return;
  }
  restart(now, true);
  fed_program_ = program;
  fed_next_ = 0;
  fed_text_.clear();
  firmware_->run_to(now);
  firmware_->feed([this](uint64_t tick, std::string& text, int& line) {
    while (fed_next_ < fed_program_.statements.size()) {
      const Statement& st = fed_program_.statements[fed_next_++];
      PredictRecord r;
      if (!lines_->begin(st, r, text)) {  // (the host's own: it never reaches the firmware)
        if (r.reply != kOk) rejected(tick, r.line, r.text, r.reply, r.note);
        continue;
      }
      line = st.line;
      fed_text_[st.line] = r.text;
      return true;
    }
    return false;
  });
}

double ArmDriver::program_end() const {
  if (!fed_) return program_end_s_;
  return double(firmware_->feeding() ? firmware_->now() : firmware_->feed_ended()) / kStepTickHz;
}

Status ArmDriver::command(const std::string& line, uint64_t now) {
  Statement st{Statement::Kind::kProtocol, {}, line, 0};
  if (motors_) {  // as soon as the reply before is off the wire: a streamed program
    const Status s = send(st, now, FirmwareSession::kStreamed);
    program_end_s_ = std::max(program_end_s_, double(firmware_->now()) / kStepTickHz);
    return s;
  }
  const size_t rejected_before = pending_.size();
  enqueue(st, now);
  return pending_.size() > rejected_before ? pending_.back().reply : kOk;
}

// A rejected line: an event at `tick`, shown when the clock reaches it.
void ArmDriver::rejected(uint64_t tick, int line, const std::string& text, Status s, const std::string& note) {
  SimEvent e;
  e.kind = SimEvent::Kind::kRejected;
  e.t = double(tick) / kStepTickHz;
  e.arm = body_.name();
  e.line = line;
  e.a = text;
  e.reply = s;
  e.detail = std::string("error:") + std::to_string(int(s)) + " " + status_text(s) + ", nothing moves" +
             (note.empty() ? "" : "; " + note);
  pending_.push_back(e);
}

void ArmDriver::take_rejections(double t_end, std::vector<SimEvent>& out) {
  while (pending_next_ < pending_.size() && pending_[pending_next_].t <= t_end + 1e-12)
    out.push_back(pending_[pending_next_++]);
}

// One statement to the firmware, as `sender` sends it. Its reply; a refusal, the firmware's or
// the host's own (a line that does not parse, an a without a solution), is an event at the
// reply's tick.
Status ArmDriver::send(const Statement& st, uint64_t now_tick, FirmwareSession::Sender sender) {
  PredictRecord r;
  std::string line;
  if (!lines_->begin(st, r, line)) {
    if (r.reply != kOk) rejected(std::max(now_tick, firmware_->now()), r.line, r.text, r.reply, r.note);
    return r.reply;
  }
  const Status s = firmware_->send(line, st.line, now_tick, sender);
  if (s != kOk) rejected(firmware_->now(), st.line, r.text, s, "");  // (at its reply, in the order sent)
  return s;
}

// One statement through the kinematic model; an accepted one becomes an action that starts
// when the queue before it ends (or now, when the arm is idle) and lasts as long as the model
// says. A whole program at t = 0 is so queued back to back from rest to rest.
void ArmDriver::enqueue(const Statement& st, uint64_t now_tick) {
  const uint64_t start = std::max(now_tick, queue_end_tick_);
  const RunRecord r = kinematic_->execute(st);
  if (r.reply != kOk) {
    rejected(start, r.line, r.text, r.reply, r.note);
    return;
  }
  Action a;
  a.line = r.line;
  if (!r.via_joints.empty() && r.line_speed > 0) {  // T: a move per segment, along its line at its speed
    uint64_t t = start;
    for (size_t k = 0; k < r.via_joints.size(); ++k) {
      Action seg = a;
      seg.kind = Action::kJoints;
      seg.q_from = queued_q_;
      seg.q_to.resize(size_t(n_joints_));
      for (int j = 0; j < n_joints_; ++j) seg.q_to[size_t(j)] = joint_to_model(robot_, j, r.via_joints[k][size_t(j)]);
      seg.start_tick = t;
      seg.end_tick = t = start + uint64_t(std::ceil((r.via_mm[k] / r.line_speed) * kStepTickHz));
      queued_q_ = seg.q_to;
      actions_.push_back(seg);
    }
    queue_end_tick_ = t;
    program_end_s_ = double(queue_end_tick_) / kStepTickHz;
    return;
  }
  std::vector<double> q_to(static_cast<size_t>(n_joints_));
  for (int j = 0; j < n_joints_; ++j) q_to[size_t(j)] = joint_to_model(robot_, j, r.joints[size_t(j)]);
  double duration = opt_.joints.move_s(robot_, queued_q_.data(), q_to.data());
  if (duration > 0) {
    a.kind = Action::kJoints;
    a.q_from = queued_q_;
    a.q_to = q_to;
    queued_q_ = q_to;
  } else if (r.gripper_percent != queued_percent_ || is_gripper_statement(st)) {
    a.kind = Action::kGripper;
    duration = opt_.joints.gripper_settle_s;
    queued_percent_ = r.gripper_percent;
    a.opening_to = robot_.gripper.max_opening_mm * (queued_percent_ < 0 ? 100 : queued_percent_) / 100.0;
  } else if (r.dwell_s > 0) {
    a.kind = Action::kDwell;
    duration = r.dwell_s;
  } else {
    return;
  }
  a.start_tick = start;
  a.end_tick = start + uint64_t(std::ceil(duration * kStepTickHz));
  actions_.push_back(a);
  queue_end_tick_ = a.end_tick;
  program_end_s_ = double(queue_end_tick_) / kStepTickHz;
}

void ArmDriver::begin_action(size_t index) {
  Action& a = actions_[index];
  action_running_ = true;
  body_.action_begins(a.start_tick, a.line, false);
  if (a.kind == Action::kGripper)
    body_.grip(a.opening_to, double(a.start_tick) / kStepTickHz, double(a.end_tick) / kStepTickHz);
}

void ArmDriver::end_action() {
  const Action& a = actions_[action_];
  if (a.kind == Action::kJoints) {
    const std::vector<double>& q = body_.joints();
    double worst = 0;
    for (int j = 0; j < n_joints_; ++j) worst = std::max(worst, std::fabs(q[size_t(j)] - a.q_to[size_t(j)]));
    if (worst > 1e-9) {
      SimEvent e;
      e.kind = SimEvent::Kind::kBlocked;
      e.t = double(a.end_tick) / kStepTickHz;
      e.line = a.line;
      char buf[120];
      std::snprintf(buf, sizeof buf, "the move ended %.3f (deg or mm) short of its target; the joints follow later",
                    robot_.model.joints[0].param != kParamD ? worst * 180 / M_PI : worst);
      e.detail = buf;
      body_.add_event(e);
    }
  }
  action_running_ = false;
  ++action_;
}

void ArmDriver::advance(uint64_t until, double t_end, double dt) {
  if (motors_) {
    motor_events(until);
    if (body_.has_servos()) body_.servo_follow(dt);
  } else {
    joint_follow(t_end, dt);
  }
}

// The firmware's events up to `until`, each at its tick: its coils' steps move the arm (unless
// something blocks it), its actions say which line runs and what the gripper does.
void ArmDriver::motor_events(uint64_t until) {
  firmware_->run_to(until);
  for (const FirmwareSession::Event& e : firmware_->take(until)) {
    body_.set_event_tick(e.tick);
    if (!signals_.empty() && signals_.back().waiting() &&
        (e.kind == FirmwareSession::Event::kBegin || e.kind == FirmwareSession::Event::kIdle)) {
      Signal& w = signals_.back();
      w.ended = true;
      w.end_tick = e.tick;
      w.met = firmware_->input_level(w.pin, e.tick) == (w.level != 0);  // (else it ran out)
    }
    if (e.kind == FirmwareSession::Event::kBegin &&
        (e.action == FirmwareSession::Event::kOutput || e.action == FirmwareSession::Event::kWaitIn)) {
      const bool wait = e.action == FirmwareSession::Event::kWaitIn;
      signals_.push_back({wait ? Signal::kWait : Signal::kOutput, e.line, e.pin, e.level, e.tick, false, 0});
    }
    switch (e.kind) {
      case FirmwareSession::Event::kStep:
        if (log_steps_) step_log_.push_back({e.tick, e.mask, e.negative});
        body_.apply_steps(e.mask, e.negative);
        break;
      case FirmwareSession::Event::kBegin:
        body_.action_begins(e.tick, e.line, true);
        body_.recount(e.counted);
        if (e.action == FirmwareSession::Event::kMove || e.action == FirmwareSession::Event::kHome)
          body_.stall_check(e.delta, e.motion);
        if (e.action == FirmwareSession::Event::kGripper)
          body_.grip(robot_.gripper.max_opening_mm * e.percent / 100.0, double(e.tick) / kStepTickHz,
                     double(e.tick + e.settle_ticks) / kStepTickHz);
        break;
      case FirmwareSession::Event::kIdle:
        body_.firmware_action_ends(e.tick);
        body_.recount(e.counted);
        break;
      case FirmwareSession::Event::kReply:
        if (!e.counted.empty()) body_.recount(e.counted);
        if (fed_ && e.status != kOk) {  // (a line sent otherwise: an event since it was sent)
          const auto text = fed_text_.find(e.line);
          rejected(e.tick, e.line, text != fed_text_.end() ? text->second : e.text, e.status, "");
        }
        break;
    }
  }
}

void ArmDriver::joint_follow(double t_end, double dt) {
  const uint64_t until = uint64_t(std::llround(t_end * kStepTickHz));
  for (;;) {
    if (!action_running_) {
      if (action_ >= actions_.size() || actions_[action_].start_tick > until) break;
      begin_action(action_);
      continue;
    }
    Action& a = actions_[action_];
    if (a.end_tick > until) break;
    if (a.kind == Action::kJoints) body_.follow_joints(a.q_to, dt);
    end_action();
  }
  if (action_running_ && actions_[action_].kind == Action::kJoints) {
    const Action& a = actions_[action_];
    const double f = double(until - a.start_tick) / double(a.end_tick - a.start_tick);
    q_cmd_.resize(size_t(n_joints_));
    for (int j = 0; j < n_joints_; ++j)
      q_cmd_[size_t(j)] = a.q_from[size_t(j)] + f * (a.q_to[size_t(j)] - a.q_from[size_t(j)]);
    body_.follow_joints(q_cmd_, dt);
  } else if (action_ > 0 && !action_running_) {
    body_.follow_joints(actions_[action_ - 1].kind == Action::kJoints ? actions_[action_ - 1].q_to : body_.joints(), dt);
  }
}

bool ArmDriver::busy() const {
  if (motors_) return firmware_->pending() || firmware_->feeding() || !firmware_->at_rest();
  return action_ < actions_.size();
}

}  // namespace articula::host
