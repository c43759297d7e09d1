// host/lib/schedule.cpp - when each action runs (predict.h, schedule()): the firmware's
// motion queue, planner and step interrupt, replayed on the lines as a sender delivers them.
// Each rule names the firmware code it follows; the step timing and the plan are the shared
// core's own (articula/motion.h, articula/planner.h), so the ticks are the firmware's.
#include <articula/planner.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <optional>

#include "predict.h"
#include "replay.h"

namespace articula::host {

const char* sender_name(SenderModel::Kind k) {
  switch (k) {
    case SenderModel::kRest: return "rest";
    case SenderModel::kStream: return "stream";
  }
  return "?";
}

namespace {

// An action in the queue (queue::Action): its record (and which of a T's segments) and its
// plan.
struct Queued {
  size_t record;
  int segment;  // -1: the record's own action
  PlanBlock plan;
};

// The move a queued action makes: the record's, or one of its segments.
struct MoveOf {
  const std::vector<int32_t>& delta;
  uint32_t steps;
  uint16_t cruise4;
};
MoveOf move_of(const PredictRecord& r, int segment) {
  if (segment < 0) return {r.delta_steps, r.dominant_steps, 0};
  const PredictRecord::Segment& s = r.segments[size_t(segment)];
  return {s.delta_steps, s.dominant_steps, s.cruise4};
}

// controller.cpp push_planned(): a move's block, with its junction level to the move queued
// before it (`before`: none when the arm is at rest with nothing queued, or after another
// action) kept below the cruise caps of both; `cap` is set to this move's cap.
PlanBlock plan_block(const MoveOf& m, const MoveOf* before, uint16_t before_cap, const MotionSettings& motion,
                     uint32_t junction, uint16_t& cap) {
  PlanBlock b{uint16_t(std::min(m.steps, uint32_t(0xFFFF))), 0, 0, m.cruise4};
  ProfileConstants k;
  profile_constants(k, motion);
  cap = cruise_level_cap(motion, k.cruise, block_cruise(b, k.cruise));
  if (before)
    b.max_entry = std::min({cap, before_cap,
                            junction_level<kMaxJoints>(before->delta.data(), before->steps, m.delta.data(), m.steps,
                                                       uint8_t(m.delta.size()), junction)});
  return b;
}

// A queue action: its record and which of a T's segments (-1: the record's own).
using Item = std::pair<size_t, int>;

// The steps an action has made.
struct Done {
  std::vector<int32_t> delta;
  uint32_t steps = 0;  // dominant steps
};

// The firmware's step interrupt and queue, stepped deadline by deadline.
class Controller {
 public:
  Controller(std::vector<PredictRecord>& records, uint32_t queue_size) : rec_(records), size_(queue_size) {}

  // '!' at tick t (the receive interrupt's stepper::request_stop()): the step interrupt
  // decelerates along the path (move_tick, and continue_stop on into the queued moves while
  // still moving), a pause is cut by the main loop at once (cut_pause), a switch search
  // fails; at rest the main loop empties the queue (service_stop). The tick of rest; `hit`
  // gets the actions that were running or queued, in order.
  uint64_t stop(uint64_t t, std::vector<Item>& hit) {
    advance_to(t);
    hit.clear();
    if (mode_ == kIdle) return t;
    hit.push_back(current_);
    for (const Queued& q : queue_) hit.push_back({q.record, q.segment});
    if (mode_ == kMove) {
      stop_ = true;
      while (mode_ != kIdle) on_timer();
      stop_ = false;
      t = std::max(t, last_);
    } else {  // a pause cut now; a search ends at its next deadline with a fault
      if (mode_ == kSeek) t = deadline_;
      halt(t);
    }
    queue_.clear();
    last_steps_ = 0;  // rederive_planned(): no move to blend with
    return t;
  }
  // The steps an action made (none if it never ran).
  Done done(const Item& k) const {
    const auto it = done_.find(k);
    return it == done_.end() ? Done{} : it->second;
  }

  bool full() const { return queue_.size() >= size_; }
  bool busy() const { return mode_ != kIdle || !queue_.empty(); }

  // Every deadline up to and including `t` (the interrupt comes before a line that arrives
  // at the same tick).
  void advance_to(uint64_t t) {
    while (mode_ != kIdle && deadline_ <= t) on_timer();
  }

  // Until the queue has room: the tick a slot freed (a pop), or `t` when it has room;
  // kNever if that is not before `limit` (the controller then stands at `limit`).
  uint64_t room_after(uint64_t t, uint64_t limit = kNever) {
    advance_to(t);
    while (full()) {
      const size_t before = queue_.size();
      while (queue_.size() == before) {
        if (deadline_ >= limit) return advance_to(limit), kNever;
        on_timer();
      }
      t = std::max(t, last_);
    }
    return t;
  }
  // Until nothing runs and nothing is queued; kNever as room_after().
  uint64_t rest_after(uint64_t t, uint64_t limit = kNever) {
    advance_to(t);
    while (mode_ != kIdle) {
      if (deadline_ >= limit) return advance_to(limit), kNever;
      on_timer();
    }
    return std::max(t, last_);
  }
  static constexpr uint64_t kNever = UINT64_MAX;
  uint64_t first_step() const { return first_step_; }

  // controller.cpp push_planned(), then stepper::kick() when nothing runs.
  void push(size_t k, uint64_t now, int segment = -1) {
    const PredictRecord& r = rec_[k];
    Queued q{k, segment, {0, 0, 0, 0}};
    if (r.action == PredictRecord::Action::kMove) {
      const MoveOf m = move_of(r, segment);  // the controller model's (predict.cpp, queue_move, line)
      const MoveOf last{last_delta_, last_steps_, 0};
      uint16_t cap = 0;
      q.plan = plan_block(m, last_steps_ != 0 && busy() ? &last : nullptr, last_cap_, r.motion, r.junction, cap);
      last_delta_ = m.delta;
      last_steps_ = m.steps;
      last_cap_ = cap;
    } else {
      last_steps_ = 0;
    }
    queue_.push_back(q);
    plan_entries([this](size_t i) -> const PlanBlock& { return queue_[i].plan; },
                 [this](size_t i, uint16_t e) { queue_[i].plan.entry = e; }, queue_.size());
    if (mode_ == kMove && !homing_) stepper_.raise_exit(planned_exit());  // stepper::raise_exit()
    if (mode_ == kIdle) {  // kick()
      last_ = now;
      next_action(now);
    }
  }

  // After Z (stepper::set_positions, no move to blend with).
  void forget_last_move() { last_steps_ = 0; }

 private:
  enum Mode { kIdle, kMove, kPause, kSeek };

  uint32_t planned_exit() const {
    if (queue_.empty()) return 0;
    const Queued& q = queue_.front();
    return rec_[q.record].action == PredictRecord::Action::kMove ? q.plan.entry : 0;
  }

  void end_running(uint64_t t) {
    if (running_ != kNone) rec_[running_].end_tick = t;
    running_ = kNone;
  }

  // Takes the front action off the queue as the one running.
  Queued take(uint64_t t) {
    const Queued q = queue_.front();
    queue_.pop_front();
    if (q.segment <= 0) rec_[q.record].start_tick = t;
    running_ = q.record;
    current_ = {q.record, q.segment};
    current_done_ = &done_[current_];
    current_done_->delta.assign(rec_[q.record].delta_steps.size(), 0);
    return q;
  }

  void halt(uint64_t t) {
    end_running(t);
    mode_ = kIdle;
    stepper_.halt();
    homing_ = false;
  }

  // stepper.cpp next_action(): the next queued action that takes time, from tick t.
  void next_action(uint64_t t) {
    end_running(t);
    mode_ = kIdle;
    homing_ = false;
    while (!queue_.empty()) {
      const Queued q = take(t);
      PredictRecord& r = rec_[q.record];
      uint64_t dt = 0;
      switch (r.action) {
        case PredictRecord::Action::kMove:
          dt = begin_move(r, planned_exit(), q.segment, q.plan.cruise4);
          break;
        case PredictRecord::Action::kPause:
          dt = r.ticks;
          if (dt != 0) mode_ = kPause;
          break;
        case PredictRecord::Action::kHome:
          homing_ = true;
          if (r.seek_ticks != 0) {
            mode_ = kSeek;
            dt = r.seek_ticks;
          } else {
            dt = begin_move(r, 0);
          }
          break;
        case PredictRecord::Action::kNone:
          break;
      }
      if (dt != 0) {
        deadline_ = t + dt;
        return;
      }
      end_running(t);
    }
    halt(t);
  }

  // stepper.cpp continue_stop(): a move ended still moving after '!': the stop goes on into
  // the queued moves, each to end at rest, until the arm is at rest.
  void continue_stop(uint64_t t) {
    end_running(t);
    while (stepper_.level() != 0 && !homing_ && !queue_.empty() &&
           rec_[queue_.front().record].action == PredictRecord::Action::kMove) {
      const Queued q = take(t);
      const uint64_t dt = begin_move(rec_[q.record], 0, q.segment, q.plan.cruise4, true);
      if (dt != 0) {
        deadline_ = t + dt;
        return;
      }
      end_running(t);
    }
    halt(t);
  }

  // stepper.cpp begin_move(): blended on from a move that ended moving.
  uint64_t begin_move(const PredictRecord& r, uint32_t exit, int segment = -1, uint16_t cruise4 = 0,
                      bool stopping = false) {
    const MoveOf m = move_of(r, segment);
    if (m.steps == 0) return 0;
    move_delta_ = &m.delta;
    move_steps_ = m.steps;
    if (constants_for_ != r.motion.max_rate * 1000003ULL + r.motion.accel) {
      profile_constants(constants_, r.motion);
      constants_for_ = r.motion.max_rate * 1000003ULL + r.motion.accel;
    }
    const uint32_t dt = stepper_.begin(m.delta.data(), m.delta.size(), constants_, exit, uint32_t(cruise4) * 4, stopping);
    if (dt != 0) mode_ = kMove;
    return dt;
  }

  // The step staged for this deadline (stepper.cpp book_staged()).
  void book() {
    if (first_step_ == kNever) first_step_ = deadline_;
    ++current_done_->steps;
    if (move_delta_->size() > MoveStepper::kMaxMotors) {  // (no Nano drives so many: spread in proportion)
      for (size_t i = 0; i < current_done_->delta.size(); ++i)
        current_done_->delta[i] = int32_t(std::lround(double((*move_delta_)[i]) * current_done_->steps / move_steps_));
      return;
    }
    const uint8_t mask = stepper_.step();
    for (size_t i = 0; i < current_done_->delta.size(); ++i)
      if (mask & (1u << i)) current_done_->delta[i] += (stepper_.negative() & (1u << i)) ? -1 : 1;
  }

  // stepper.cpp on_timer() at the current deadline.
  void on_timer() {
    const uint64_t t = deadline_;
    last_ = t;
    switch (mode_) {
      case kMove: {  // move_tick()
        book();
        const uint32_t dt = stepper_.next(stop_);
        if (dt != 0)
          deadline_ = t + dt;
        else if (stop_)
          continue_stop(t);
        else
          next_action(t);
        break;
      }
      case kSeek: {  // the switches found: Home's final move, from rest
        PredictRecord& r = rec_[running_];
        current_done_->delta.assign(r.delta_steps.size(), 0);  // (the search's steps are not the move's)
        const uint64_t dt = begin_move(r, 0);
        if (dt != 0)
          deadline_ = t + dt;
        else
          next_action(t);
        break;
      }
      case kPause:
        next_action(t);
        break;
      case kIdle:
        break;
    }
  }

  static constexpr size_t kNone = size_t(-1);
  std::vector<PredictRecord>& rec_;
  size_t size_;
  std::deque<Queued> queue_;
  Mode mode_ = kIdle;
  bool homing_ = false;
  size_t running_ = kNone;
  MoveStepper stepper_;
  const std::vector<int32_t>* move_delta_ = nullptr;
  uint32_t move_steps_ = 0;
  Item current_{kNone, -1};
  Done* current_done_ = nullptr;
  std::map<Item, Done> done_;
  bool stop_ = false;
  uint64_t first_step_ = kNever;
  ProfileConstants constants_{};
  uint64_t constants_for_ = 0;
  uint64_t deadline_ = 0;
  uint64_t last_ = 0;  // the last deadline handled
  std::vector<int32_t> last_delta_;
  uint32_t last_steps_ = 0;
  uint16_t last_cap_ = 0xFFFF;
};

}  // namespace

std::vector<PlanBlock> plan_segments(const std::vector<PredictRecord::Segment>& segments, const MotionSettings& motion,
                                     uint32_t junction) {
  std::vector<PlanBlock> plan;
  uint16_t last_cap = 0xFFFF;
  for (size_t i = 0; i < segments.size(); ++i) {
    const PredictRecord::Segment& s = segments[i];
    const MoveOf m{s.delta_steps, s.dominant_steps, s.cruise4};
    std::optional<MoveOf> before;
    if (i > 0) before.emplace(MoveOf{segments[i - 1].delta_steps, segments[i - 1].dominant_steps, 0});
    uint16_t cap = 0;
    plan.push_back(plan_block(m, before ? &*before : nullptr, last_cap, motion, junction, cap));
    last_cap = cap;
  }
  plan_entries([&](size_t k) -> const PlanBlock& { return plan[k]; }, [&](size_t k, uint16_t e) { plan[k].entry = e; },
               plan.size());
  return plan;
}

uint64_t segments_ticks(const std::vector<PredictRecord::Segment>& segments, const std::vector<PlanBlock>& plan,
                        const MotionSettings& motion, std::vector<uint64_t>* ends) {
  if (ends) ends->clear();
  ProfileConstants k;
  profile_constants(k, motion);
  StepProfile p;
  uint64_t t = 0;
  for (size_t i = 0; i < segments.size(); ++i) {
    const uint32_t exit = i + 1 < plan.size() ? plan[i + 1].entry : 0;
    const uint32_t cruise = block_cruise(plan[i], k.cruise);
    if (p.level() > 0)
      p.follow(segments[i].dominant_steps, exit, cruise);
    else
      p.start(segments[i].dominant_steps, k, exit, cruise);
    while (!p.done()) t += p.next_interval();
    if (ends) ends->push_back(t);
  }
  return t;
}

namespace {

// Ticks for `bytes` bytes on the line. The Nano asks for 115,200 baud and gets 117,647
// (16 MHz / 8 / 17, UBRR0 16 with U2X0): a bit is 136 CPU cycles, 17 ticks of the 2 MHz
// step timer.
uint64_t byte_ticks(const SenderModel& s, uint64_t bytes) { return bytes * s.bits_per_byte * 17; }

size_t reply_bytes(Status st) {
  char buf[16];
  return format_reply(buf, sizeof buf, st);
}


// What a '!' did to the actions it hit (Controller::stop): each one's steps, delta and
// segments become what it made; `stop` (the '!''s record) gets where the arm came to rest
// and the gripper of the last gripper action that ran.
void cut(Prediction& p, size_t stop, const std::vector<Item>& hit, const Controller& c, uint64_t rest) {
  if (hit.empty()) return;
  const size_t first = hit.front().first;
  std::vector<int32_t> at = p.records[first].steps;  // before the first: its end less its move
  for (size_t i = 0; i < at.size() && i < p.records[first].delta_steps.size(); ++i)
    at[i] -= p.records[first].delta_steps[i];
  int gripper = first > 0 ? p.records[first - 1].gripper_percent : p.records[first].gripper_percent;
  bool dropped_gripper = false;
  for (size_t k = first; k < stop; ++k) {
    PredictRecord& r = p.records[k];
    std::vector<Item> mine;
    for (const Item& it : hit)
      if (it.first == k) mine.push_back(it);
    if (mine.empty()) {  // not an action (or one the '!' answered error:15): where the arm was
      if (r.reply == kStopped) {
        r.delta_steps.assign(at.size(), 0);
        r.dominant_steps = 0;
        r.segments.clear();
        r.queued = false;
        r.action = PredictRecord::Action::kNone;
      }
      r.steps = at;
      if (!dropped_gripper) gripper = r.gripper_percent;
      continue;
    }
    const bool ran = k == first || c.done(mine.front()).steps > 0;  // (the first one hit was running)
    std::vector<int32_t> delta(at.size(), 0);
    uint32_t dominant = 0;
    std::vector<PredictRecord::Segment> segments;
    for (const Item& it : mine) {
      const Done d = c.done(it);
      for (size_t i = 0; i < d.delta.size() && i < delta.size(); ++i) delta[i] += d.delta[i];
      dominant += d.steps;
      if (it.second >= 0 && d.steps > 0) {
        PredictRecord::Segment sg = r.segments[size_t(it.second)];
        sg.delta_steps = d.delta;
        sg.dominant_steps = d.steps;
        segments.push_back(sg);
      }
    }
    if (!r.segments.empty()) {  // the segments before the first one hit ran in full
      std::vector<PredictRecord::Segment> all(r.segments.begin(), r.segments.begin() + mine.front().second);
      for (const auto& sg : all)
        for (size_t i = 0; i < delta.size(); ++i) delta[i] += sg.delta_steps[i];
      for (const auto& sg : all) dominant += sg.dominant_steps;
      all.insert(all.end(), segments.begin(), segments.end());
      r.segments = all;
    }
    for (size_t i = 0; i < at.size(); ++i) at[i] += delta[i];
    if (ran && delta == r.delta_steps) {  // run in full, the stop running on past it
      r.steps = at;
      if (!dropped_gripper) gripper = r.gripper_percent;
      continue;
    }
    r.cut = true;
    r.delta_steps = delta;
    r.dominant_steps = dominant;
    r.steps = at;
    if (r.action == PredictRecord::Action::kPause && r.gripper_percent != gripper && !ran) dropped_gripper = true;
    if (!dropped_gripper) gripper = r.gripper_percent;
    if (!ran && !(k == first)) {
      r.start_tick = r.end_tick = rest;
      append_note(r.note, "never ran: the '!' on line " + std::to_string(p.records[stop].line) + " emptied the queue");
    } else {
      append_note(r.note, "cut short by the '!' on line " + std::to_string(p.records[stop].line) + " (" +
                              std::to_string(dominant) + " steps made)");
    }
  }
  p.records[stop].steps = at;
  p.records[stop].gripper_percent = gripper;
}

}  // namespace

void schedule(Prediction& p, const SenderModel& sender) {
  Controller c(p.records, std::max<uint32_t>(1, sender.queue_size));
  uint64_t wire = 0;       // when the sender may start on the next line (the reply to the one before is in)
  uint64_t resume = 0;     // after a '!': lines are read again once the arm is at rest
  uint64_t reply = 0;      // when the previous line was answered
  bool first = true;
  std::vector<Item> hit;
  for (size_t k = 0; k < p.records.size(); ++k) {
    PredictRecord& r = p.records[k];
    const std::string line = r.protocol.empty() ? r.text : r.protocol;
    if (r.stop) {
      // '!' alone, without an LF (docs/protocol.md): it acts when its byte is in; no reply,
      // the next line follows it on the wire. A timed one goes when it goes.
      const bool timed = r.stop_at >= 0;
      const uint64_t bang = timed                                ? uint64_t(r.stop_at)
                            : first                              ? 0
                            : sender.kind == SenderModel::kRest ? c.rest_after(reply)
                                                                : wire + byte_ticks(sender, 1);
      const uint64_t rest = c.stop(bang, hit);
      cut(p, k, hit, c, rest);
      r.start_tick = r.arrive_tick = bang;
      r.end_tick = resume = std::max(resume, rest);
      if (!timed) {
        wire = bang;
        reply = bang;
        first = false;
      }
      continue;
    }
    const uint64_t line_bytes = line.size() + 1;
    uint64_t arrive = 0;
    switch (sender.kind) {
      case SenderModel::kRest:
        arrive = first ? 0 : c.rest_after(reply);
        break;
      case SenderModel::kStream:
        arrive = first ? 0 : wire + byte_ticks(sender, line_bytes);
        break;
    }
    arrive = std::max(arrive, resume);
    first = false;
    uint64_t answered = arrive;
    r.start_tick = r.end_tick = r.arrive_tick = arrive;
    // A timed '!' next: a line still unanswered when it comes is answered error:15.
    const bool timed_next = k + 1 < p.records.size() && p.records[k + 1].stop && p.records[k + 1].stop_at >= 0;
    const uint64_t stop_at = timed_next ? uint64_t(p.records[k + 1].stop_at) : UINT64_MAX;
    bool stopped = false;
    // (the '!' at the same tick as a deadline comes after it: advance_to)
    const uint64_t limit = stop_at == UINT64_MAX ? Controller::kNever : stop_at + 1;
    if (r.waits_for_rest) {
      answered = c.rest_after(arrive, limit);
      stopped = answered == Controller::kNever;
      if (!stopped && r.text.rfind('Z', 0) == 0) c.forget_last_move();
    } else if (r.queued && !r.segments.empty()) {  // T: each segment as the queue has room
      answered = arrive;
      for (size_t s = 0; s < r.segments.size() && !stopped; ++s) {
        answered = c.room_after(answered, limit);
        stopped = answered == Controller::kNever;
        if (!stopped) c.push(k, answered, int(s));
      }
    } else if (r.queued) {
      answered = c.room_after(arrive, limit);
      stopped = answered == Controller::kNever;
      if (!stopped) c.push(k, answered);
    } else {
      c.advance_to(arrive);
    }
    if (stopped) {  // (the segments it did queue are cut by the '!' with the rest of the queue)
      answered = stop_at;
      r.reply = kStopped;
      r.cut = true;
      append_note(r.note, "answered error:15: the '!' came while it waited");
    }
    if (r.waits_for_rest) r.start_tick = r.end_tick = answered;
    reply = answered;
    wire = reply + byte_ticks(sender, reply_bytes(r.reply));
  }
  p.total_ticks = std::max(c.rest_after(reply), resume);
  p.first_step_tick = c.first_step() == Controller::kNever ? 0 : c.first_step();
  for (PredictRecord& r : p.records)
    r.ticks = r.end_tick - r.start_tick;
}

}  // namespace articula::host
