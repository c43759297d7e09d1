// host/lib/timeline.cpp - a program's time line and the arm at any instant of it.
#include "timeline.h"

#include <algorithm>
#include <cmath>

#include "records_json.h"

namespace articula::host {
namespace {

std::vector<double> user_units(const Robot& robot, const std::vector<double>& q_model) {
  std::vector<double> out(q_model.size());
  for (size_t j = 0; j < q_model.size(); ++j) out[j] = joint_from_model(robot, int(j), q_model[j]);
  return out;
}

std::vector<double> model_units(const Robot& robot, const std::vector<double>& q_user) {
  std::vector<double> out(q_user.size());
  for (size_t j = 0; j < q_user.size(); ++j) out[j] = joint_to_model(robot, int(j), q_user[j]);
  return out;
}

// What every action has, whatever made it.
TimelineAction action(int line, const std::string& command, Status reply, const std::string& note) {
  TimelineAction a;
  a.line = line;
  a.command = command;
  a.reply = reply;
  a.error = reply == kOk ? "" : status_text(uint8_t(reply));
  a.note = note;
  return a;
}

std::vector<double> lerp(const std::vector<double>& a, const std::vector<double>& b, double f) {
  std::vector<double> out(a.size());
  for (size_t k = 0; k < a.size(); ++k) out[k] = a[k] + f * (b[k] - a[k]);
  return out;
}

// The ideal tool where the last accepted action left it (the power-up pose before any).
Vec3<double> last_tool(const std::vector<TimelineAction>& actions, const Robot& robot, const std::vector<double>& start_q) {
  for (auto it = actions.rbegin(); it != actions.rend(); ++it)
    if (it->reply == kOk) return it->tool_ideal;
  return tool_position(robot.model, model_units(robot, start_q).data());
}

// A T record's segment ends as time line points: their steps (from the record's end back
// by its segments), in joint values (the record's own shift by Z added: the joints are linear
// in the steps), at the ticks the firmware ended them (predict_program), on the record's span.
void add_segments(const Robot& robot, const PredictRecord& r, TimelineAction& a) {
  const int n = robot.actuation.num_motors, nj = robot.model.num_joints;
  if (r.segments.empty() || r.end_tick <= r.start_tick) return;
  std::vector<uint64_t> ends;
  for (const auto& sg : r.segments) ends.push_back(std::max(sg.end_tick, r.start_tick) - r.start_tick);
  ends.back() = r.end_tick - r.start_tick;
  std::vector<int32_t> steps = r.steps;
  for (const auto& s : r.segments)
    for (int i = 0; i < n; ++i) steps[size_t(i)] -= s.delta_steps[size_t(i)];
  auto joints_at = [&](const std::vector<int32_t>& st) {
    double q[kMaxJoints];
    joints_from_steps(q, robot.actuation, st.data());
    std::vector<double> out(static_cast<size_t>(nj));
    for (int j = 0; j < nj; ++j) out[size_t(j)] = joint_from_model(robot, j, q[j]);
    return out;
  };
  const std::vector<double> at_end = joints_at(r.steps);
  for (size_t k = 0; k < r.segments.size(); ++k) {
    for (int i = 0; i < n; ++i) steps[size_t(i)] += r.segments[k].delta_steps[size_t(i)];
    std::vector<double> q = joints_at(steps);
    for (int j = 0; j < nj; ++j) q[size_t(j)] += r.joints[size_t(j)] - at_end[size_t(j)];
    a.via_s.push_back(a.start_s + (a.end_s - a.start_s) * double(ends[k]) / double(ends.back()));
    a.via_q.push_back(std::move(q));
  }
}

}  // namespace

double JointTiming::move_s(const Robot& robot, const double* q_from, const double* q_to) const {
  double s = 0;
  for (int j = 0; j < robot.model.num_joints; ++j) {
    const double speed = joint_is_angle(robot, j) ? deg_to_rad(speed_deg) : speed_mm;
    s = std::max(s, std::fabs(q_to[j] - q_from[j]) / speed);
  }
  return s;
}

Timeline Timeline::of(const Robot& robot, const Prediction& prediction) {
  Timeline tl;
  tl.start_q_ = user_units(robot, KinematicModel(robot).q());  // power-up: every motor at its zero
  tl.start_tool_ = tool_position(robot.model, model_units(robot, tl.start_q_).data());
  for (const PredictRecord& r : prediction.records) {
    TimelineAction a = action(r.line, r.text, r.reply, r.note);
    a.start_s = r.start_s();
    a.end_s = r.end_s();
    a.q = r.joints;
    a.q_ideal = r.joints_ideal.empty() ? r.joints : r.joints_ideal;
    a.tool = r.tool_quantized;
    a.tool_ideal = r.tool_ideal;
    a.error_mm = r.error_mm;
    a.steps = r.steps;
    a.gripper_percent = r.gripper_percent;
    if (r.reply == kOk && !r.segments.empty()) {
      add_segments(robot, r, a);
      a.straight = true;
      a.line_from = last_tool(tl.actions_, robot, tl.start_q_);
      a.line_to = r.target;
      a.line_error_mm = r.line_error_mm;
    }
    a.path = r.path;
    tl.actions_.push_back(std::move(a));
  }
  tl.duration_ = tl.actions_.empty() ? 0.0 : tl.actions_.back().end_s;
  tl.predicted_ = true;
  return tl;
}

Timeline Timeline::of(const Robot& robot, const Program& program, const std::vector<RunRecord>& records,
                      const std::vector<double>& start_q, const JointTiming& timing) {
  Timeline tl;
  tl.start_q_ = start_q;
  tl.start_tool_ = tool_position(robot.model, model_units(robot, start_q).data());
  std::vector<double> at = model_units(robot, start_q);  // where the last accepted action left the arm
  int grip = -1;
  double clock = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const RunRecord& r = records[i];
    TimelineAction a = action(r.line, r.text, r.reply, r.note);
    a.q = a.q_ideal = r.joints;
    a.tool = a.tool_ideal = r.tool.p;
    a.gripper_percent = r.gripper_percent;
    double s = 0;
    if (r.reply == kOk && !r.via_joints.empty() && r.line_speed > 0) {  // T: along its line at its speed
      s = r.line_length_mm / r.line_speed;
      for (size_t k = 0; k < r.via_joints.size(); ++k) {
        a.via_s.push_back(clock + s * r.via_mm[k] / std::max(r.line_length_mm, 1e-9));
        a.via_q.push_back(r.via_joints[k]);
      }
      a.straight = true;
      a.line_from = tool_position(robot.model, at.data());
      a.line_to = r.target;
      // The tool as the model moves it (each segment straight in joints), 8 points a segment.
      std::vector<double> from = at;
      const Vec3<double> ab = a.line_to - a.line_from;
      for (const auto& via : r.via_joints) {
        const std::vector<double> to = model_units(robot, via);
        for (int k = 1; k <= 8; ++k) {
          const Vec3<double> p = tool_position(robot.model, lerp(from, to, k / 8.0).data());
          a.path.push_back(p);
          const double f = std::clamp(dot(p - a.line_from, ab) / std::max(dot(ab, ab), 1e-12), 0.0, 1.0);
          a.line_error_mm = std::max(a.line_error_mm, norm(p - (a.line_from + f * ab)));
        }
        from = to;
      }
      at = model_units(robot, r.joints);
      grip = r.gripper_percent;
    } else if (r.reply == kOk) {
      const std::vector<double> to = model_units(robot, r.joints);
      s = timing.move_s(robot, at.data(), to.data());
      // as the physics times it: a move, else a gripper action
      if (s == 0 && (r.gripper_percent != grip || is_gripper_statement(program.statements[i])))
        s = timing.gripper_settle_s;
      if (s == 0) s = r.dwell_s;  // D: a wait
      at = to;
      grip = r.gripper_percent;
    }
    a.start_s = clock;
    a.end_s = clock + s;
    clock += s;
    tl.actions_.push_back(std::move(a));
  }
  tl.duration_ = clock;
  return tl;
}

Timeline Timeline::of_program(const Robot& robot, const Program& program, const std::vector<double>& start_q,
                              const JointTiming& timing) {
  if (robot.has_motors) return of(robot, predict_program(robot, program, {}, {}, true));
  return of(robot, program, run_program(robot, program), start_q, timing);
}

TimelinePose Timeline::at(double t) const {
  TimelinePose p;
  p.t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, duration_);
  std::vector<double> prev = start_q_, prev_ideal = start_q_;
  p.q = prev;
  p.q_ideal = prev_ideal;
  for (const TimelineAction& a : actions_) {
    if (a.reply != kOk) {
      if (a.start_s <= p.t) p.line = a.line;
      continue;
    }
    if (p.t >= a.end_s) {  // ended: the arm rests at its pose
      prev = p.q = a.q;
      prev_ideal = p.q_ideal = a.q_ideal;
      p.line = a.line;
      p.steps = a.steps;
      p.error_mm = a.error_mm;
      if (a.gripper_percent >= 0) p.gripper_percent = a.gripper_percent;
      continue;
    }
    if (p.t >= a.start_s) {  // running
      double t0 = a.start_s, t1 = a.end_s;
      std::vector<double> from = prev, to = a.q, from_ideal = prev_ideal, to_ideal = a.q_ideal;
      for (size_t k = 0; k < a.via_s.size(); ++k) {  // a T: within one of its segments
        if (p.t < a.via_s[k]) {
          to = to_ideal = a.via_q[k];
          t1 = a.via_s[k];
          break;
        }
        from = from_ideal = a.via_q[k];
        t0 = a.via_s[k];
      }
      const double f = t1 > t0 ? (p.t - t0) / (t1 - t0) : 1.0;
      p.q = lerp(from, to, f);
      p.q_ideal = lerp(from_ideal, to_ideal, f);
      p.line = a.line;
    }
    break;
  }
  return p;
}

// A path as one flat list, x y z after x y z, to the micrometre (it is drawn, not computed on).
static nlohmann::json path_json(const std::vector<Vec3<double>>& path) {
  nlohmann::json out = nlohmann::json::array();
  for (const Vec3<double>& p : path)
    for (double v : {p.x, p.y, p.z}) out.push_back(std::round(v * 1000) / 1000);
  return out;
}

// A straight line's {from, to, error_mm}.
static nlohmann::json line_json(const TimelineAction& a) {
  nlohmann::json j = nlohmann::json::object();
  j["from"] = nlohmann::json::array({a.line_from.x, a.line_from.y, a.line_from.z});
  j["to"] = nlohmann::json::array({a.line_to.x, a.line_to.y, a.line_to.z});
  j["error_mm"] = a.line_error_mm;
  return j;
}

nlohmann::json timeline_json(const Timeline& tl) {
  using json = nlohmann::json;
  json records = json::array();
  for (const TimelineAction& a : tl.actions()) {
    records.push_back({{"line", a.line},
                       {"command", a.command},
                       {"reply", reply_text(a.reply)},
                       {"code", int(a.reply)},
                       {"error", a.error},
                       {"note", a.note},
                       {"start_s", a.start_s},
                       {"end_s", a.end_s},
                       {"q", a.q},
                       {"q_ideal", a.q_ideal},
                       {"tool", {a.tool.x, a.tool.y, a.tool.z}},
                       {"tool_ideal", {a.tool_ideal.x, a.tool_ideal.y, a.tool_ideal.z}},
                       {"error_mm", a.error_mm},
                       {"steps", a.steps.empty() ? json(nullptr) : json(a.steps)},
                       {"path", path_json(a.path)},
                       {"straight", a.straight ? line_json(a) : json(nullptr)},
                       {"gripper", a.gripper_percent < 0 ? json(nullptr) : json(a.gripper_percent)}});
  }
  json summary = {{"commands", tl.actions().size()}, {"rejected", 0}};
  double worst = 0;
  int rejected = 0;
  for (const TimelineAction& a : tl.actions()) {
    if (a.reply != kOk) ++rejected;
    else worst = std::max(worst, a.error_mm);
  }
  summary["rejected"] = rejected;
  if (tl.predicted()) summary["worst_error_mm"] = worst;
  return {{"start_q", tl.start_q()},
          {"start_tool", json::array({tl.start_tool().x, tl.start_tool().y, tl.start_tool().z})},
          {"duration", tl.duration()},
          {"summary", summary},
          {"records", records}};
}

nlohmann::json timeline_pose_json(const TimelinePose& p) {
  using json = nlohmann::json;
  return {{"t", p.t},
          {"line", p.line},
          {"q", p.q},
          {"q_ideal", p.q_ideal},
          {"steps", p.steps.empty() ? json(nullptr) : json(p.steps)},
          {"error_mm", p.error_mm},
          {"gripper", p.gripper_percent < 0 ? json(nullptr) : json(p.gripper_percent)}};
}

nlohmann::json timeline_samples_json(const Robot& robot, const Timeline& tl, double per_s, size_t max_samples) {
  using json = nlohmann::json;
  std::vector<double> ts{0.0, tl.duration()};
  for (const TimelineAction& a : tl.actions()) {
    if (a.reply != kOk) continue;
    ts.push_back(a.start_s);
    ts.push_back(a.end_s);
    ts.insert(ts.end(), a.via_s.begin(), a.via_s.end());
  }
  const double d = tl.duration();
  const size_t even = d > 0 ? static_cast<size_t>(std::ceil(d * std::max(per_s, 0.0))) : 0;
  const size_t room = max_samples > ts.size() ? max_samples - ts.size() : 0;
  const size_t n = std::min(even, room);
  for (size_t k = 1; k < n; ++k) ts.push_back(d * static_cast<double>(k) / static_cast<double>(n));
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end(), [](double a, double b) { return b - a < 1e-9; }), ts.end());
  const size_t nj = tl.start_q().size();
  json t = json::array(), line = json::array(), q = json::array(), tool = json::array({json::array(), json::array(), json::array()});
  for (size_t j = 0; j < nj; ++j) q.push_back(json::array());
  for (double at_s : ts) {
    const TimelinePose p = tl.at(at_s);
    t.push_back(p.t);
    line.push_back(p.line);
    for (size_t j = 0; j < nj && j < p.q.size(); ++j) q[j].push_back(p.q[j]);
    const Vec3<double> x = tool_position(robot.model, model_units(robot, p.q).data());
    tool[0].push_back(x.x);
    tool[1].push_back(x.y);
    tool[2].push_back(x.z);
  }
  return {{"t", t}, {"line", line}, {"q", q}, {"tool", tool}};
}

}  // namespace articula::host
