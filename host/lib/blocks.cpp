// host/lib/blocks.cpp - blocks to programs and back, and the protocol line formatter
// (blocks.h).
#include "blocks.h"

#include <articula/protocol.h>
#include <articula/settings.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "draw.h"
#include "program.h"
#include "records_json.h"
#include "robot_view.h"
#include "wiring.h"

namespace articula::host {

using nlohmann::json;

namespace {

constexpr size_t kCommentBytes = 60;  // a protocol line holds 64 bytes, "# " and the comment included
const char* const kHeader = "# made from blocks in Articula Studio";

// Line ends inside a block's text become blanks (a program line is one line).
std::string one_line(const std::string& s) {
  std::string out;
  bool in_break = false;
  for (char c : s) {
    const bool brk = c == '\r' || c == '\n';
    if (brk && !in_break) out += ' ';
    if (!brk) out += c;
    in_break = brk;
  }
  return out;
}

std::string trim_end(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.pop_back();
  return s;
}

// Comment lines of at most kCommentBytes bytes each, split between characters (UTF-8).
std::vector<std::string> comment_lines(const std::string& text) {
  const std::string s = one_line(text);
  std::vector<std::string> out;
  std::string cur;
  for (size_t i = 0; i < s.size();) {
    size_t n = 1;
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0xF0) n = 4;
    else if (c >= 0xE0) n = 3;
    else if (c >= 0xC0) n = 2;
    n = std::min(n, s.size() - i);
    if (cur.size() + n > kCommentBytes) {
      out.push_back(cur);
      cur.clear();
    }
    cur.append(s, i, n);
    i += n;
  }
  out.push_back(cur);
  for (std::string& l : out) l = trim_end("# " + l);
  return out;
}

std::vector<double> numbers_of(const json& v, const std::string& block, const char* what);

struct BlockError : std::runtime_error {
  BlockError(std::string b, const std::string& m) : std::runtime_error(m), block(std::move(b)) {}
  std::string block;
};

double number_of(const json& op, const char* key, const std::string& block) {
  const auto it = op.find(key);
  if (it == op.end() || !it->is_number()) throw BlockError(block, std::string("'") + key + "' must be a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) throw BlockError(block, std::string("'") + key + "' must be a finite number");
  return v;
}

std::vector<double> numbers_of(const json& v, const std::string& block, const char* what) {
  if (!v.is_array()) throw BlockError(block, std::string("'") + what + "' must be a list of numbers");
  std::vector<double> out;
  for (const json& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      throw BlockError(block, std::string("'") + what + "' must hold finite numbers");
    out.push_back(x.get<double>());
  }
  return out;
}

std::string text_of(const json& op, const char* key) {
  const auto it = op.find(key);
  return it != op.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string joined(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i) out += (i ? sep : "") + parts[i];
  return out;
}

// The compiler's state: the pose the actions have reached, and what they wrote.
class Compiler {
 public:
  Compiler(const Robot& r, const InverseKinematics& ik) : r_(r), ik_(ik), joints_(joints_json(r)) {
    if (r.has_motors) motors_ = motors_json(r);
    q_ = power_up_pose(r);
    limits_ = joint_limits(r);
    proto_.push_back(kHeader);
    lines_.push_back("");
    rs_.push_back(kHeader);
  }

  void action(const json& o) {
    const std::string b = text_of(o, "block");
    const std::string op = text_of(o, "op");
    const int n = r_.model.num_joints;
    if (op == "joint_to" || op == "joint_by") {
      const double j = number_of(o, "joint", b);
      if (j != std::floor(j) || j < 0 || j >= n)
        throw BlockError(b, r_.name + " has no joint " + protocol_number(j + 1) + ": choose one of " +
                                joined(r_.joint_names, ", "));
      std::vector<double> t = q_;
      const double v = number_of(o, "value", b);
      t[size_t(j)] = op == "joint_to" ? v : q_[size_t(j)] + v;
      move(b, t);
    } else if (op == "joints") {
      const std::vector<double> v = numbers_of(o.value("values", json()), b, "values");
      if (int(v.size()) != n)
        throw BlockError(b, r_.name + " has " + std::to_string(n) + " joints (" + joined(r_.joint_names, ", ") +
                                "): this block gives " + std::to_string(v.size()) + " values");
      move(b, v);
    } else if (op == "home") {
      move(b, home_pose(r_));
    } else if (op == "tool_to") {
      const std::vector<double> p = point(o, b);
      emit(b, {protocol_line(r_, 'P', p)});
      rs_.push_back("a");
      for (double x : p) rs_.push_back(protocol_number(x));
      reach(b, p);
    } else if (op == "line_to") {
      // The line itself is checked where the arm checks it: the prediction refuses a line it
      // cannot follow, on this block's line, and says where.
      const std::vector<double> p = point(o, b);
      const double speed = number_of(o, "speed", b);
      if (!(speed > 0 && speed <= kMaxLineSpeed / 1000.0))
        problem(b, "the speed is from more than 0 to 1000 mm/s, not " + protocol_number(speed) + " mm/s");
      emit(b, {protocol_line(r_, 'T', {p[0], p[1], p[2], speed})});
      rs_.push_back("# (a straight line: RoboSim moves to its end)");
      rs_.push_back("a");
      for (double x : p) rs_.push_back(protocol_number(x));
      reach(b, p);
    } else if (op == "gripper") {
      const double pct = number_of(o, "percent", b);
      if (!r_.gripper.present) problem(b, r_.name + " has no gripper");
      if (pct < 0 || pct > 100) problem(b, "the gripper opens from 0 % to 100 %, not " + protocol_number(pct) + " %");
      emit(b, {protocol_line(r_, 'G', {pct})});
      rs_.push_back("h");
      rs_.push_back(protocol_number((100 - pct) / 100 * kRoboSimClosedHand));
    } else if (op == "speed") {
      const double pct = number_of(o, "percent", b);
      if (pct <= 0 || pct > 100) throw BlockError(b, "the speed is from 1 % to 100 %, not " + protocol_number(pct) + " %");
      // $0 at 100 %: the firmware's default top rate (the settings table)
      const double top = setting_range(kSetMaxRate, uint8_t(std::max(1, int(r_.actuation.num_motors)))).fallback;
      emit(b, {protocol_line(r_, '$', {double(kSetMaxRate), std::max(1.0, std::round(top * pct / 100))})});
      rs_.push_back("s");
      rs_.push_back(std::to_string(int(std::max(1.0, std::round(kRoboSimFastest * pct / 100)))));
    } else if (op == "wait") {
      const double s = number_of(o, "seconds", b);
      // its range is the parser's: a wait beyond it is refused on its block by the prediction
      emit(b, {"D " + protocol_number(s)});
      rs_.push_back("# (a wait of " + protocol_number(s) + " s: RoboSim has none)");
    } else if (op == "comment") {
      const std::vector<std::string> c = comment_lines(text_of(o, "text"));
      emit(b, c);
      rs_.insert(rs_.end(), c.begin(), c.end());
    } else if (op == "pen") {
      pen_.pen_mm = number_of(o, "pen", b);
      pen_.paper_z = number_of(o, "z", b);
      const std::string problem = pen_value_problem(kPenFields[kPenLength], pen_.pen_mm);
      if (!problem.empty()) throw BlockError(b, "the pen's length: " + problem);
      pen_set_ = true;
      const std::vector<std::string> c = comment_lines("the pen " + protocol_number(pen_.pen_mm) + " mm below the tool point, the paper at z " +
                                                       protocol_number(pen_.paper_z) + " mm");
      emit(b, c);
      rs_.insert(rs_.end(), c.begin(), c.end());
    } else if (op == "pen_down" || op == "pen_up" || op == "pen_to") {
      need_pen(b);
      const Vec3<double> at = tool();
      double x = at.x, y = at.y;
      if (op == "pen_to") {
        const std::vector<double> xy = numbers_of(o.value("xy", json()), b, "xy");
        if (xy.size() != 2) throw BlockError(b, "a point on the paper is x and y in mm");
        x = xy[0], y = xy[1];
      } else {
        pen_down_ = op == "pen_down";
      }
      line(b, {x, y, pen_.paper_z + pen_.pen_mm + (pen_down_ ? 0 : pen_.lift_mm)}, pen_down_ ? pen_.speed : pen_.travel_speed);
    } else if (op == "write" || op == "shape") {
      need_pen(b);
      DrawRequest req;
      (op == "write" ? req.text : req.shape) = text_of(o, op == "write" ? "text" : "shape");
      if (op == "write" && req.text.empty()) throw BlockError(b, "type the text to write");
      req.width_mm = number_of(o, "width", b);
      const std::vector<double> xy = numbers_of(o.value("at", json()), b, "at");
      if (xy.size() != 2) throw BlockError(b, "a place on the paper is x and y in mm");
      req.x = xy[0], req.y = xy[1];
      req.pen = pen_;
      Drawing d;
      try {
        d = make_drawing(r_, ik_, req);
      } catch (const std::invalid_argument& e) {
        throw BlockError(b, e.what());
      }
      if (!d.reach.fits) return problem(b, d.what + ": " + d.reach.advice);
      for (const PenMove& m : pen_moves(d.strokes, pen_)) {  // the drawing's own order (draw.h)
        const std::vector<double> at{m.x, m.y, m.z};
        if (m.reach) {  // from wherever the arm is: a move, not a line
          emit(b, {protocol_line(r_, 'P', at)});
          rs_.push_back("a");
          for (double x : at) rs_.push_back(protocol_number(x));
          reach(b, at);
        } else {
          line(b, at, m.speed);
        }
      }
      pen_down_ = false;
    } else if (op == "output" || op == "wait_input") {
      // A signal to another arm or a device (protocol.h's O and W): a header pin the arm's
      // drive leaves free (wiring.h), high or low; a wait at most 600 s.
      const double pin = number_of(o, "pin", b), level = number_of(o, "level", b);
      std::vector<double> v{pin, level};
      const uint32_t free = io_pins_free(r_);
      const bool whole = pin == std::floor(pin) && pin >= 0 && pin < 32;
      if (!whole || !(free & (uint32_t(1) << int(pin))))
        problem(b, r_.name + "'s board leaves " + io_pins_free_text(r_) + " for signals, not " +
                       (whole ? header_pin_name(int(pin)) : "pin " + protocol_number(pin)));
      if (level != 0 && level != 1) problem(b, "a pin is high (1) or low (0), not " + protocol_number(level));
      if (op == "wait_input") {
        const double s = number_of(o, "seconds", b);
        if (s < 0 || s > 600) problem(b, "a wait for a signal lasts 0 to 600 seconds, not " + protocol_number(s));
        v.push_back(s);
      }
      const std::string l = protocol_line(r_, op == "output" ? 'O' : 'W', v);
      emit(b, {l});
      rs_.push_back("# (a signal, no RoboSim) " + l);
    } else if (op == "raw") {
      const std::string t = one_line(text_of(o, "text"));
      emit(b, {t});
      rs_.push_back("# (a protocol line, no RoboSim) " + t);
    } else {
      throw BlockError(b, "no action '" + op + "'");
    }
  }

  json result() const {
    std::string text, robosim;
    for (const std::string& l : proto_) text += l + "\n";
    for (const std::string& l : rs_) robosim += l + "\n";
    return json{{"text", text}, {"robosim", robosim}, {"lines", lines_}, {"problems", problems_}};
  }

 private:
  std::string unit(int j) const { return joints_[size_t(j)].value("unit", "deg"); }
  std::string show(int j, double v) const {
    return protocol_number(v) + (unit(j) == "mm" ? " mm" : "\xC2\xB0");
  }
  void emit(const std::string& block, const std::vector<std::string>& ls) {
    for (const std::string& l : ls) {
      proto_.push_back(l);
      lines_.push_back(block);
    }
  }
  void problem(const std::string& block, const std::string& message) {
    problems_.push_back({{"block", block}, {"message", message}});
  }
  std::vector<double> point(const json& o, const std::string& b) const {
    std::vector<double> p = numbers_of(o.value("xyz", json()), b, "xyz");
    if (p.size() != 3) throw BlockError(b, "a point is x, y and z in mm");
    return p;
  }

  // The pen's blocks need its length and the paper's height first.
  void need_pen(const std::string& b) const {
    if (!pen_set_) throw BlockError(b, "say first where the pen and the paper are: the block 'the pen is ... mm long, the paper at z ...'");
  }
  Vec3<double> tool() const {
    const std::vector<double> q = joints_in(r_, q_, "pose");
    return tool_position(r_.model, q.data());
  }
  // A straight line (T) to p at speed mm/s, the pose following it.
  void line(const std::string& b, const std::vector<double>& p, double speed) {
    emit(b, {protocol_line(r_, 'T', {p[0], p[1], p[2], speed})});
    rs_.push_back("a");
    for (double x : p) rs_.push_back(protocol_number(x));
    reach(b, p);
  }

  // Joint values to a move: the problems the arm would refuse it for, in the student's
  // units; the pose follows only when the move is allowed.
  void move(const std::string& b, const std::vector<double>& target) {
    bool ok = true;
    for (size_t j = 0; j < target.size(); ++j) {
      const double lo = limits_[j][0], hi = limits_[j][1], v = target[j];
      if (v < lo - 1e-9 || v > hi + 1e-9) {
        ok = false;
        problem(b, r_.joint_names[j] + " at " + show(int(j), v) + " is beyond its range, " + show(int(j), lo) + " to " +
                       show(int(j), hi));
      }
    }
    std::vector<double> values = target;
    if (r_.has_motors) {
      values = motors_from_joints(r_, joints_in(r_, target, "joints"));
      for (size_t k = 0; k < values.size(); ++k) {
        const double m = values[k], lo = motors_[k].at("min").get<double>(), hi = motors_[k].at("max").get<double>();
        if (ok && (m < lo - 1e-6 || m > hi + 1e-6)) {
          ok = false;
          std::vector<std::string> pose;
          for (size_t j = 0; j < target.size(); ++j) pose.push_back(r_.joint_names[j] + " " + show(int(j), target[j]));
          problem(b, "this pose needs the " + motors_[k].at("name").get<std::string>() + " motor at " + protocol_number(m) +
                         "\xC2\xB0, beyond its range " + protocol_number(lo) + "\xC2\xB0 to " + protocol_number(hi) +
                         "\xC2\xB0 (the joints: " + joined(pose, ", ") + ")");
        }
      }
    }
    emit(b, {protocol_line(r_, 'M', values)});
    rs_.push_back("m");
    for (double v : target) rs_.push_back(protocol_number(v));
    if (ok) q_ = target;
  }

  // The tool to a point (P, and T's end): the pose follows when the IK reaches it.
  void reach(const std::string& b, const std::vector<double>& xyz) {
    IkResult res;
    try {
      res = ik_.solve(ik_target(xyz.data(), 3), joints_in(r_, q_, "start"), ik_options("auto", nullptr, 0.01, 0, 1));
    } catch (const std::invalid_argument& e) {
      throw BlockError(b, e.what());
    }
    if (res.status == IkStatus::kReached) {
      q_ = joints_out(r_, res.q.data());
    } else {
      problem(b, "the tool cannot reach (" + protocol_number(xyz[0]) + ", " + protocol_number(xyz[1]) + ", " +
                     protocol_number(xyz[2]) + ") mm: " + ik_miss_words(r_, res));
    }
  }

  const Robot& r_;
  const InverseKinematics& ik_;
  json joints_, motors_;
  std::vector<std::array<double, 2>> limits_;
  std::vector<double> q_;
  std::vector<std::string> proto_, lines_, rs_;
  json problems_ = json::array();
  PenSettings pen_;  // the pen's blocks: its length, the paper's height (lift and speeds: draw.h's)
  bool pen_set_ = false, pen_down_ = false;
};

}  // namespace

std::string protocol_number(double v, bool every_decimal) {
  const double t = std::round(v * 1000);
  if (!std::isfinite(t) || std::fabs(t) > 2e9) return number_text(v);
  struct Sink {
    std::string s;
    void put(char c) { s.push_back(c); }
  } out;
  detail::write_fixed(out, t == 0 ? 0 : int32_t(t), 3);  // (no "-0.000")
  if (!every_decimal) {
    while (out.s.back() == '0') out.s.pop_back();
    if (out.s.back() == '.') out.s.pop_back();
  }
  return out.s;
}

std::string protocol_line(const Robot& robot, char word, const std::vector<double>& values, bool every_decimal) {
  const int actuators = robot.has_motors ? robot.actuation.num_motors : robot.model.num_joints;
  const bool any = !values.empty();
  for (const CommandSpec& spec : kCommandTable) {
    if (spec.word != word || (word == '$' && (spec.args[0] != '\0') != any)) continue;
    std::string kinds;
    for (const char* k = spec.args; *k; ++k) {
      if (k[1] == '*') {
        kinds.append(size_t(actuators), *k);
        ++k;
      } else {
        kinds += *k == 's' ? std::string("jn") : std::string(1, *k);
      }
    }
    if (kinds.find('t') != std::string::npos)
      throw std::invalid_argument(std::string(1, word) + " takes text, not numbers");
    if (values.size() != kinds.size())
      throw std::invalid_argument(std::string(1, word) + " takes " + std::to_string(kinds.size()) + " values on " +
                                  robot.name + ", not " + std::to_string(values.size()));
    std::string line(1, word);
    for (size_t i = 0; i < values.size(); ++i) {
      const double v = values[i];
      if (!std::isfinite(v) || std::fabs(v) > 1e6)
        throw std::invalid_argument(std::string(1, word) + ": value " + std::to_string(i + 1) +
                                    " must be a finite number within +-1,000,000");
      if (!in_thousandths(kinds[i]) && v != std::floor(v))
        throw std::invalid_argument(std::string(1, word) + ": value " + std::to_string(i + 1) + " must be whole");
      const std::string text = protocol_number(v, every_decimal && in_thousandths(kinds[i]));
      if (word == '$') line += i == 0 ? text : "=" + text;
      else line += " " + text;
    }
    return line;
  }
  throw std::invalid_argument(std::string("the protocol has no command '") + word + "'");
}

std::string move_line(const Robot& robot, const std::vector<double>& q) {
  return protocol_line(robot, 'M', robot.has_motors ? motors_from_joints(robot, joints_in(robot, q, "q")) : q);
}

json blocks_program_json(const Robot& robot, const InverseKinematics& ik, const json& ops) {
  if (!ops.is_array()) throw std::invalid_argument("'ops' must be a list of actions");
  Compiler c(robot, ik);
  for (const json& o : ops) {
    if (!o.is_object()) throw std::invalid_argument("an action is an object with an 'op'");
    try {
      c.action(o);
    } catch (const BlockError& e) {
      return json{{"error", {{"block", e.block}, {"message", e.what()}}}};
    } catch (const std::invalid_argument& e) {
      return json{{"error", {{"block", text_of(o, "block")}, {"message", e.what()}}}};
    }
  }
  return c.result();
}

json program_actions_json(const Robot& robot, const std::string& text, const std::string& name) {
  const Program program = parse_program(text, name, robot);
  const json parsed = program_json(robot, program, text);
  std::vector<std::pair<double, json>> ops;
  for (const Comment& c : program_comments(text))
    ops.emplace_back(c.line - (c.whole_line ? 0 : 0.5), json{{"op", "comment"}, {"text", c.text}});
  for (const json& st : parsed.at("statements")) {
    json op;
    const std::string kind = st.at("kind");
    if (kind == "protocol") {
      const std::string cmd = st.value("command", "");
      const std::vector<double> a = st.at("args").get<std::vector<double>>();
      if (cmd == "M") op = {{"op", "joints"}, {"values", robot.has_motors ? joints_from_motors(robot, a) : a}};
      else if (cmd == "P") op = {{"op", "tool_to"}, {"xyz", a}};
      else if (cmd == "T") op = {{"op", "line_to"}, {"xyz", {a[0], a[1], a[2]}}, {"speed", a[3]}};
      else if (cmd == "G") op = {{"op", "gripper"}, {"percent", a[0]}};
      else if (cmd == "S") op = {{"op", "gripper"}, {"percent", a[0] != 0 ? 0 : 100}};
      else if (cmd == "D") op = {{"op", "wait"}, {"seconds", a[0]}};
      else if (cmd == "O") op = {{"op", "output"}, {"pin", a[0]}, {"level", a[1]}};
      else if (cmd == "W") op = {{"op", "wait_input"}, {"pin", a[0]}, {"level", a[1]}, {"seconds", a[2]}};
      else op = {{"op", "raw"}, {"text", st.at("text")}};
    } else {
      const std::vector<double> v = st.at("values").get<std::vector<double>>();
      if (kind == "m") op = {{"op", "joints"}, {"values", v}};
      else if (kind == "a") op = {{"op", "tool_to"}, {"xyz", {v[0], v[1], v[2]}}};
      else if (kind == "h") op = {{"op", "gripper"}, {"percent", (kRoboSimClosedHand - v[0]) / kRoboSimClosedHand * 100}};
      else if (kind == "s") op = {{"op", "speed"}, {"percent", v[0] / kRoboSimFastest * 100}};
      else {
        std::string t = kind;
        for (double x : v) t += " " + protocol_number(x);
        op = {{"op", "raw"}, {"text", t}};
      }
    }
    ops.emplace_back(st.at("line").get<double>(), op);
  }
  std::stable_sort(ops.begin(), ops.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  json out = json::array();
  for (auto& o : ops) out.push_back(std::move(o.second));
  return json{{"ops", out}, {"format", program.format == Program::Format::kRoboSim ? "robosim" : "protocol"}};
}

namespace {
double round_to(double v, double step) { return std::round(v / step) * step + 0.0; }
}  // namespace

json example_places_json(const Robot& robot, const InverseKinematics& ik) {
  const std::vector<double> start = ik_start(robot, nullptr);
  HostFrames f;
  forward_kinematics(f, robot.model, start.data());
  const Vec3<double> home = f.T_base_tool.p;
  const double reach = ik.reach_bound(), step = round_to(std::max(10.0, 0.1 * reach), 10);
  IkOptions opt;
  opt.position_tolerance_mm = 0.01;
  auto reaches = [&](const Vec3<double>& p) { return ik.solve(IkTarget::at(p), start, opt).reached(); };
  auto rounded = [&](const Vec3<double>& p, double to) {
    return make_vec3(round_to(p.x, to), round_to(p.y, to), round_to(p.z, to));
  };
  // the tool: below the home pose's point (where a lesson's objects are), else at it
  Vec3<double> tool = rounded(home, 1);
  const Vec3<double> below = rounded(home - make_vec3(0.0, 0.0, 1.5 * step), 10), at_home = rounded(home, 10);
  for (const Vec3<double>& c : {below, at_home})
    if (reaches(c)) {
      tool = c;
      break;
    }
  // a straight line from there: out, down, in or up, every point of it reached
  Vec3<double> line_to = tool;
  const Vec3<double> ways[] = {make_vec3(step, 0.0, 0.0), make_vec3(0.0, 0.0, -step), make_vec3(-step, 0.0, 0.0),
                               make_vec3(0.0, 0.0, step)};
  for (const Vec3<double>& d : ways) {
    bool all = true;
    for (int k = 1; k <= 8 && all; ++k) all = reaches(tool + (k / 8.0) * d);
    if (all) {
      line_to = tool + d;
      break;
    }
  }
  // a pen and a place where it draws a square: the MK2's (a 120 mm pen, 40 mm at (250, 0)) if
  // they fit, else a pen about half the home point's height, the square below it or at about
  // half the reach
  PenSettings pen;
  const std::vector<Stroke> square = shape_strokes("square");
  const double horizontal = std::hypot(home.x, home.y);
  const double width = std::min(40.0, std::max(10.0, round_to(0.12 * reach, 10)));
  struct Try {
    double pen, x;
  };
  std::vector<Try> tries = {{120, 250}};
  for (double share : {0.5, 0.6, 0.4, 0.7, 0.3})
    for (double x : {horizontal, horizontal + step, horizontal - step, 0.6 * reach, 0.5 * reach, 0.7 * reach})
      tries.push_back({std::max(10.0, round_to(share * home.z, 10)), round_to(x, 10)});
  Try found = tries.front();
  bool fits = false;
  for (const Try& t : tries) {
    if (t.x - width / 2 <= 0) continue;
    pen.pen_mm = t.pen;
    if (reaches_all(robot, ik, place_strokes(square, width, t.x, 0), pen)) {
      found = t, fits = true;
      break;
    }
  }
  return {{"tool", {tool.x, tool.y, tool.z}},
          {"line_to", {line_to.x, line_to.y, line_to.z}},
          {"pen", found.pen},
          {"paper_z", 0},
          {"draw_at", {found.x, 0}},
          {"draw_width", fits ? width : 40.0},
          {"fits", fits}};
}

}  // namespace articula::host
