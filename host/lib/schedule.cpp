// host/lib/schedule.cpp - when each action runs (predict.h, schedule()): the firmware's
// motion queue, planner and step interrupt, replayed on the lines as a sender delivers them.
// Each rule names the firmware code it follows; the step timing and the plan are the shared
// core's own (articula/motion.h, articula/planner.h), so the ticks are the firmware's.
#include <articula/planner.h>

#include <algorithm>
#include <deque>
#include <optional>

#include "predict.h"

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

// The firmware's step interrupt and queue, stepped deadline by deadline.
class Controller {
 public:
  Controller(std::vector<PredictRecord>& records, uint32_t queue_size) : rec_(records), size_(queue_size) {}

  bool full() const { return queue_.size() >= size_; }
  bool busy() const { return mode_ != kIdle || !queue_.empty(); }

  // Every deadline up to and including `t` (the interrupt comes before a line that arrives
  // at the same tick).
  void advance_to(uint64_t t) {
    while (mode_ != kIdle && deadline_ <= t) on_timer();
  }
  // Until the queue has room: the tick a slot freed (a pop), or `t` when it has room.
  uint64_t room_after(uint64_t t) {
    advance_to(t);
    while (full()) {
      const size_t before = queue_.size();
      while (queue_.size() == before) on_timer();
      t = std::max(t, last_);
    }
    return t;
  }
  // Until nothing runs and nothing is queued.
  uint64_t rest_after(uint64_t t) {
    advance_to(t);
    while (mode_ != kIdle) on_timer();
    return std::max(t, last_);
  }

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
    if (mode_ == kMove && !homing_) profile_.raise_exit(planned_exit());  // stepper::raise_exit()
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

  // stepper.cpp next_action(): the next queued action that takes time, from tick t.
  void next_action(uint64_t t) {
    end_running(t);
    mode_ = kIdle;
    homing_ = false;
    while (!queue_.empty()) {
      const Queued q = queue_.front();
      queue_.pop_front();
      PredictRecord& r = rec_[q.record];
      if (q.segment <= 0) r.start_tick = t;
      running_ = q.record;
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
    profile_ = StepProfile();  // halt(): at rest
    homing_ = false;
  }

  // stepper.cpp begin_move(): blended on from a move that ended moving.
  uint64_t begin_move(const PredictRecord& r, uint32_t exit, int segment = -1, uint16_t cruise4 = 0) {
    const uint32_t n = move_of(r, segment).steps;
    if (n == 0) return 0;
    if (constants_for_ != r.motion.max_rate * 1000003ULL + r.motion.accel) {
      profile_constants(constants_, r.motion);
      constants_for_ = r.motion.max_rate * 1000003ULL + r.motion.accel;
    }
    const uint32_t cruise = std::max(uint32_t(cruise4) * 4, constants_.cruise);
    if (profile_.level() > 0)
      profile_.follow(n, exit, cruise);
    else
      profile_.start(n, constants_, exit, cruise);
    mode_ = kMove;
    return profile_.next_interval();
  }

  // stepper.cpp on_timer() at the current deadline.
  void on_timer() {
    const uint64_t t = deadline_;
    last_ = t;
    switch (mode_) {
      case kMove:
        if (profile_.done()) {
          next_action(t);
        } else {
          deadline_ = t + profile_.next_interval();
        }
        break;
      case kSeek: {  // the switches found: Home's final move, from rest
        PredictRecord& r = rec_[running_];
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
  StepProfile profile_;
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

}  // namespace

void schedule(Prediction& p, const SenderModel& sender) {
  Controller c(p.records, std::max<uint32_t>(1, sender.queue_size));
  uint64_t reply = 0;       // when the previous line was answered
  size_t reply_len = 0;     // its bytes
  bool first = true;
  for (size_t k = 0; k < p.records.size(); ++k) {
    PredictRecord& r = p.records[k];
    const std::string line = r.protocol.empty() ? r.text : r.protocol;
    const uint64_t line_bytes = line.size() + 1;
    uint64_t arrive = 0;
    switch (sender.kind) {
      case SenderModel::kRest:
        arrive = first ? 0 : c.rest_after(reply);
        break;
      case SenderModel::kStream:
        arrive = first ? 0 : reply + byte_ticks(sender, reply_len + line_bytes);
        break;
    }
    first = false;
    uint64_t answered = arrive;
    r.start_tick = r.end_tick = arrive;
    if (r.waits_for_rest) {
      answered = c.rest_after(arrive);
      if (r.text.rfind('Z', 0) == 0) c.forget_last_move();
      r.start_tick = r.end_tick = answered;
    } else if (r.queued && !r.segments.empty()) {  // T: each segment as the queue has room
      answered = arrive;
      for (size_t s = 0; s < r.segments.size(); ++s) {
        answered = c.room_after(answered);
        c.push(k, answered, int(s));
      }
    } else if (r.queued) {
      answered = c.room_after(arrive);
      c.push(k, answered);
    } else {
      c.advance_to(arrive);
    }
    reply = answered;
    reply_len = reply_bytes(r.reply);
  }
  p.total_ticks = c.rest_after(reply);
  for (PredictRecord& r : p.records)
    r.ticks = r.end_tick - r.start_tick;
}

}  // namespace articula::host
