// host/lib/program.cpp - reading RoboSim and protocol programs (program.h).
#include "program.h"

#include <articula/protocol.h>

#include "wiring.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace articula::host {

namespace {
std::string problems_text(const std::string& file, const std::vector<ProgramError::Problem>& problems) {
  std::string s;
  for (const ProgramError::Problem& p : problems)
    s += (s.empty() ? "" : "\n") + file + ":" + std::to_string(p.line) + ": " + p.problem;
  return s;
}
}  // namespace

ProgramError::ProgramError(const std::string& file, int line, const std::string& problem, bool other_arm)
    : ProgramError(file, std::vector<Problem>{{line, problem, other_arm}}) {}

ProgramError::ProgramError(const std::string& file, std::vector<Problem> problems)
    : std::runtime_error(problems_text(file, problems)), problems_(std::move(problems)) {
  if (problems_.empty()) problems_.push_back({0, "cannot be read", false});
}

namespace {

struct Line {
  int number;
  std::string text;  // comment and surrounding blanks removed; never empty
};

// The lines that hold something, with `#` comments removed.
std::vector<Line> content_lines(const std::string& text) {
  std::vector<Line> out;
  std::istringstream in(text);
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    s = line_command(s);
    if (!s.empty()) out.push_back({n, s});
  }
  return out;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// One number alone on a line (RoboSim puts every argument on a line of its own).
double number_line(const std::string& file, const Line& l, const std::string& what) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(l.text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != l.text.size() || !std::isfinite(v))
    throw ProgramError(file, l.number, what + ": expected one number, got '" + l.text + "'");
  return v;
}

void check_range(const std::string& file, int line, const std::string& what, double v, double lo, double hi) {
  if (v < lo || v > hi)
    throw ProgramError(file, line, what + " " + number_text(v) + " is outside " + number_text(lo) + " .. " + number_text(hi));
}

}  // namespace

char robosim_letter(Statement::Kind kind) {
  switch (kind) {
    case Statement::Kind::kJoints: return 'm';
    case Statement::Kind::kTarget: return 'a';
    case Statement::Kind::kLinkLengths: return 'l';
    case Statement::Kind::kWeights: return 'w';
    case Statement::Kind::kSpeed: return 's';
    case Statement::Kind::kHand: return 'h';
    case Statement::Kind::kZoom: return 'z';
    case Statement::Kind::kProtocol: break;
  }
  return '?';
}

bool is_gripper_statement(const Statement& st) {
  if (st.kind == Statement::Kind::kHand) return true;
  if (st.kind != Statement::Kind::kProtocol) return false;
  const size_t i = st.text.find_first_not_of(" \t");
  if (i == std::string::npos) return false;
  const char c = char(std::toupper(static_cast<unsigned char>(st.text[i])));
  return c == 'G' || c == 'S';
}

Program::Format detect_format(const std::string& text, const std::string& name) {
  const std::string n = lower(name);
  if (ends_with(n, ".robosim") || ends_with(n, ".file")) return Program::Format::kRoboSim;
  if (ends_with(n, ".arm") || ends_with(n, ".txt")) return Program::Format::kProtocol;
  for (const Line& l : content_lines(text)) {
    const bool single = l.text.size() == 1 && std::isalpha(static_cast<unsigned char>(l.text[0]));
    // Letters that are protocol commands without arguments (H, Z, I) and RoboSim commands
    // at once would be ambiguous alone: only RoboSim's own letters decide for RoboSim.
    if (single && std::string("malwshz").find(char(std::tolower(l.text[0]))) != std::string::npos &&
        std::string("hzi").find(char(std::tolower(l.text[0]))) == std::string::npos)
      return Program::Format::kRoboSim;
    return Program::Format::kProtocol;
  }
  return Program::Format::kProtocol;
}

Program parse_robosim(const std::string& text, const std::string& name, const Robot& robot) {
  Program p;
  p.format = Program::Format::kRoboSim;
  p.source = name;
  const std::vector<Line> lines = content_lines(text);
  const int joints = robot.model.num_joints;
  int adjustable_rows = 0;
  for (const auto& r : robot.length_ranges) adjustable_rows += r.adjustable;

  std::string prev_what;  // the last m, w or l statement's, while its values may still follow
  int prev_count = 0;
  for (size_t i = 0; i < lines.size();) {
    const Line& cmd = lines[i++];
    // a number where a command letter should be, right after an m, w or l: more values than
    // this robot has joints or rows (a program for an arm of another shape)
    if (!prev_what.empty() && !cmd.text.empty() &&
        (std::isdigit(static_cast<unsigned char>(cmd.text[0])) || cmd.text[0] == '-' || cmd.text[0] == '+' || cmd.text[0] == '.'))
      throw ProgramError(name, cmd.number,
                         prev_what + ": " + std::to_string(prev_count) + " values expected, more given", true);
    prev_what.clear();
    if (cmd.text.size() != 1)
      throw ProgramError(name, cmd.number,
                         "expected a command letter alone on its line (m, a, l, w, s, h, z), got '" + cmd.text + "'");
    const char c = char(std::tolower(static_cast<unsigned char>(cmd.text[0])));
    Statement st;
    st.line = cmd.number;
    int count = 0;
    std::string what;
    switch (c) {
      case 'm': st.kind = Statement::Kind::kJoints, count = joints, what = "m (joint value)"; break;
      case 'a': st.kind = Statement::Kind::kTarget, count = 3, what = "a (target coordinate)"; break;
      case 'l': st.kind = Statement::Kind::kLinkLengths, count = adjustable_rows, what = "l (link length)"; break;
      case 'w': st.kind = Statement::Kind::kWeights, count = joints, what = "w (angle weight)"; break;
      case 's': st.kind = Statement::Kind::kSpeed, count = 1, what = "s (speed)"; break;
      case 'h': st.kind = Statement::Kind::kHand, count = 1, what = "h (hand aperture)"; break;
      case 'z': st.kind = Statement::Kind::kZoom, count = 1, what = "z (zoom)"; break;
      default:
        throw ProgramError(name, cmd.number, std::string("unknown command '") + cmd.text + "' (m, a, l, w, s, h, z)");
    }
    if (c == 'l' && count == 0)
      throw ProgramError(name, cmd.number, robot.name + " has no link with an allowed length range (robot file: \"a\" as {\"value\", \"min\", \"max\"})");
    for (int k = 0; k < count; ++k) {
      if (i >= lines.size() || (lines[i].text.size() == 1 && std::isalpha(static_cast<unsigned char>(lines[i].text[0]))))
        throw ProgramError(name, i < lines.size() ? lines[i].number : cmd.number,
                           what + ": " + std::to_string(count) + " values expected, " + std::to_string(k) + " given",
                           c == 'm' || c == 'w' || c == 'l');  // counts this robot's joints or rows
      const Line& l = lines[i++];
      const double v = number_line(name, l, what);
      switch (st.kind) {
        case Statement::Kind::kJoints: {
          const bool angle = robot.model.joints[k].param != kParamD;
          const double lo = robot.model.joints[k].lo, hi = robot.model.joints[k].hi;
          check_range(name, l.number, "joint " + robot.joint_names[k], v, angle ? rad_to_deg(lo) : lo,
                      angle ? rad_to_deg(hi) : hi);
          break;
        }
        case Statement::Kind::kLinkLengths: {
          int seen = -1;
          for (const auto& r : robot.length_ranges)
            if (r.adjustable && ++seen == k) check_range(name, l.number, "link length", v, r.min, r.max);
          break;
        }
        case Statement::Kind::kWeights:
          if (v < 0 || v != std::floor(v))
            throw ProgramError(name, l.number, "w: weights are whole numbers >= 0, got " + number_text(v));
          break;
        case Statement::Kind::kSpeed: check_range(name, l.number, "speed", v, 1, kRoboSimFastest); break;
        case Statement::Kind::kHand: check_range(name, l.number, "hand aperture", v, 0.0, kRoboSimClosedHand); break;
        case Statement::Kind::kZoom: check_range(name, l.number, "zoom", v, 0.1, 3.5); break;
        default: break;
      }
      st.values.push_back(v);
    }
    if (c == 'm' || c == 'w' || c == 'l') prev_what = what, prev_count = count;
    p.statements.push_back(st);
  }
  return p;
}

Program parse_protocol_program(const std::string& text, const std::string& name, const Robot& robot) {
  Program p;
  p.format = Program::Format::kProtocol;
  p.source = name;
  const int joints = robot.has_motors ? robot.actuation.num_motors : robot.model.num_joints;
  std::vector<ProgramError::Problem> problems;  // every line that cannot be read
  std::istringstream in(text);
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    if (!s.empty() && s.back() == '\r') s.pop_back();
    const std::string t = trim_blanks(s);
    if (t.empty() || t[0] == '#') continue;
    if (t.size() > kMaxLineLength) {
      problems.push_back({n, "line longer than " + std::to_string(kMaxLineLength) + " bytes (error:7)", false});
      continue;
    }
    Command cmd;
    const Status st = is_stop_line(t) ? kOk : parse_line(cmd, t.data(), uint8_t(t.size()), uint8_t(joints));
    if (st != kOk) {
      const std::string why = explain_line_error(t, st, robot);
      problems.push_back({n,
                          "'" + t + "': error:" + std::to_string(int(st)) + " " + status_text(st) +
                              (why.empty() ? "" : ": " + why),
                          st == kMissingArgument || st == kExtraArgument || st == kBadJoint});
      continue;
    }
    Statement statement;
    statement.kind = Statement::Kind::kProtocol;
    statement.text = t;
    statement.line = n;
    p.statements.push_back(statement);
  }
  if (!problems.empty()) throw ProgramError(name, std::move(problems));
  return p;
}

Program load_program(const std::string& path, const Robot& robot) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ProgramError(path, 0, "cannot read the file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_program(ss.str(), path, robot);
}

Program parse_program(const std::string& text, const std::string& name, const Robot& robot) {
  return detect_format(text, name) == Program::Format::kRoboSim ? parse_robosim(text, name, robot)
                                                                 : parse_protocol_program(text, name, robot);
}

bool is_stop_line(const std::string& text) { return trim_blanks(text) == "!"; }

Status parse_protocol_line(Command& cmd, const std::string& text, int num_joints) {
  if (text.size() > 255) return kLineTooLong;
  return parse_line(cmd, text.data(), uint8_t(text.size()), uint8_t(num_joints));
}

std::string number_text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

std::string trim_blanks(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

void append_note(std::string& notes, const std::string& note) {
  if (note.empty()) return;
  notes += (notes.empty() ? "" : "; ") + note;
}

namespace {

// The words of a protocol line without its comment.
std::vector<std::string> line_words(const std::string& line) {
  std::istringstream in(line_command(line));
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// A number as the codec reads one (docs/protocol.md, "Numbers"): for naming the word that is not.
bool looks_like_number(const std::string& w) {
  size_t i = (!w.empty() && (w[0] == '+' || w[0] == '-')) ? 1 : 0;
  bool digits = false, point = false;
  for (; i < w.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(w[i]))) digits = true;
    else if (w[i] == '.' && !point) point = true;
    else return false;
  }
  return digits;
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out;
}

}  // namespace

std::string explain_line_error(const std::string& line, Status status, const Robot& robot) {
  const std::vector<std::string> words = line_words(line);
  if (words.empty()) return "";
  const char c = char(std::toupper(static_cast<unsigned char>(words[0][0])));
  const int actuators = robot.has_motors ? robot.actuation.num_motors : robot.model.num_joints;
  const std::vector<std::string>& names = robot.has_motors ? robot.motor_names : robot.joint_names;
  const int given = int(words.size()) - 1;
  std::string takes;
  switch (c) {
    case 'L': takes = "L takes 2 values: a joint number (0 to " + std::to_string(actuators - 1) + ") and an angle in degrees"; break;
    case 'M': takes = "M takes " + std::to_string(actuators) + " values, one angle in degrees for each " +
                      (robot.has_motors ? "motor" : "joint") + " (" + join_names(names) + ")"; break;
    case 'P': takes = "P takes 3 values: x, y and z of the point, in mm"; break;
    case 'G': takes = "G takes 1 value: how far open, 0 (closed) to 100 (open) %"; break;
    case 'S': takes = "S takes 1 value: 1 closes the gripper, 0 opens it"; break;
    case 'D': takes = "D takes 1 value: the seconds to wait, 0 to " + std::to_string(kMaxDwellMs / 1000); break;
    case 'O': takes = "O takes 2 values: a pin (D0..D13 are 0..13, A0..A5 14..19) and its level, 1 or 0"; break;
    case 'W': takes = "W takes 3 values: a pin (D0..D13 are 0..13, A0..A5 14..19), the level to wait for (1 or 0) and the seconds at most, 0 to " +
                      std::to_string(kMaxDwellMs / 1000); break;
    default: break;
  }
  switch (status) {
    case kMissingArgument:
    case kExtraArgument:
      return takes.empty() ? "" : takes + "; this line gives " + std::to_string(given);
    case kBadNumber:
      for (size_t i = 1; i < words.size(); ++i)
        if (!looks_like_number(words[i]) && words[i].find('=') == std::string::npos)
          return "'" + words[i] + "' is not a number: write digits, like 10 or -2.5";
      return "";
    case kUnknownCommand:
      return "'" + words[0] + "' is not a command: a line starts with L, M, P, T, G, S, D, O, W, H, Z, I or $ (docs/protocol.md)";
    case kBadJoint:
      return "the joints are numbered 0 to " + std::to_string(actuators - 1) + " (" + join_names(names) + ")";
    case kValueOutOfRange:
      return takes;
    case kPinUnavailable:
      if (!robot.has_motors) return "";
      return std::string("O and W take a pin this arm's board leaves free: ") + io_pins_free_text(robot) +
             " (D0..D13 are 0..13, A0..A5 14..19)";
    default:
      return "";
  }
}

std::vector<Comment> program_comments(const std::string& text) {
  std::vector<Comment> out;
  std::istringstream in(text);
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    const size_t hash = comment_start(s.data(), s.size());
    if (hash == s.size()) continue;
    std::string body = s.substr(hash + 1);
    if (!body.empty() && body.back() == '\r') body.pop_back();
    out.push_back({n, trim_blanks(body), trim_blanks(s.substr(0, hash)).empty()});
  }
  return out;
}

std::string line_command(const std::string& line) {
  return trim_blanks(line.substr(0, comment_start(line.data(), line.size())));
}

std::string command_text(const std::string& line) {
  const std::string s = line_command(line);
  return s.empty() ? line : s;
}

ProgramFit program_fit(const std::string& text, const std::string& name, const Robot& robot) {
  ProgramFit f;
  try {
    parse_program(text, name, robot);
  } catch (const ProgramError& e) {
    f.fits = false;
    f.other_arm = e.other_arm();
    f.line = e.line();
    f.problem = e.what();  // (every line that cannot be read)
  }
  return f;
}

nlohmann::json program_fit_json(const ProgramFit& fit) {
  return {{"fits", fit.fits}, {"other_arm", fit.other_arm}, {"line", fit.line}, {"problem", fit.problem}};
}

}  // namespace articula::host
