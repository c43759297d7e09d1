// host/lib/predict_run.cpp - predict_program() (predict.h): the firmware itself (firmware/src,
// on its virtual clock: firmware/sitl) runs the program's lines as the sender delivers them,
// and every record is read from what it did: its reply and the plan it left (hal::replied),
// the actions it queued (hal::action_queued) and when each began (the action log), the steps
// its coils made, where each '!' left the arm. The host adds what the firmware does not
// know: RoboSim's statements as protocol lines, the tool positions the steps give (the
// shared core's kinematics), and notes.
#include <articula/line.h>
#include <articula/planner.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <optional>

#include "blocks.h"
#include "firmware_machine.h"
#include "firmware_session.h"
#include "predict.h"
#include "predict_detail.h"
#include "records_json.h"
#include "robot_view.h"

// The firmware (firmware/src, built for the host's eight motors: firmware/sitl/sitl.cmake).
#include "hal_sitl.h"
#include "firmware.h"
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

// An action the firmware began (hal::action_began): its ticks and what it made.
struct Begun {
  uint64_t begin, end;  // end: the action log's next entry (the next action, or the timer's stop)
  size_t at;            // its place in the action log
  Done done;
};

void note_on(PredictRecord& r, const std::string& note) { append_note(r.note, note); }

// Notes on what a line did, for a reader: from its command, its reply and what it queued.
void command_notes(PredictRecord& r, const Command& cmd, const Robot& robot, const int32_t* commanded_before,
                   const uint32_t* settings, bool shifted, uint32_t driven) {
  const int n = robot.actuation.num_motors;
  if (r.reply != kOk) {
    if (r.reply == kJointLimit && (cmd.type == kCmdRotate || cmd.type == kCmdMoveAbsolute)) {
      int32_t target[kMaxJoints];
      for (int i = 0; i < n; ++i)
        target[i] = cmd.type == kCmdMoveAbsolute ? cmd.arg[i] : commanded_before[i] + (i == cmd.arg[0] ? cmd.arg[1] : 0);
      note_on(r, limit_note(robot, target));
    }
    if (r.reply == kUnreachable && cmd.type == kCmdMoveTool) {  // how far, and what holds the tool back
      const IkResult res = InverseKinematics(robot).solve(
          IkTarget::at(make_vec3(cmd.arg[0] / 1000.0, cmd.arg[1] / 1000.0, cmd.arg[2] / 1000.0)), ik_start(robot, nullptr));
      note_on(r, ik_miss_words(robot, res));
    }
    if (r.reply == kNoClosedForm)
      note_on(r, std::string("the firmware ") + (cmd.type == kCmdLine ? "runs T" : "solves P") +
                      " only for a yaw-pitch-pitch arm with 3 motors (identity or parallelogram coupling)" +
                      (cmd.type == kCmdLine ? "; articula run follows the line on any robot" : ""));
    return;
  }
  switch (cmd.type) {
    case kCmdInfo: note_on(r, "answered with an info line; nothing moves"); break;
    case kCmdListSettings: note_on(r, "answered with the settings; nothing moves"); break;
    case kCmdName: note_on(r, "stages the robot's name in the configuration (robot configuration: not simulated)"); break;
    case kCmdSetSetting:
      if (cmd.arg[0] == kCommitSetting)
        note_on(r, "commits the staged robot configuration when its checksum is this one (not simulated: the "
                    "prediction keeps this robot file's arm)");
      else if (cmd.arg[0] >= 100)
        note_on(r, "stages a value of the robot configuration (not simulated)");
      else
        note_on(r, cmd.arg[0] == ControllerSettings::kEndstops
                        ? "saved; decides Alarm at the next power-up, H uses it from now"
                        : "takes effect for the actions after it");
      break;
    case kCmdSetZero:
      note_on(r, shifted ? "nothing moves: the controller now counts the arm's pose as home, so its steps and "
                            "limits are off the arm's (joint values and tools below are where the arm really is)"
                          : "nothing moves");
      break;
    case kCmdRotate:
    case kCmdMoveAbsolute:
    case kCmdMoveTool:
    case kCmdLine:
      if (!r.queued) note_on(r, "within the same steps: only the commanded angles change, nothing is queued");
      break;
    case kCmdHome:
      if (settings[ControllerSettings::kEndstops] != 0)
        note_on(r, "seek time assumes each switch trips at its motor's minimum angle");
      break;
    case kCmdDwell: note_on(r, "waits; nothing moves"); break;
    case kCmdOutput: note_on(r, "sets an output pin; nothing moves"); break;
    case kCmdWaitInput:
      note_on(r, (cmd.arg[0] >= 0 && cmd.arg[0] < 32 && (driven >> cmd.arg[0]) & 1)
                     ? "waits for an input's level, which a wire drives (another arm's output in the cell); a wait "
                       "whose time runs out drops what was queued after it (W:21)"
                     : "waits for an input's level: alone, nothing drives an input (it reads 1, its pull-up; a pin O "
                       "set reads its own level); a wait whose time runs out drops what was queued after it (W:21)");
      break;
    default: break;
  }
}

// T's notes: where a refused line fails, or how close to the line the tool stays.
void line_notes(PredictRecord& r, const Robot& robot, const ConfiguredArm<kFirmwareMotors>& arm, const Command& cmd,
                const int32_t* before_steps, const Millideg* before_commanded, const int32_t* offset,
                uint32_t chord, bool keep_path) {
  if (!arm.has_point || robot.actuation.num_motors != 3) return;
  const YppLineSolver solver = {&arm.arm, robot.actuation.motors};
  float from[3], to[4];
  for (int k = 0; k < 4; ++k) to[k] = float(cmd.arg[k]) * 0.001f;
  solver.tool(from, before_commanded);
  if (r.reply == kUnreachable || r.reply == kLineNotFollowed) {
    LineCutter<float, kMaxJoints> cut;
    Millideg end[kMaxJoints] = {};
    cut.start(from, to, before_commanded, 3, float(int32_t(chord)) * 0.001f);
    while (!cut.done()) {
      const Status s = cut.next(solver, end);
      if (s == kOk) continue;
      const float f = cut.refused_fraction();
      const auto at = [&](int k) { return number_text(std::round((from[k] + f * (to[k] - from[k])) * 10) / 10); };
      note_on(r, std::string(s == kLineNotFollowed ? "the pose would jump" : "cannot be reached") + " at " +
                      number_text(std::round(double(f) * cut.length() * 10) / 10) + " mm along the line of " +
                      number_text(std::round(double(cut.length()) * 10) / 10) + " mm, at (" + at(0) + ", " + at(1) +
                      ", " + at(2) + ") mm; nothing moves");
      return;
    }
    return;
  }
  if (r.reply != kOk || r.segments.empty()) return;
  std::vector<const std::vector<int32_t>*> moves;
  for (const auto& sg : r.segments) moves.push_back(&sg.delta_steps);
  const std::vector<Vec3<double>> path = tool_path(robot, before_steps, offset, moves);
  r.line_error_mm = distance_from_segment(path, make_vec3(double(from[0]), double(from[1]), double(from[2])),
                                          make_vec3(double(to[0]), double(to[1]), double(to[2])));
  if (keep_path) r.path = path;
  note_on(r, std::to_string(r.segments.size()) + " segments; the tool at every step stays within " +
                  number_text(std::round(r.line_error_mm * 1000) / 1000) + " mm of the line");
}

}  // namespace

Prediction predict_program(const Robot& robot_in, const Program& program, const ControllerSettings& settings,
                           const SenderModel& sender, bool keep_path, const DrivenInputs& inputs) {
  const ConfiguredArm<kFirmwareMotors> arm = machine_arm(robot_in);
  const int motors = robot_in.actuation.num_motors;
  Prediction p;
  p.robot = robot_in.name;
  p.program = program.source;
  p.settings = settings;

  // A Nano of its own (firmware/sitl/machine.h), this thread's until the prediction is made:
  // predictions run side by side, in threads of their own too.
  const std::unique_ptr<sitl::Machine> nano = std::make_unique<sitl::Machine>();
  const sitl::Machine::Use use(*nano);
  power_up(robot_in, arm, settings);
  sitl::Hardware& hw = sitl::hw();
  const uint64_t t0 = hw.now;
  if (inputs.pins && inputs.levels) {
    hw.io_driven = inputs.pins;
    hw.io_sync = [&hw, t0, levels = inputs.levels] { hw.io_external = levels(hw.now - t0); };
  }
  const size_t coils0 = hw.coil_log.size(), actions0 = hw.actions.size(), queued0 = hw.queued.size(),
               replies0 = hw.replies.size();
  const robot::State start = firmware::planned();

  // The program's lines as the sender sends them, each asked for when it goes. The robot
  // each record is described on (RoboSim's l changes the host's model, not the arm).
  std::vector<Robot> models{robot_in};
  Robot robot = robot_in;
  StatementLines statements(robot, settings.value[ControllerSettings::kMaxRate], [] {
    const robot::State& plan = firmware::planned();
    return std::vector<Millideg>(plan.commanded, plan.commanded + robot::kJoints);
  });
  std::vector<size_t> model_of;  // each record's model
  std::vector<size_t> sent_of;   // each line sent: its record
  size_t next_statement = 0;
  p.records.reserve(program.statements.size());
  model_of.reserve(program.statements.size());
  const auto next_line = [&](std::string& line) {
    while (next_statement < program.statements.size()) {
      PredictRecord r;
      const Statement& st = program.statements[next_statement++];
      const bool send = statements.begin(st, r, line);
      if (st.kind == Statement::Kind::kLinkLengths) models.push_back(robot);
      model_of.push_back(models.size() - 1);
      p.records.push_back(std::move(r));
      if (send) {
        sent_of.push_back(p.records.size() - 1);
        return true;
      }
    }
    return false;
  };
  const std::vector<sitl::Exchange> got = sitl::run_lines(
      next_line, sender.kind == SenderModel::kRest ? sitl::kAtRest : sitl::kStreamed, sender.stop_ticks);
  if (!hw.errors.empty()) throw std::logic_error("the firmware's run: " + sitl::hal_errors());

  // The '!'s: when each came and when the arm was at rest after it.
  std::vector<sitl::StopEvent> stops = sitl::stop_events();
  for (sitl::StopEvent& e : stops) {
    e.bang -= t0;
    if (e.rest == ~uint64_t(0)) {
      e.rest = hw.now, e.actions = hw.actions.size(), e.queued = hw.queued.size();
      e.planned = firmware::planned();
    }
    e.rest -= t0;
  }

  // A line whose bytes came in while a '!' was stopping the arm is read once it is at rest
  // (the main loop reads no line while a stop goes on): then it is in.
  const auto read_at = [&](uint64_t in) {
    for (const sitl::StopEvent& e : stops)
      if (e.bang < in && in < e.rest) in = e.rest;
    return in;
  };

  // Each record's source: a line sent (its exchange), a timed '!' (its place among the stops
  // sent), or none (host-only). The timed '!'s go in before the first record that came after
  // them: a line read after it, a host-only record after a line answered after it.
  const std::vector<uint64_t>& stops_sent = sitl::stops_sent();
  struct Source {
    int line = -1;   // exchange
    int timed = -1;  // stops_sent
  };
  std::vector<PredictRecord> records;
  std::vector<Source> source;
  std::vector<size_t> models_of;
  records.reserve(p.records.size() + stops_sent.size());
  source.reserve(records.capacity());
  models_of.reserve(records.capacity());
  {
    size_t line = 0, timed = 0;
    uint64_t last_answered = 0;
    for (size_t k = 0; k <= p.records.size(); ++k) {
      const bool sent = line < sent_of.size() && sent_of[line] == k && line < got.size();
      uint64_t arrives = k == p.records.size() ? ~uint64_t(0) : sent ? read_at(got[line].in - t0) : last_answered;
      if (sent && p.records[k].stop) arrives = got[line].in - t0;
      while (timed < stops_sent.size() && stops_sent[timed] - t0 < arrives) {
        PredictRecord r;
        r.line = k < p.records.size() ? p.records[k].line : p.records.empty() ? 0 : p.records.back().line;
        r.text = "!";
        r.stop = true;
        r.stop_at = int64_t(stops_sent[timed] - t0);
        note_on(r, "stops the arm: it decelerates along its path to rest and empties its queue; the lines after "
                    "it wait for rest and start from the steps reached (never answered)");
        records.push_back(r);
        source.push_back(Source{-1, int(timed++)});
        models_of.push_back(k < p.records.size() ? model_of[k] : models.size() - 1);
      }
      if (k == p.records.size()) break;
      records.push_back(std::move(p.records[k]));
      models_of.push_back(model_of[k]);
      Source s;
      if (line < sent_of.size() && sent_of[line] == k) {
        if (sent) {
          s.line = int(line);
          if (!p.records[k].stop) last_answered = got[line].answered - t0;
        }
        ++line;
      }
      source.push_back(s);
    }
  }
  p.records.swap(records);
  const size_t n = p.records.size();
  const uint64_t first_step = sitl::first_step() == 0 ? 0 : sitl::first_step() - t0;
  for (PredictRecord& r : p.records)
    if (r.stop_at >= 0)
      note_on(r, "sent " + number_text(double(uint64_t(r.stop_at) - first_step) / kStepTickHz) +
                      " s after the first step, whatever the lines are doing");

  // Each record's arrival and reply: a line when it was in (read); a host-only line, a line the
  // run never reached, at the last answer before it.
  std::vector<uint64_t> in(n, 0), answered(n, 0);
  std::vector<bool> reached(n, false);
  {
    uint64_t last = 0;
    for (size_t k = 0; k < n; ++k) {
      PredictRecord& r = p.records[k];
      if (source[k].line >= 0) {
        const sitl::Exchange& x = got[size_t(source[k].line)];
        in[k] = r.stop ? x.in - t0 : read_at(x.in - t0);
        answered[k] = x.answered - t0;
        reached[k] = r.stop || !x.reply.empty();
        if (reached[k]) last = answered[k];
        continue;
      }
      if (source[k].timed >= 0) {
        in[k] = answered[k] = stops_sent[size_t(source[k].timed)] - t0;
        reached[k] = true;
        continue;
      }
      in[k] = answered[k] = last;
    }
  }

  // What each line did, from the firmware's replies and the actions it queued; the state
  // after each record, the steps the firmware counts, and the steps the arm really is at
  // (offset: they differ after Z).
  std::vector<std::vector<Item>> items(n);  // each record's actions: (record, segment)
  std::vector<std::vector<size_t>> queued_of(n);  // each one's place in hw.queued
  std::vector<std::vector<int32_t>> offset_of(n);
  {
    robot::State state = start;
    int32_t offset[kMaxJoints] = {};
    uint32_t now_settings[kSettingCount];
    for (int s = 0; s < kSettingCount; ++s) now_settings[s] = settings.value[size_t(s)];
    int gripper = -1;
    size_t reply = replies0, queued = queued0;
    for (size_t k = 0; k < n; ++k) {
      PredictRecord& r = p.records[k];
      const Robot& model = models[models_of[k]];
      const robot::State before = state;
      int32_t before_offset[kMaxJoints];
      std::copy(offset, offset + kMaxJoints, before_offset);
      Command cmd;
      const bool answered_line = source[k].line >= 0 && !r.stop && reached[k];
      if (r.stop) {
        if (reached[k]) {  // (its event: matched below; the state is the firmware's after it)
          for (const sitl::StopEvent& e : stops)
            if (e.bang == in[k]) {
              state = e.planned;
              // The gripper: the last gripper action that began (a '!' emptied the others).
              gripper = -1;
              for (size_t q = queued0; q < e.queued; ++q)
                if (hw.queued[q].kind == queue::kGripper && hw.queued[q].began != sitl::kNever)
                  gripper = hw.queued[q].percent;
              break;
            }
        }
      } else if (answered_line) {
        if (reply >= hw.replies.size()) throw std::logic_error("a reply the firmware never wrote");
        const sitl::Reply& got_reply = hw.replies[reply++];
        r.reply = Status(got_reply.status);
        if (reply_text(r.reply) != got[size_t(source[k].line)].reply)
          throw std::logic_error("line " + std::to_string(r.line) + ": the firmware's reply " +
                                 got[size_t(source[k].line)].reply + " and its record differ");
        // (Its arguments, for the notes and a target: parsed again only when they are needed.)
        const bool args = r.command == kCmdSetSetting || r.command == kCmdMoveTool || r.command == kCmdLine ||
                          (r.command == kCmdWaitInput && inputs.pins) ||
                          r.reply == kJointLimit || r.reply == kNoClosedForm || r.reply == kUnreachable;
        if (args) parse_protocol_line(cmd, r.protocol.empty() ? r.text : r.protocol, motors);
        cmd.type = r.command;
        // Its actions: those queued since the reply before.
        std::vector<int32_t> total(size_t(motors), 0);
        for (size_t q = queued; q < got_reply.queued; ++q) {
          const sitl::QueuedAction& a = hw.queued[q];
          const bool move = a.kind == queue::kMove || a.kind == queue::kHome;
          std::vector<int32_t> delta(size_t(motors), 0);
          uint32_t dominant = 0;
          if (move)
            for (int i = 0; i < motors; ++i) {
              delta[size_t(i)] = a.delta[i];
              total[size_t(i)] += a.delta[i];
              dominant = std::max(dominant, uint32_t(a.delta[i] < 0 ? -int64_t(a.delta[i]) : a.delta[i]));
            }
          r.queued = true;
          r.action = a.kind == queue::kMove   ? PredictRecord::Action::kMove
                     : a.kind == queue::kHome ? PredictRecord::Action::kHome
                                              : PredictRecord::Action::kPause;
          if (cmd.type == kCmdLine) {
            PredictRecord::Segment sg;
            sg.delta_steps = delta;
            sg.dominant_steps = dominant;
            sg.cruise4 = a.cruise4;
            r.segments.push_back(sg);
            items[k].push_back(Item{k, int(r.segments.size()) - 1});
            r.dominant_steps += dominant;
          } else {
            items[k].push_back(Item{k, -1});
            r.dominant_steps = dominant;
          }
          queued_of[k].push_back(q);
          if (a.kind == queue::kGripper) {
            gripper = a.percent;
            note_on(r, "servo pulse " + std::to_string(a.pulse_us) + " us");
          }
        }
        queued = got_reply.queued;
        if (r.queued) r.delta_steps = total;
        r.motion = MotionSettings{kStepTickHz, got_reply.settings[kSetMaxRate], got_reply.settings[kSetAccel]};
        r.junction = got_reply.settings[kSetJunction];
        bool shifted = false;
        if (r.reply == kOk) {
          if (cmd.type == kCmdSetZero)  // the arm stays where it is: the firmware counts it as home
            for (int i = 0; i < motors; ++i) {
              offset[i] = before.steps[i] + before_offset[i] - got_reply.planned.steps[i];
              shifted = shifted || offset[i] != 0;
            }
          state = got_reply.planned;
          std::copy(got_reply.settings, got_reply.settings + kSettingCount, now_settings);
        } else if (r.queued) {  // a line a '!' caught while it queued (a T's segments): what it queued
          for (int i = 0; i < motors; ++i) state.steps[i] += r.delta_steps[size_t(i)];
        }
        r.waits_for_rest = r.reply == kOk && !r.queued && answered[k] > in[k];
        if (r.waits_for_rest)
          note_on(r, "answered once the arm was at rest, " +
                          number_text(std::round(double(answered[k] - in[k]) / kStepTickHz * 1000) / 1000) +
                          " s after it came");
        command_notes(r, cmd, model, before.commanded, now_settings, shifted, inputs.pins);
        if (cmd.type == kCmdMoveTool || cmd.type == kCmdLine) {
          r.has_target = true;
          r.target = make_vec3(cmd.arg[0] / 1000.0, cmd.arg[1] / 1000.0, cmd.arg[2] / 1000.0);
        }
        if (cmd.type == kCmdLine)
          line_notes(r, model, arm, cmd, before.steps, before.commanded, before_offset,
                     now_settings[kSetChord], keep_path);
        else if (keep_path && r.queued && r.action != PredictRecord::Action::kPause)
          r.path = tool_path(model, before.steps, before_offset, {&r.delta_steps});
        if (r.reply == kStopped) append_note(r.note, "answered error:15: the '!' came while it waited");
      }
      describe_state(model, r, state.steps, state.commanded, offset);
      offset_of[k].assign(offset, offset + motors);
      r.gripper_percent = gripper;
    }
  }

  std::vector<std::vector<int32_t>> described(stops.empty() ? 0 : n);  // (only a '!' changes them)
  for (size_t k = 0; k < described.size(); ++k) described[k] = p.records[k].steps;

  // The actions the firmware began, and the steps each made (the coil log's steps after its
  // start, up to and with its end's).
  std::vector<Begun> begun;                      // in the action log's order
  std::vector<size_t> begun_at(hw.actions.size());  // each log entry's in begun
  const std::vector<sitl::ActionEvent>& log = hw.actions;
  for (size_t i = actions0; i < log.size(); ++i) {
    if (log[i].kind == sitl::kTimerStopped) continue;
    Begun b{log[i].tick - t0, (i + 1 < log.size() ? log[i + 1].tick : log[i].tick) - t0, i, {}};
    b.done.delta.assign(size_t(motors), 0);
    begun_at[i] = begun.size();
    begun.push_back(std::move(b));
  }
  {
    auto a = begun.begin();
    uint64_t last_step = ~uint64_t(0);
    for (size_t i = coils0; i < hw.coil_log.size(); ++i) {
      const sitl::CoilWrite& w = hw.coil_log[i];
      if (w.step == 0) continue;
      const uint64_t t = w.tick - t0;
      while (a != begun.end() && a->end < t) ++a;
      if (a == begun.end() || a->begin >= t || w.motor >= motors) continue;  // (a step outside any action)
      a->done.delta[w.motor] += w.step;
      if (t != last_step) ++a->done.steps;
      last_step = t;
    }
  }

  // Each action: what it made and when it ran; one that never began, the first '!' after it
  // was queued emptied from the queue.
  std::map<Item, Done> made;  // (for the '!'s)
  std::vector<std::vector<const Begun*>> when(n);  // each record's actions' (null: never began)
  std::vector<std::vector<Item>> cleared_by(stops.size());
  for (size_t k = 0; k < n; ++k)
    for (size_t j = 0; j < items[k].size(); ++j) {
      const Item& item = items[k][j];
      const size_t q = queued_of[k][j];
      const size_t at = hw.queued[q].began;
      if (at != sitl::kNever) {
        const Begun& b = begun[begun_at[at]];
        if (!stops.empty()) made[item] = b.done;
        when[k].push_back(&b);
        continue;
      }
      when[k].push_back(nullptr);
      made[item] = Done{std::vector<int32_t>(size_t(motors), 0), 0};
      size_t e = 0;
      while (e < stops.size() && stops[e].queued <= q) ++e;
      if (e == stops.size())
        throw std::logic_error("line " + std::to_string(p.records[item.first].line) +
                               ": an action the firmware queued never began, and no '!' emptied it");
      cleared_by[e].push_back(item);
    }

  // A T's segments: each one's end (one the firmware never began: its record's arrival).
  for (size_t k = 0; k < n; ++k)
    for (size_t sg = 0; sg < p.records[k].segments.size() && sg < when[k].size(); ++sg)
      p.records[k].segments[sg].end_tick = when[k][sg] ? when[k][sg]->end : in[k];

  // Times: a record that queued is from its first action's start to its last one's end; any
  // other at its reply (a setting or Z waits for the arm to be at rest).
  for (size_t k = 0; k < n; ++k) {
    PredictRecord& r = p.records[k];
    r.arrive_tick = in[k];
    r.start_tick = r.end_tick = r.reply == kOk ? answered[k] : in[k];
    if (r.stop || items[k].empty()) continue;
    if (when[k].front()) r.start_tick = when[k].front()->begin;
    for (auto it = when[k].rbegin(); it != when[k].rend(); ++it)
      if (*it) {
        r.end_tick = (*it)->end;
        break;
      }
  }

  // What each '!' did: the actions running or queued when it came.
  for (size_t k = 0; k < n; ++k) {
    PredictRecord& r = p.records[k];
    if (!r.stop) continue;
    if (!reached[k]) {  // (a '!' the run never sent)
      r.start_tick = r.end_tick = r.arrive_tick = in[k];
      continue;
    }
    size_t e = 0;
    while (e < stops.size() && stops[e].bang != in[k]) ++e;
    if (e == stops.size()) throw std::logic_error("a '!' the firmware never received");
    const sitl::StopEvent& ev = stops[e];
    std::vector<Item> hit;
    for (size_t q = 0; q < n; ++q)  // running when it came (begun, not ended before it), or begun during the stop
      for (size_t j = 0; j < when[q].size(); ++j)
        if (when[q][j] && when[q][j]->at < ev.actions && when[q][j]->end >= ev.bang) hit.push_back(items[q][j]);
    for (const Item& c : cleared_by[e]) hit.push_back(c);
    std::sort(hit.begin(), hit.end());
    r.start_tick = r.arrive_tick = ev.bang;
    r.end_tick = ev.rest;
    cut(p, k, hit, made, ev.rest);
    for (int i = 0; i < motors; ++i)
      if (r.steps[size_t(i)] != ev.planned.steps[i])
        throw std::logic_error("line " + std::to_string(r.line) + ": the '!' left motor " + std::to_string(i) +
                               " at step " + std::to_string(ev.planned.steps[i]) + ", the records at " +
                               std::to_string(r.steps[size_t(i)]));
  }

  // The records a '!' changed: their state is the steps they made, the commanded angles
  // theirs (the firmware's after a stop: controller.cpp rederive_planned).
  for (size_t k = 0; k < n; ++k) {
    PredictRecord& r = p.records[k];
    if (!r.cut && !r.stop && (described.empty() || r.steps == described[k])) continue;
    Millideg commanded[kMaxJoints];
    for (int i = 0; i < motors; ++i)
      commanded[i] = steps_to_millideg(models[models_of[k]].actuation.motors[i], r.steps[size_t(i)]);
    describe_state(models[models_of[k]], r, r.steps.data(), commanded, offset_of[k].data());
  }

  uint64_t end = 0;
  for (size_t k = 0; k < n; ++k) end = std::max(end, answered[k]);
  for (size_t i = actions0; i < log.size(); ++i) end = std::max(end, log[i].tick - t0);
  for (const sitl::StopEvent& e : stops) end = std::max(end, e.rest);
  p.total_ticks = end;
  p.first_step_tick = first_step;
  for (PredictRecord& r : p.records) {
    r.ticks = r.end_tick - r.start_tick;
    if (r.reply != kOk) ++p.rejected;
    p.worst_error_mm = std::max(p.worst_error_mm, r.error_mm);
  }
  return p;
}

}  // namespace articula::host
