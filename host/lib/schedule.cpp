// host/lib/schedule.cpp - when each action runs (predict.h, schedule()): the firmware itself
// (firmware/src, on its virtual clock: firmware/sitl) runs the lines as the sender delivers
// them, and every time is read from what it did: when each line was in and answered, the
// actions it took off its queue and when its step timer stopped (the action log), the steps
// its coils made, where each '!' left the arm.
#include <articula/planner.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <optional>

#include "blocks.h"
#include "nano_config.h"
#include "predict.h"

// The firmware (firmware/src, built for the host's eight motors: firmware/sitl/sitl.cmake).
#include "hal_sitl.h"
#include "machine.h"
#include "queue.h"

namespace articula::host {

const char* sender_name(SenderModel::Kind k) {
  switch (k) {
    case SenderModel::kRest: return "rest";
    case SenderModel::kStream: return "stream";
  }
  return "?";
}

namespace {

// The move a queued action makes: the record's, or one of its segments.
struct MoveOf {
  const std::vector<int32_t>& delta;
  uint32_t steps;
  uint16_t cruise4;
};

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

// A queued action: its record and which of a T's segments (-1: the record's own action).
using Item = std::pair<size_t, int>;

// The steps an action made, read from the coil log.
struct Done {
  std::vector<int32_t> delta;
  uint32_t steps = 0;  // step deadlines: the dominant motor's steps
};

// What a '!' did to the actions it hit (running or queued when it came): each one's steps,
// delta and segments become what it made; `stop` (the '!''s record) gets where the arm came
// to rest and the gripper of the last gripper action that ran.
void cut(Prediction& p, size_t stop, const std::vector<Item>& hit, const std::map<Item, Done>& made, uint64_t rest) {
  const auto done = [&](const Item& k) {
    const auto it = made.find(k);
    return it == made.end() ? Done{} : it->second;
  };
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
    const bool ran = k == first || done(mine.front()).steps > 0;  // (the first one hit was running)
    std::vector<int32_t> delta(at.size(), 0);
    uint32_t dominant = 0;
    std::vector<PredictRecord::Segment> segments;
    for (const Item& it : mine) {
      const Done d = done(it);
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

namespace {

// The firmware's state is global, as on the Nano: one machine per process, one run at a time.
std::mutex g_firmware;

static_assert(kFirmwareMotors == robot::kJoints, "the host's build of the firmware (host/CMakeLists.txt)");

// The queue's kind of a record's action.
bool kind_is(uint8_t kind, PredictRecord::Action a) {
  switch (a) {
    case PredictRecord::Action::kMove: return kind == queue::kMove;
    case PredictRecord::Action::kHome: return kind == queue::kHome;
    case PredictRecord::Action::kPause: return kind == queue::kDwell || kind == queue::kGripper;
    case PredictRecord::Action::kNone: break;
  }
  return false;
}

// An action the firmware began (hal::action_began): its ticks and what it made.
struct Begun {
  uint64_t begin, end;  // end: the action log's next entry (the next action, or the timer's stop)
  uint8_t kind;
  size_t at;  // its place in the action log
  Done done;
};

std::string reply_text(Status s) {
  char buf[16];
  const uint16_t n = format_reply(buf, sizeof buf, s);
  return std::string(buf, n > 0 ? n - 1 : 0);
}

// Power-up with the robot's arm and the settings: the settings written as `$n=v` lines, then
// a power cycle (as a Nano set up so and switched on).
void power_up(const Robot& robot, const ConfiguredArm<kFirmwareMotors>& arm, const ControllerSettings& settings) {
  sitl::boot(true, "", nullptr, &arm);
  const ControllerSettings defaults;
  bool changed = false;
  for (int n = 0; n < ControllerSettings::kCount; ++n) {
    if (settings.value[size_t(n)] == defaults.value[size_t(n)]) continue;
    const std::string reply = sitl::command(protocol_line(robot, '$', {double(n), double(settings.value[size_t(n)])}));
    if (reply != "ok") throw PredictError("the firmware refused setting $" + std::to_string(n) + " = " +
                                          std::to_string(settings.value[size_t(n)]) + ": " + reply);
    changed = true;
  }
  if (changed) sitl::boot(false, "", nullptr, &arm);
  sitl::take_lines();
}

}  // namespace

void schedule(Prediction& p, const SenderModel& sender, const Robot& robot) {
  std::lock_guard<std::mutex> lock(g_firmware);
  ConfiguredArm<kFirmwareMotors> arm;
  try {
    arm = firmware_arm(robot);
  } catch (const NanoConfigError& e) {
    throw PredictError(e.what());
  }
  power_up(robot, arm, p.settings);
  const sitl::Hardware& hw = sitl::hw;
  const uint64_t t0 = hw.now;
  const size_t coils0 = hw.coil_log.size(), actions0 = hw.actions.size();

  // The lines as the host sends them: every record that is a command or a '!' (not RoboSim's
  // host-only l, w, z, nor an a the host could not solve); the timed '!'s at their ticks.
  std::vector<std::string> lines;
  std::vector<size_t> sent_of;  // each line's record
  std::vector<uint64_t> timed;  // after the first step
  std::vector<size_t> timed_of;
  for (size_t k = 0; k < p.records.size(); ++k) {
    const PredictRecord& r = p.records[k];
    if (r.stop && r.stop_at >= 0) {
      timed.push_back(uint64_t(r.stop_at) - std::min(uint64_t(r.stop_at), p.first_step_tick));
      timed_of.push_back(k);
    } else if (r.stop || r.command != kCmdNone) {
      lines.push_back(r.stop ? "!" : r.protocol.empty() ? r.text : r.protocol);
      sent_of.push_back(k);
    }
  }
  const std::vector<sitl::Exchange> got =
      sitl::run_lines(lines, sender.kind == SenderModel::kRest ? sitl::kAtRest : sitl::kStreamed, timed);
  if (!sitl::hw.errors.empty()) throw std::logic_error("the firmware's run: " + sitl::hal_errors());

  // The '!'s: when each came and when the arm was at rest after it.
  std::vector<sitl::StopEvent> stops = sitl::stop_events();
  for (sitl::StopEvent& e : stops) {
    e.bang -= t0;
    if (e.rest == ~uint64_t(0)) e.rest = hw.now, e.actions = hw.actions.size();
    e.rest -= t0;
  }
  // Each record's arrival and reply: a line when it was in (read); a host-only line, a line the run
  // never reached, at the last answer before it.
  const size_t n = p.records.size();
  std::vector<uint64_t> in(n, 0), answered(n, 0);
  std::vector<bool> reached(n, false);
  uint64_t last = 0;
  size_t next_line = 0;
  const std::vector<uint64_t>& stops_sent = sitl::stops_sent();
  size_t next_timed = 0;
  for (size_t k = 0; k < n; ++k) {
    PredictRecord& r = p.records[k];
    if (next_line < sent_of.size() && sent_of[next_line] == k) {
      const size_t i = next_line++;
      if (i < got.size()) {
        in[k] = got[i].in - t0;
        // A line whose bytes came in while a '!' was stopping the arm is read once it is at
        // rest (the main loop reads no line while a stop goes on): then it is in.
        if (!r.stop)
          for (const sitl::StopEvent& e : stops)
            if (e.bang < in[k] && in[k] < e.rest) in[k] = e.rest;
        answered[k] = got[i].answered - t0;
        reached[k] = true;
        last = answered[k];
        if (!r.stop && got[i].reply != reply_text(r.reply)) {
          if (got[i].reply == reply_text(kStopped) && r.reply == kOk) {
            r.reply = kStopped;  // a timed '!' came while it waited: it changed nothing
            r.cut = true;
            append_note(r.note, "answered error:15: the '!' came while it waited");
          } else {
            throw std::logic_error("line " + std::to_string(r.line) + " (" + lines[i] + "): the firmware answered " +
                                   (got[i].reply.empty() ? "nothing" : got[i].reply) + ", the host's model " +
                                   reply_text(r.reply));
          }
        }
        continue;
      }
    } else if (next_timed < timed_of.size() && timed_of[next_timed] == k) {
      const size_t i = next_timed++;
      if (i < stops_sent.size()) {
        in[k] = answered[k] = stops_sent[i] - t0;
        reached[k] = true;
        continue;
      }
    }
    in[k] = answered[k] = last;
  }

  // The actions the firmware began, and the steps each made (the coil log's steps after its
  // start, up to and with its end's).
  std::vector<Begun> begun;
  const std::vector<sitl::ActionEvent>& log = hw.actions;
  const int motors = robot.actuation.num_motors;
  for (size_t i = actions0; i < log.size(); ++i) {
    if (log[i].kind == sitl::kTimerStopped) continue;
    Begun b{log[i].tick - t0, (i + 1 < log.size() ? log[i + 1].tick : log[i].tick) - t0, log[i].kind, i, {}};
    b.done.delta.assign(size_t(motors), 0);
    begun.push_back(b);
  }
  {
    size_t a = 0;
    uint64_t last_step = ~uint64_t(0);
    for (size_t i = coils0; i < hw.coil_log.size(); ++i) {
      const sitl::CoilWrite& w = hw.coil_log[i];
      if (w.step == 0) continue;
      const uint64_t t = w.tick - t0;
      while (a < begun.size() && begun[a].end < t) ++a;
      if (a == begun.size() || begun[a].begin >= t || w.motor >= motors) continue;  // (a step outside any action)
      begun[a].done.delta[w.motor] += w.step;
      if (t != last_step) ++begun[a].done.steps;
      last_step = t;
    }
  }

  // Each '!' record's event (its bang is when the record was in), and for each record the
  // first '!' that could empty the queue of its actions: the first to come after its reply
  // (a line answered ok was queued by then; one held while a stop went on is read after it),
  // or, for a line a '!' caught waiting (error:15), that one.
  std::vector<const sitl::StopEvent*> event_of(n, nullptr), next_stop(n, nullptr);
  std::vector<size_t> record_of(stops.size(), n);
  {
    size_t e = 0;
    for (size_t k = 0; k < n; ++k) {
      if (!p.records[k].stop || !reached[k]) continue;
      while (e < stops.size() && stops[e].bang != in[k]) ++e;
      if (e == stops.size()) throw std::logic_error("a '!' the firmware never received");
      record_of[e] = k;
      event_of[k] = &stops[e++];
    }
    size_t ordinal = 0;  // the replies before this record's
    for (size_t k = 0; k < n; ++k) {
      const PredictRecord& r = p.records[k];
      if (r.stop || !reached[k]) continue;
      for (const sitl::StopEvent& ev : stops) {
        const size_t e = size_t(&ev - stops.data());
        const bool after = ev.bang > in[k] || (ev.bang == in[k] && record_of[e] > k);  // (read before it)
        if (after && (r.reply == kOk ? ev.replies > ordinal : ev.replies >= ordinal)) {
          next_stop[k] = &ev;
          break;
        }
      }
      ++ordinal;
    }
  }

  // The model's actions, in queue order, matched to those the firmware began. An action the
  // firmware did not begin before the arm came to rest after the first '!' since its line
  // came, that '!' emptied from the queue (or its line, waiting, was answered error:15).
  std::map<Item, Done> made;
  std::map<Item, const Begun*> when;
  std::vector<std::vector<Item>> cleared_by(stops.size());
  size_t j = 0;
  for (size_t k = 0; k < n; ++k) {
    const PredictRecord& r = p.records[k];
    if (!r.queued || !reached[k] || r.stop) continue;
    const int parts = r.segments.empty() ? 1 : int(r.segments.size());
    const sitl::StopEvent* stop = next_stop[k];
    for (int s = 0; s < parts; ++s) {
      const Item item{k, r.segments.empty() ? -1 : s};
      const bool next = j < begun.size() && kind_is(begun[j].kind, r.action) && begun[j].begin >= in[k];
      if (next && (stop == nullptr || begun[j].at < stop->actions)) {
        made[item] = begun[j].done;
        when[item] = &begun[j];
        ++j;
      } else if (stop != nullptr && r.reply != kOk) {
        made[item] = Done{std::vector<int32_t>(size_t(motors), 0), 0};  // never queued
      } else if (stop != nullptr) {
        made[item] = Done{std::vector<int32_t>(size_t(motors), 0), 0};
        cleared_by[size_t(stop - stops.data())].push_back(item);
      } else {
        throw std::logic_error("line " + std::to_string(r.line) + " (" + r.text +
                               "): the firmware began no action of its kind where the host's model queued one");
      }
    }
  }
  if (j != begun.size())
    throw std::logic_error("the firmware began " + std::to_string(begun.size()) + " actions, the host's model queued " +
                           std::to_string(j));

  // A T's segments: each one's end (one the firmware never began: its record's start).
  for (size_t k = 0; k < n; ++k)
    for (size_t sg = 0; sg < p.records[k].segments.size(); ++sg) {
      const auto it = when.find(Item{k, int(sg)});
      p.records[k].segments[sg].end_tick = it != when.end() ? it->second->end : in[k];
    }

  // Times: a record that queued is from its first action's start to its last one's end; one
  // that waits for rest (a setting, Z) is at its reply; any other at its arrival.
  for (size_t k = 0; k < n; ++k) {
    PredictRecord& r = p.records[k];
    r.arrive_tick = in[k];
    r.start_tick = r.end_tick = r.waits_for_rest && r.reply == kOk ? answered[k] : in[k];
    if (r.stop || !r.queued) continue;
    const int parts = r.segments.empty() ? 1 : int(r.segments.size());
    const auto first = when.find(Item{k, r.segments.empty() ? -1 : 0});
    if (first != when.end()) r.start_tick = first->second->begin;
    for (int s = parts - 1; s >= 0; --s) {
      const auto it = when.find(Item{k, r.segments.empty() ? -1 : s});
      if (it != when.end()) {
        r.end_tick = it->second->end;
        break;
      }
    }
  }

  // What each '!' did: the actions running or queued when it came.
  for (size_t k = 0; k < n; ++k) {
    PredictRecord& r = p.records[k];
    if (!r.stop) continue;
    if (!reached[k]) {  // (a timed '!' the run never sent: the arm never stepped)
      r.start_tick = r.end_tick = r.arrive_tick = in[k];
      continue;
    }
    const sitl::StopEvent& e = *event_of[k];
    std::vector<Item> hit;
    for (const auto& w : when) {  // running when it came (begun, not ended before it), or begun during the stop
      const Begun& b = *w.second;
      if (b.at < e.actions && b.end >= e.bang) hit.push_back(w.first);
    }
    for (const Item& c : cleared_by[size_t(&e - stops.data())]) hit.push_back(c);
    for (size_t q = 0; q < k; ++q)  // the lines it answered error:15
      if (p.records[q].reply == kStopped && answered[q] >= e.bang && answered[q] <= e.rest && p.records[q].queued)
        for (int s = 0; s < (p.records[q].segments.empty() ? 1 : int(p.records[q].segments.size())); ++s) {
          const Item it{q, p.records[q].segments.empty() ? -1 : s};
          if (std::find(hit.begin(), hit.end(), it) == hit.end()) hit.push_back(it);
        }
    std::sort(hit.begin(), hit.end());
    r.start_tick = r.arrive_tick = e.bang;
    r.end_tick = e.rest;
    cut(p, k, hit, made, e.rest);

  }

  uint64_t end = last;
  for (size_t i = actions0; i < log.size(); ++i) end = std::max(end, log[i].tick - t0);
  for (const sitl::StopEvent& e : stops) end = std::max(end, e.rest);
  p.total_ticks = end;
  p.first_step_tick = sitl::first_step() == 0 ? 0 : sitl::first_step() - t0;
  for (PredictRecord& r : p.records) r.ticks = r.end_tick - r.start_tick;
}
}  // namespace articula::host
