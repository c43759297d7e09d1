// host/lib/robot_file.cpp - reads a robot file (format: robots/README.md) into a Robot.
//
// Two stages. A SAX handler builds the JSON document and knows, at every value, its JSON
// pointer: so a duplicated key or a number too large for a double (1e999) is reported at
// its path, and a syntax error at its line and column. Then Loader walks the document in
// the order the README describes, checking every field, and fills in the core's Model and
// Actuation; the core's own validate() functions have the last word.
#include "robot_file.h"

#include "board.h"
#include "wiring.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cctype>
#include <utility>

namespace articula::host {

RobotFileError::RobotFileError(const std::string& file, const std::string& json_path, const std::string& problem)
    : std::runtime_error(file + ": " + (json_path.empty() ? std::string() : json_path + ": ") + problem),
      file_(file),
      json_path_(json_path),
      problem_(problem) {}

const std::map<std::string, std::vector<std::string>>& robot_file_fields() {
  static const std::map<std::string, std::vector<std::string>> fields = {
      {"robot", {"$schema", "name", "description", "dh", "tool", "board", "motors", "coupling", "home", "links", "gripper", "io"}},
      {"dh_row", {"a", "alpha", "d", "theta"}},
      {"length", {"value", "min", "max"}},
      {"joint", {"joint", "min", "max"}},
      {"linked", {"linked", "offset"}},
      {"tool", {"xyz", "rpy"}},
      {"motor", {"name", "steps_per_rev", "microsteps", "gear", "direction", "zero", "min", "max", "torque", "driver"}},
      {"driver", {"kind", "chip", "enable", "pin", "pulse", "at", "speed", "accel", "deadband", "top_speed"}},
      {"torque", {"pull_out", "rotor_inertia"}},
      {"link", {"frame", "shapes"}},
      {"shape", {"type", "size", "mesh", "xyz", "rpy", "mass", "density"}},
      {"io_pin", {"name", "pin", "mode"}},
      {"gripper", {"max_opening", "finger_length", "finger_thickness", "finger_height", "servo_open", "servo_closed"}},
  };
  return fields;
}

namespace {

using json = nlohmann::json;

constexpr double kDefaultDensity = 1240.0;  // kg/m^3, PLA

// ---- small helpers ----

// One JSON pointer reference token (RFC 6901: "~" -> "~0", "/" -> "~1").
std::string escape(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

std::string child(const std::string& path, const std::string& key) { return path + "/" + escape(key); }
std::string child(const std::string& path, std::size_t index) { return path + "/" + std::to_string(index); }

std::string num(double v) { return file_number(v); }

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out;
}

// "an object", "a string (\"90\")": what a value is, for "expected X, got Y".
std::string kind_of(const json& j) {
  std::string kind;
  switch (j.type()) {
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::null: return "null";
    case json::value_t::string: kind = "a string"; break;
    case json::value_t::boolean: kind = "a boolean"; break;
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: kind = "a number"; break;
    default: return "a value of another kind";
  }
  const std::string text = j.dump();
  return text.size() <= 40 ? kind + " (" + text + ")" : kind;
}

// 1-based line and column of the byte at 0-based offset `pos`.
std::pair<std::size_t, std::size_t> line_column(const std::string& text, std::size_t pos) {
  if (pos > text.size()) pos = text.size();
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < pos; ++i)
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  return {line, pos - line_start + 1};
}

// ---- stage 1: text to document ----

// nlohmann's SAX interface, building the document the way its own DOM parser does, and
// keeping the JSON pointer of the value being read.
class DocumentBuilder {
 public:
  DocumentBuilder(const std::string& file, const std::string& text) : file_(file), text_(text) {}

  json root;

  bool null() { return put(json(nullptr)); }
  bool boolean(bool b) { return put(json(b)); }
  bool number_integer(json::number_integer_t v) { return put(json(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return put(json(v)); }
  bool number_float(json::number_float_t v, const json::string_t&) { return put(json(v)); }
  bool string(json::string_t& s) { return put(json(s)); }
  bool binary(json::binary_t& b) { return put(json(b)); }  // never for JSON text
  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(json::string_t& k) {
    Level& top = stack_.back();
    if (top.node->contains(k))
      throw RobotFileError(file_, child(top.path, k), "duplicate field " + in_quotes(k) + " (each field may appear once)");
    top.key = k;
    return true;
  }

  bool parse_error(std::size_t byte, const std::string& last_token, const json::exception& e) {
    if (e.id == 406)  // out_of_range.406: a number too large for a double
      throw RobotFileError(file_, next_path(), "not a finite number (" + last_token + ")");
    // nlohmann's byte count is 1-based and points at the last character read.
    const auto [line, column] = line_column(text_, byte > 0 ? byte - 1 : 0);
    std::string detail = e.what();
    const std::size_t at = detail.find("column ");
    if (at != std::string::npos) {
      const std::size_t colon = detail.find(": ", at);
      if (colon != std::string::npos) detail = detail.substr(colon + 2);
    }
    const std::string prefix = "syntax error ";
    if (detail.compare(0, prefix.size(), prefix) == 0) detail = detail.substr(prefix.size());
    throw RobotFileError(file_, "", "JSON syntax error at line " + std::to_string(line) + ", column " +
                                        std::to_string(column) + ": " + detail);
  }

 private:
  struct Level {
    json* node;        // an object or array still being read
    std::string path;  // its JSON pointer
    std::string key;   // objects: the key whose value comes next
  };

  std::string next_path() const {
    if (stack_.empty()) return "";
    const Level& top = stack_.back();
    return top.node->is_array() ? child(top.path, top.node->size()) : child(top.path, top.key);
  }

  json* insert(json v) {
    if (stack_.empty()) {
      root = std::move(v);
      return &root;
    }
    Level& top = stack_.back();
    if (top.node->is_array()) {
      top.node->push_back(std::move(v));
      return &top.node->back();
    }
    json& slot = (*top.node)[top.key];
    slot = std::move(v);
    return &slot;
  }

  bool put(json v) {
    insert(std::move(v));
    return true;
  }

  // Only the open containers are pointed to, and each is the newest element of its
  // parent, which does not change while it is open: the pointers stay valid.
  bool open(json v) {
    std::string path = next_path();
    json* node = insert(std::move(v));
    stack_.push_back(Level{node, std::move(path), std::string()});
    return true;
  }

  bool close() {
    stack_.pop_back();
    return true;
  }

  const std::string& file_;
  const std::string& text_;
  std::vector<Level> stack_;
};

// ---- stage 2: document to Robot ----

const char* param_name(int param) { return param == kParamTheta ? "theta" : (param == kParamD ? "d" : "alpha"); }

class Loader {
 public:
  explicit Loader(const std::string& file) : file_(file) {}

  Robot load(const json& root) {
    robot_.source = file_;
    fields(root, "", "robot");
    robot_.name = string(required(root, "", "name"), "/name");
    if (robot_.name.empty()) fail("/name", "must not be empty");
    if (const json* d = member(root, "description")) robot_.description = string(*d, "/description");
    if (const json* s = member(root, "$schema")) string(*s, "/$schema");

    load_dh(required(root, "", "dh"));
    resolve_links();
    if (const json* t = member(root, "tool")) load_tool(*t);
    const ModelError me = validate(robot_.model);
    if (me != kModelOk) fail("/dh", std::string("the DH model is not usable: ") + model_error_text(me));

    load_home(member(root, "home"));
    if (const json* b = member(root, "board")) load_board(*b, member(root, "motors") != nullptr);
    load_motors(member(root, "motors"), member(root, "coupling"));
    if (robot_.has_motors) check_home_actuators(member(root, "home") != nullptr);
    if (const json* l = member(root, "links")) load_links(*l);
    if (const json* g = member(root, "gripper")) load_gripper(*g);
    if (const json* io = member(root, "io")) load_io(*io);
    if (robot_.drive.given) {
      for (int i = 0; i < robot_.actuation.num_motors; ++i)
        if (robot_.drive.motors[std::size_t(i)].kind != kDriveServo)
          check_microsteps(robot_.actuation.motors[i], robot_.drive.motors[std::size_t(i)], child("/motors", std::size_t(i)));
    }
    if (robot_.drive.given || !robot_.io.empty()) check_wiring();
    check_io_free();
    return std::move(robot_);
  }

 private:
  // What the file said about one joint variable, for messages and defaults.
  struct JointInfo {
    std::string path;  // of its {"joint": ...} object
    bool rotary;       // theta or alpha (degrees in the file) rather than d (mm)
    double min, max;   // as written (deg or mm)
  };
  struct PendingLink {
    int index;  // into model.linked
    std::string path;
    const json* gains;
  };

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw RobotFileError(file_, path, problem);
  }

  [[noreturn]] void wrong_type(const json& j, const std::string& path, const std::string& expected) const {
    fail(path, "expected " + expected + ", got " + kind_of(j));
  }

  // ---- typed access ----

  static const json* member(const json& obj, const char* key) {
    const auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  const json& required(const json& obj, const std::string& path, const char* key, const std::string& why = "") const {
    const json* j = member(obj, key);
    if (!j) fail(child(path, key), "missing required field " + in_quotes(key) + why);
    return *j;
  }

  // An object whose fields are all among those of `kind` (robot_file_fields()).
  void fields(const json& obj, const std::string& path, const char* kind) const {
    if (!obj.is_object()) wrong_type(obj, path, "an object");
    const std::vector<std::string>& allowed = robot_file_fields().at(kind);
    for (const auto& item : obj.items()) {
      bool known = false;
      for (const std::string& a : allowed) known = known || a == item.key();
      if (!known)
        fail(child(path, item.key()), "unknown field " + in_quotes(item.key()) + " (expected one of: " + join(allowed) + ")");
    }
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) wrong_type(j, path, "a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "not a finite number");
    return v;
  }

  // A length that may be zero (a link length RoboSim's `l` may change).
  double length(const json& j, const std::string& path) const {
    const double v = number(j, path);
    if (v < 0) fail(path, "negative length (" + num(v) + " mm)");
    return v;
  }

  double positive(const json& j, const std::string& path, const char* what) const {
    const double v = number(j, path);
    if (!(v > 0)) fail(path, std::string(what) + " must be > 0 (got " + num(v) + ")");
    return v;
  }

  long long integer(const json& j, const std::string& path, long long lo, long long hi) const {
    const double v = number(j, path);
    if (v != std::floor(v)) fail(path, "expected an integer, got " + num(v));
    if (v < double(lo) || v > double(hi))
      fail(path, num(v) + " is out of range (" + std::to_string(lo) + ".." + std::to_string(hi) + ")");
    return static_cast<long long>(v);
  }

  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) wrong_type(j, path, "a string");
    return j.get<std::string>();
  }

  const json& array(const json& j, const std::string& path) const {
    if (!j.is_array()) wrong_type(j, path, "an array");
    return j;
  }

  Vec3<double> vec3(const json& j, const std::string& path) const {
    array(j, path);
    if (j.size() != 3) fail(path, "expected 3 numbers, got " + std::to_string(j.size()));
    return make_vec3(number(j[0], child(path, 0)), number(j[1], child(path, 1)), number(j[2], child(path, 2)));
  }

  // The "xyz" and "rpy" of a tool or shape (mm, degrees) as a transform.
  Transform<double> pose(const json& obj, const std::string& path) const {
    Vec3<double> xyz = make_vec3(0.0, 0.0, 0.0), rpy = xyz;
    if (const json* p = member(obj, "xyz")) xyz = vec3(*p, child(path, "xyz"));
    if (const json* r = member(obj, "rpy")) rpy = vec3(*r, child(path, "rpy"));
    return make_transform(rpy_to_matrix(deg_to_rad(rpy.x), deg_to_rad(rpy.y), deg_to_rad(rpy.z)), xyz);
  }

  int find_joint(const std::string& name) const {
    for (std::size_t j = 0; j < robot_.joint_names.size(); ++j)
      if (robot_.joint_names[j] == name) return int(j);
    return -1;
  }

  [[noreturn]] void unknown_joint(const std::string& path, const std::string& name) const {
    fail(path, "unknown joint name " + in_quotes(name) + " (the joint variables are: " +
                   (robot_.joint_names.empty() ? std::string("none") : join(robot_.joint_names)) + ")");
  }

  // ---- the DH table ----

  void load_dh(const json& dh) {
    array(dh, "/dh");
    if (dh.empty()) fail("/dh", "needs at least one row");
    if (dh.size() > std::size_t(kMaxRows))
      fail("/dh", std::to_string(dh.size()) + " rows; this build supports at most " + std::to_string(kMaxRows));
    HostModel& m = robot_.model;
    m.num_rows = uint8_t(dh.size());
    m.T_last_tool = Transform<double>::identity();
    for (std::size_t i = 0; i < dh.size(); ++i) {
      const std::string path = child("/dh", i);
      const json& row = dh[i];
      fields(row, path, "dh_row");
      m.rows[i].a = link_length(required(row, path, "a"), child(path, "a"), i);
      // Joint variables are numbered in this order: theta, d, alpha.
      for (int param : {int(kParamTheta), int(kParamD), int(kParamAlpha)})
        load_param(required(row, path, param_name(param)), child(path, param_name(param)), int(i), param);
    }
  }

  // "a": a signed distance in mm along x(i-1) (published tables such as Franka's use
  // negative ones), or {"value", "min", "max"}: a link length, >= 0, that RoboSim's `l` may
  // change within the range.
  double link_length(const json& j, const std::string& path, std::size_t row) {
    robot_.length_ranges.resize(row + 1);
    if (!j.is_object()) return number(j, path);
    fields(j, path, "length");
    const double v = length(required(j, path, "value"), child(path, "value"));
    const double lo = length(required(j, path, "min"), child(path, "min"));
    const double hi = length(required(j, path, "max"), child(path, "max"));
    if (lo > hi) fail(child(path, "min"), "limits inverted (min " + num(lo) + " > max " + num(hi) + ")");
    if (v < lo || v > hi) fail(child(path, "value"), num(v) + " mm is outside its range " + num(lo) + " .. " + num(hi));
    robot_.length_ranges[row] = LengthRange{true, lo, hi};
    return v;
  }

  void load_param(const json& j, const std::string& path, int row, int param) {
    HostModel& m = robot_.model;
    const bool rotary = param != kParamD;
    double* slot = detail::param_slot(m.rows[row], uint8_t(param));
    *slot = 0;  // variable and linked parameters have no constant
    if (j.is_number()) {
      const double v = number(j, path);
      *slot = rotary ? deg_to_rad(v) : v;
      return;
    }
    if (!j.is_object() || (!j.contains("joint") && !j.contains("linked"))) {
      const std::string got = j.is_object() ? "an object with neither \"joint\" nor \"linked\"" : kind_of(j);
      fail(path, "expected a number, a joint variable {\"joint\", \"min\", \"max\"} or a linked parameter "
                 "{\"linked\", \"offset\"}, got " + got);
    }
    if (j.contains("joint")) {
      fields(j, path, "joint");
      if (m.num_joints == kMaxJoints)
        fail(path, "more than " + std::to_string(kMaxJoints) + " joint variables; this build supports at most " +
                       std::to_string(kMaxJoints));
      const std::string name_path = child(path, "joint");
      const std::string name = string(required(j, path, "joint"), name_path);
      if (name.empty()) fail(name_path, "a joint name must not be empty");
      const int other = find_joint(name);
      if (other >= 0)
        fail(name_path, "duplicate joint name " + in_quotes(name) + " (already used at " + joint_info_[other].path + ")");
      const double lo = number(required(j, path, "min"), child(path, "min"));
      const double hi = number(required(j, path, "max"), child(path, "max"));
      if (lo > hi) fail(child(path, "min"), "limits inverted (min " + num(lo) + " > max " + num(hi) + ")");
      JointSpec<double>& js = m.joints[m.num_joints++];
      js.row = uint8_t(row);
      js.param = uint8_t(param);
      js.lo = rotary ? deg_to_rad(lo) : lo;
      js.hi = rotary ? deg_to_rad(hi) : hi;
      robot_.joint_names.push_back(name);
      joint_info_.push_back(JointInfo{path, rotary, lo, hi});
      return;
    }
    fields(j, path, "linked");
    if (m.num_linked == kMaxRows)
      fail(path, "more than " + std::to_string(kMaxRows) + " linked parameters; this build supports at most " +
                     std::to_string(kMaxRows));
    const json& gains = required(j, path, "linked");
    if (!gains.is_object()) wrong_type(gains, child(path, "linked"), "an object {\"joint name\": gain, ...}");
    double offset = 0;
    if (const json* o = member(j, "offset")) offset = number(*o, child(path, "offset"));
    LinkedParam<double, kMaxJoints>& l = m.linked[m.num_linked];
    l.row = uint8_t(row);
    l.param = uint8_t(param);
    l.offset = rotary ? deg_to_rad(offset) : offset;
    for (double& g : l.gain) g = 0;
    pending_links_.push_back(PendingLink{m.num_linked, path, &gains});
    ++m.num_linked;
  }

  // Gains name joints of any row, so they are read once every joint is known. A gain is
  // in the file's units: parameter unit per joint unit (deg/deg, mm/mm, mm/deg, deg/mm).
  void resolve_links() {
    for (const PendingLink& p : pending_links_) {
      LinkedParam<double, kMaxJoints>& l = robot_.model.linked[p.index];
      const bool param_rotary = l.param != kParamD;
      for (const auto& item : p.gains->items()) {
        const std::string path = child(child(p.path, "linked"), item.key());
        const int j = find_joint(item.key());
        if (j < 0) unknown_joint(path, item.key());
        const double g = number(item.value(), path);
        const bool joint_rotary = joint_info_[j].rotary;
        if (param_rotary == joint_rotary)
          l.gain[j] = g;
        else if (param_rotary)
          l.gain[j] = deg_to_rad(g);  // deg per mm -> rad per mm
        else
          l.gain[j] = rad_to_deg(g);  // mm per deg -> mm per rad
      }
    }
  }

  void load_tool(const json& tool) {
    fields(tool, "/tool", "tool");
    robot_.model.T_last_tool = pose(tool, "/tool");
  }

  // ---- home ----

  void load_home(const json* home) {
    const HostModel& m = robot_.model;
    robot_.home.assign(m.num_joints, 0.0);
    if (!home) {
      for (int j = 0; j < m.num_joints; ++j) robot_.home[j] = clamp(0.0, m.joints[j].lo, m.joints[j].hi);
      return;
    }
    if (!home->is_object()) wrong_type(*home, "/home", "an object {\"joint name\": value, ...}");
    for (const auto& item : home->items()) {
      const std::string path = child("/home", item.key());
      const int j = find_joint(item.key());
      if (j < 0) unknown_joint(path, item.key());
      const double v = number(item.value(), path);
      const JointInfo& info = joint_info_[j];
      if (v < info.min || v > info.max)
        fail(path, "outside the joint limits (" + num(v) + " not in " + num(info.min) + ".." + num(info.max) + ")");
      robot_.home[j] = info.rotary ? clamp(deg_to_rad(v), m.joints[j].lo, m.joints[j].hi) : v;
    }
    for (const std::string& name : robot_.joint_names)
      if (!home->contains(name))
        fail(child("/home", name), "missing required field " + in_quotes(name) + " (home gives every joint variable)");
  }

  // ---- motors and coupling ----

  void load_motors(const json* motors, const json* coupling) {
    if (!motors) {
      if (coupling) fail("/coupling", "a coupling needs \"motors\"");
      return;
    }
    array(*motors, "/motors");
    const int n = robot_.model.num_joints;
    if (motors->size() != std::size_t(n))
      fail("/motors", "expected " + std::to_string(n) + " motors (one per joint variable), got " +
                          std::to_string(motors->size()));
    robot_.has_motors = true;
    HostActuation& a = robot_.actuation;
    a.num_motors = uint8_t(n);
    for (int i = 0; i < kMaxJoints; ++i)
      for (int k = 0; k < kMaxJoints; ++k) a.coupling[i][k] = a.coupling_inv[i][k] = i == k ? 1.0 : 0.0;

    bool identity = true;
    if (coupling) {
      array(*coupling, "/coupling");
      if (coupling->size() != std::size_t(n))
        fail("/coupling", "expected " + std::to_string(n) + " rows (one per joint variable), got " +
                              std::to_string(coupling->size()));
      for (int i = 0; i < n; ++i) {
        const std::string row_path = child("/coupling", std::size_t(i));
        const json& row = array((*coupling)[i], row_path);
        if (row.size() != std::size_t(n))
          fail(row_path, "expected " + std::to_string(n) + " entries (one per motor), got " + std::to_string(row.size()));
        for (int k = 0; k < n; ++k) {
          a.coupling[i][k] = number(row[k], child(row_path, std::size_t(k)));
          identity = identity && a.coupling[i][k] == (i == k ? 1.0 : 0.0);
        }
      }
      if (n > 0 && !invert_coupling(a))
        fail("/coupling", "singular matrix: the motors cannot set every joint variable independently");
    }

    for (int i = 0; i < n; ++i) {
      const std::string path = child("/motors", std::size_t(i));
      const json& mj = (*motors)[i];
      fields(mj, path, "motor");
      const std::string name = string(required(mj, path, "name"), child(path, "name"));
      if (name.empty()) fail(child(path, "name"), "a motor name must not be empty");
      for (std::size_t k = 0; k < robot_.motor_names.size(); ++k)
        if (robot_.motor_names[k] == name)
          fail(child(path, "name"), "duplicate motor name " + in_quotes(name) + " (already used at " +
                                        child(child("/motors", k), "name") + ")");
      robot_.motor_names.push_back(name);

      MotorSpec& s = a.motors[i];
      s.full_steps_per_rev = 200;
      s.microsteps = 1;
      s.direction = 1;
      s.gear_num = s.gear_den = 1;
      robot_.drive.motors.push_back(MotorDriver{});
      if (const json* d = member(mj, "driver")) {
        robot_.drive.motors.back() = load_driver(*d, child(path, "driver"));
        robot_.drive.given = true;
      }
      const MotorDriver& driver = robot_.drive.motors.back();
      if (driver.kind == kDriveServo) servo_steps(s, driver, mj, path);
      if (const json* v = member(mj, "steps_per_rev"))
        s.full_steps_per_rev = uint16_t(integer(*v, child(path, "steps_per_rev"), 0, 65535));
      if (const json* v = member(mj, "microsteps")) s.microsteps = uint8_t(integer(*v, child(path, "microsteps"), 0, 255));
      if (const json* v = member(mj, "direction")) s.direction = int8_t(integer(*v, child(path, "direction"), -128, 127));
      if (const json* g = member(mj, "gear")) {
        const std::string gp = child(path, "gear");
        array(*g, gp);
        if (g->size() != 2) fail(gp, "expected [motor turns, joint turns] (2 integers), got " + std::to_string(g->size()) + " entries");
        s.gear_num = int32_t(integer((*g)[0], child(gp, 0), -2147483647LL, 2147483647LL));
        s.gear_den = int32_t(integer((*g)[1], child(gp, 1), -2147483647LL, 2147483647LL));
      }
      double zero = 0, lo = 0, hi = 0;
      if (const json* v = member(mj, "zero")) zero = number(*v, child(path, "zero"));
      const std::string why = " (required unless the coupling is identity)";
      if (const json* v = member(mj, "min"))
        lo = number(*v, child(path, "min"));
      else if (identity)
        lo = rad_to_deg(robot_.model.joints[i].lo);
      else
        required(mj, path, "min", why);
      if (const json* v = member(mj, "max"))
        hi = number(*v, child(path, "max"));
      else if (identity)
        hi = rad_to_deg(robot_.model.joints[i].hi);
      else
        required(mj, path, "max", why);
      if (driver.kind == kDriveServo)
        zero = driver.at[0][1];
      millideg(s.zero, zero, child(path, "zero"));
      millideg(s.min, lo, child(path, "min"));
      millideg(s.max, hi, child(path, "max"));
      if (driver.kind == kDriveServo) check_servo_range(driver, lo, hi, path);

      const MotorError e = validate(s);
      if (e != kMotorOk) {
        std::string where = path, detail;
        if (e == kMotorBadGear && mj.contains("gear")) where = child(path, "gear");
        if (e == kMotorBadDirection) where = child(path, "direction");
        if (e == kMotorBadSteps)
          detail = " (steps_per_rev " + std::to_string(s.full_steps_per_rev) + ", microsteps " +
                   std::to_string(s.microsteps) + ")";
        if (e == kMotorBadGear) detail = " (gear [" + std::to_string(s.gear_num) + ", " + std::to_string(s.gear_den) + "])";
        if (e == kMotorBadLimits) detail = " (min " + num(lo) + ", max " + num(hi) + ", zero " + num(zero) + ")";
        fail(where, motor_error_text(e) + detail);
      }
      robot_.motor_torque.push_back(MotorTorque{});
      if (const json* t = member(mj, "torque")) robot_.motor_torque.back() = load_torque(*t, child(path, "torque"));
    }
  }

  // ---- the drive: the board and each motor's driver (wiring.h has the pins) ----

  void load_board(const json& b, bool has_motors) {
    const std::string id = string(b, "/board");
    if (!has_motors) fail("/board", "a board needs \"motors\" to drive");
    const int index = board_by_id(id);
    if (index < 0) fail("/board", "unknown board " + in_quotes(id) + " (expected one of: " + board_ids() + ")");
    robot_.drive.board = index;
    robot_.drive.given = true;
  }

  // "driver": {"kind": "l298n" | "uln2003" | "step-dir" | "servo", and the kind's own fields}.
  MotorDriver load_driver(const json& d, const std::string& path) const {
    fields(d, path, "driver");
    MotorDriver out;
    const std::string kind = string(required(d, path, "kind"), child(path, "kind"));
    std::vector<std::string> kinds;
    bool found = false;
    for (uint8_t k = 0; k < kDriveKinds; ++k) {
      kinds.push_back(kDriveKindInfo[k].id);
      if (kind == kDriveKindInfo[k].id) {
        out.kind = DriveKind(k);
        found = true;
      }
    }
    if (!found) fail(child(path, "kind"), "unknown driver " + in_quotes(kind) + " (expected one of: " + join(kinds) + ")");
    // The fields each kind takes besides "kind".
    const std::vector<std::string> own = out.kind == kDriveStepDir ? std::vector<std::string>{"chip", "enable"}
                                         : out.kind == kDriveServo ? std::vector<std::string>{"pin", "pulse", "at", "speed", "accel", "deadband", "top_speed"}
                                                                   : std::vector<std::string>{};
    for (const auto& item : d.items()) {
      bool ok = item.key() == "kind";
      for (const std::string& f : own) ok = ok || f == item.key();
      if (!ok)
        fail(child(path, item.key()), "a " + kind + " driver takes no " + in_quotes(item.key()) +
                                          (own.empty() ? std::string(" (it takes only \"kind\")")
                                                       : " (it takes: kind, " + join(own) + ")"));
    }
    if (out.kind == kDriveStepDir) {
      const std::string cp = child(path, "chip");
      const std::string chip = string(required(d, path, "chip", " (the driver module's chip: its timing and microsteps)"), cp);
      std::vector<std::string> chips;
      out.chip = -1;
      for (uint8_t c = 0; c < kStepDirChips; ++c) {
        chips.push_back(kStepDirChip[c].id);
        if (chip == kStepDirChip[c].id) out.chip = c;
      }
      if (out.chip < 0) fail(cp, "unknown STEP/DIR chip " + in_quotes(chip) + " (expected one of: " + join(chips) + ")");
      if (const json* e = member(d, "enable")) {
        const std::string ep = child(path, "enable");
        const std::string pin = string(*e, ep);
        const board::BoardInfo& b = board::kBoardInfo[robot_.drive.board];
        if (b.cnc_shield && pin != "D8")
          fail(ep, std::string("the ") + b.title + " wires every driver's EN to D8, not " + pin);
      }
    }
    if (out.kind == kDriveServo) {
      const std::string pp = child(path, "pin");
      std::string why;
      out.pin = header_pin(robot_.drive.board, string(required(d, path, "pin", " (the servo's signal pin, \"D9\")"), pp), why);
      if (out.pin < 0) fail(pp, why);
      out.pulse_min_us = 500;
      out.pulse_max_us = 2500;
      if (const json* p = member(d, "pulse")) {
        const std::string rp = child(path, "pulse");
        array(*p, rp);
        if (p->size() != 2) fail(rp, "expected [shortest, longest] pulse in us (2 numbers), got " + std::to_string(p->size()) + " entries");
        out.pulse_min_us = servo_us((*p)[0], child(rp, 0));
        out.pulse_max_us = servo_us((*p)[1], child(rp, 1));
        if (!(out.pulse_min_us < out.pulse_max_us))
          fail(rp, "the shortest pulse must be below the longest (" + num(out.pulse_min_us) + " >= " + num(out.pulse_max_us) + " us)");
      }
      const std::string ap = child(path, "at");
      const json& at = array(required(d, path, "at", " (two calibration points [pulse us, deg])"), ap);
      if (at.size() != 2) fail(ap, "expected two calibration points [pulse us, deg], got " + std::to_string(at.size()));
      for (std::size_t k = 0; k < 2; ++k) {
        const std::string kp = child(ap, k);
        array(at[k], kp);
        if (at[k].size() != 2) fail(kp, "expected a point [pulse us, deg] (2 numbers), got " + std::to_string(at[k].size()) + " entries");
        out.at[k][0] = servo_us(at[k][0], child(kp, 0));
        out.at[k][1] = number(at[k][1], child(kp, 1));
        if (out.at[k][0] < out.pulse_min_us || out.at[k][0] > out.pulse_max_us)
          fail(child(kp, 0), "a calibration pulse must lie within the pulse range " + num(out.pulse_min_us) + ".." +
                                 num(out.pulse_max_us) + " us (got " + num(out.at[k][0]) + ")");
      }
      if (out.at[0][0] == out.at[1][0] || out.at[0][1] == out.at[1][1])
        fail(ap, "the two calibration points need different pulses and different angles");
      out.speed_deg_s = positive(required(d, path, "speed", " (deg/s: how fast a move ramps the pulse)"), child(path, "speed"), "speed");
      if (const json* v = member(d, "accel")) out.accel_deg_s2 = positive(*v, child(path, "accel"), "accel");
      if (const json* v = member(d, "deadband")) {
        out.deadband_us = number(*v, child(path, "deadband"));
        if (out.deadband_us < 0 || out.deadband_us > 50)
          fail(child(path, "deadband"), "a servo's dead band is 0..50 us (got " + num(out.deadband_us) + ")");
      }
      if (const json* v = member(d, "top_speed")) out.top_speed_deg_s = positive(*v, child(path, "top_speed"), "top_speed");
    }
    return out;
  }

  // A servo pulse width: whole microseconds within what hobby servos take.
  double servo_us(const json& j, const std::string& path) const {
    const double us = number(j, path);
    if (us != std::floor(us)) fail(path, "a servo pulse is whole microseconds (got " + num(us) + ")");
    if (us < kServoPulseMinUs || us > kServoPulseMaxUs)
      fail(path, "a servo pulse must be within " + std::to_string(kServoPulseMinUs) + ".." + std::to_string(kServoPulseMaxUs) +
                     " us (got " + num(us) + ")");
    return us;
  }

  // A servo joint's steps are Timer1's 0.5 us ticks: its MotorSpec comes from the calibration
  // (step 0 at the first point, the ticks per degree from both), never from stepper fields.
  void servo_steps(MotorSpec& s, const MotorDriver& d, const json& mj, const std::string& path) const {
    for (const char* f : {"steps_per_rev", "microsteps", "gear", "direction", "zero", "torque"})
      if (member(mj, f))
        fail(child(path, f), std::string("a servo motor takes no \"") + f +
                                 "\": its steps are the pulse's 0.5 us ticks, set by the driver's calibration \"at\"");
    const long long ticks = std::llround(double(kServoTicksPerUs) * (d.at[1][0] - d.at[0][0])) * 1000;
    const long long mdeg = std::llround((d.at[1][1] - d.at[0][1]) * 1000.0);
    long long num_t = std::llabs(ticks), den = std::llabs(mdeg);
    long long a = num_t, b = den;
    while (b) {
      const long long t = a % b;
      a = b;
      b = t;
    }
    if (mdeg == 0 || a == 0) fail(child(child(path, "driver"), "at"), "the two calibration points need different angles");
    s.full_steps_per_rev = 360;
    s.microsteps = 1;
    s.gear_num = int32_t(num_t / a);
    s.gear_den = int32_t(den / a);
    s.direction = int8_t((ticks > 0) == (mdeg > 0) ? 1 : -1);
  }

  // Every angle from min to max must be a pulse the servo takes.
  void check_servo_range(const MotorDriver& d, double lo, double hi, const std::string& path) const {
    const auto pulse = [&](double deg) {
      return d.at[0][0] + (deg - d.at[0][1]) * (d.at[1][0] - d.at[0][0]) / (d.at[1][1] - d.at[0][1]);
    };
    for (const auto& [deg, field] : {std::pair<double, const char*>{lo, "min"}, {hi, "max"}}) {
      const double us = pulse(deg);
      if (us < d.pulse_min_us - 1e-9 || us > d.pulse_max_us + 1e-9)
        fail(child(path, field), num(deg) + " deg needs a " + num(std::round(us * 10) / 10) +
                                     " us pulse, beyond the servo's range " + num(d.pulse_min_us) + ".." +
                                     num(d.pulse_max_us) + " us");
    }
    if (d.at[0][1] < lo || d.at[0][1] > hi)
      fail(child(child(path, "driver"), "at") + "/0",
           "the first calibration point (" + num(d.at[0][1]) + " deg) is the servo's step 0 and must lie within the motor's limits " +
               num(lo) + ".." + num(hi));
  }

  // A stepper's microsteps must be a mode its driver has.
  void check_microsteps(const MotorSpec& s, const MotorDriver& d, const std::string& path) const {
    const bool step_dir = d.kind == kDriveStepDir;
    const uint16_t mask = step_dir ? kStepDirChip[d.chip].microsteps_mask : kDriveKindInfo[d.kind].microsteps_mask;
    if (microsteps_allowed(mask, s.microsteps)) return;
    std::vector<std::string> modes;
    for (uint8_t k = 0; k < 16; ++k)
      if (mask & (1u << k)) modes.push_back(std::to_string(1u << k));
    const std::string title = step_dir ? kStepDirChip[d.chip].title : kDriveKindInfo[d.kind].title;
    fail(child(path, "microsteps"), "the " + title + " has no " + std::to_string(s.microsteps) +
                                        " microsteps per full step (it takes " + join(modes) + ")");
  }

  // "io": [{"name": "ready", "pin": "D12", "mode": "output" | "input" | "input_pullup"}, ...]:
  // pins of the board the motors are wired to (check_wiring has them free).
  void load_io(const json& j) {
    const json& a = array(j, "/io");
    if (!robot_.has_motors)
      fail("/io", "I/O pins are pins of the board that drives the motors: this robot has no \"motors\"");
    if (a.size() > std::size_t(kMaxIoPins))
      fail("/io", "at most " + std::to_string(kMaxIoPins) + " I/O pins (got " + std::to_string(a.size()) + ")");
    for (std::size_t k = 0; k < a.size(); ++k) {
      const std::string path = child("/io", k);
      fields(a[k], path, "io_pin");
      IoPin p;
      const std::string np = child(path, "name");
      p.name = string(required(a[k], path, "name", " (what programs and wires call it: \"ready\")"), np);
      bool ok = !p.name.empty() && p.name.size() <= 16 && std::isalpha(static_cast<unsigned char>(p.name[0]));
      for (char c : p.name) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
      if (!ok)
        fail(np, "an I/O pin's name is 1 to 16 letters, digits, _ or -, starting with a letter (got " + in_quotes(p.name) + ")");
      for (const IoPin& other : robot_.io)
        if (other.name == p.name) fail(np, "duplicate I/O pin name " + in_quotes(p.name));
      const std::string pp = child(path, "pin");
      std::string why;
      p.pin = header_pin(robot_.drive.board, string(required(a[k], path, "pin", " (a free header pin, \"D12\")"), pp), why);
      if (p.pin < 0) fail(pp, why);
      const std::string mp = child(path, "mode");
      const std::string mode = string(required(a[k], path, "mode", " (output, input or input_pullup)"), mp);
      bool known = false;
      for (IoMode m : {kIoOutput, kIoInput, kIoInputPullup})
        if (mode == io_mode_id(m)) p.mode = m, known = true;
      if (!known) fail(mp, "unknown mode " + in_quotes(mode) + " (expected one of: output, input, input_pullup)");
      robot_.io.push_back(p);
    }
  }

  // Every I/O pin one that the arm's firmware build lets O and W use (wiring.h's io_pins_free,
  // from board.h: what the drive keeps): else programs could never set or read it.
  void check_io_free() const {
    const uint32_t free = io_pins_free(robot_);
    for (std::size_t k = 0; k < robot_.io.size(); ++k)
      if (!(free & (uint32_t(1) << robot_.io[k].pin)))
        fail(child(child("/io", k), "pin"), "pin " + header_pin_name(robot_.io[k].pin) + " is not one this arm's firmware (" +
                                                firmware_build(robot_) + ") lets O and W use: its free pins are " +
                                                io_pins_free_text(robot_));
  }

  // The board can give what every driver asks for, each pin once (wiring.cpp).
  void check_wiring() const {
    try {
      wire(robot_);
    } catch (const WiringError& e) {
      std::string where = "/board";
      if (e.io >= 0) where = child(child("/io", std::size_t(e.io)), "pin");
      if (e.motor >= 0) {
        where = child("/motors", std::size_t(e.motor));
        if (!e.field.empty()) where = child(child(where, "driver"), e.field);
      }
      fail(where, e.what());
    }
  }

  // "torque": {"pull_out": [[full steps/s, N*m], ...], "rotor_inertia": kg*m^2}.
  MotorTorque load_torque(const json& t, const std::string& path) const {
    fields(t, path, "torque");
    MotorTorque out;
    const std::string pp = child(path, "pull_out");
    const json& curve = array(required(t, path, "pull_out"), pp);
    if (curve.size() < 2)
      fail(pp, "expected at least 2 points [full steps/s, N*m] (the holding torque at 0 and one more), got " +
                   std::to_string(curve.size()));
    for (std::size_t k = 0; k < curve.size(); ++k) {
      const std::string kp = child(pp, k);
      array(curve[k], kp);
      if (curve[k].size() != 2)
        fail(kp, "expected a point [full steps/s, N*m] (2 numbers), got " + std::to_string(curve[k].size()) + " entries");
      const double rate = number(curve[k][0], child(kp, 0)), torque = number(curve[k][1], child(kp, 1));
      if (k == 0 && rate != 0)
        fail(child(kp, 0), "the curve must start at rate 0 (the holding torque), got " + num(rate));
      if (k > 0 && !(rate > out.pull_out.back()[0]))
        fail(child(kp, 0), "rates must be strictly ascending (" + num(rate) + " after " + num(out.pull_out.back()[0]) + ")");
      if (torque < 0) fail(child(kp, 1), "a torque must be >= 0 (got " + num(torque) + " N*m)");
      if (k == 0 && !(torque > 0)) fail(child(kp, 1), "the holding torque must be > 0 (got " + num(torque) + " N*m)");
      out.pull_out.push_back({rate, torque});
    }
    if (const json* j = member(t, "rotor_inertia")) {
      const std::string jp = child(path, "rotor_inertia");
      out.rotor_inertia = number(*j, jp);
      if (out.rotor_inertia < 0) fail(jp, "a rotor inertia must be >= 0 (got " + num(out.rotor_inertia) + " kg*m^2)");
    }
    return out;
  }

  void millideg(Millideg& out, double degrees, const std::string& path) const {
    if (!to_millideg(out, degrees)) fail(path, num(degrees) + " deg is beyond +-1,000,000 degrees");
  }

  // The home pose must be reachable by the motors: u = C^-1 q within every motor's limits.
  void check_home_actuators(bool home_given) const {
    const HostActuation& a = robot_.actuation;
    double u[kMaxJoints];
    actuators_from_joints(u, a, robot_.home.data());
    for (int i = 0; i < a.num_motors; ++i) {
      const double deg = rad_to_deg(u[i]);
      const double lo = a.motors[i].min / 1000.0, hi = a.motors[i].max / 1000.0;
      const double tol = 1e-6;  // degrees: rounding in C^-1 q
      if (deg < lo - tol || deg > hi + tol)
        fail("/home", "the home pose puts motor " + in_quotes(robot_.motor_names[i]) + " at " + num(deg) +
                          " deg, outside its limits " + num(lo) + ".." + num(hi) +
                          (home_given ? "" : " (no \"home\" given: each joint is 0 clamped into its limits)"));
    }
  }

  // ---- link geometry and gripper ----

  void load_links(const json& links) {
    array(links, "/links");
    const int rows = robot_.model.num_rows;
    for (std::size_t i = 0; i < links.size(); ++i) {
      const std::string path = child("/links", i);
      const json& lj = links[i];
      fields(lj, path, "link");
      LinkGeometry link;
      const std::string fp = child(path, "frame");
      const json& frame = required(lj, path, "frame");
      if (frame.is_number() && std::isfinite(frame.get<double>()) && frame.get<double>() == std::floor(frame.get<double>()) &&
          (frame.get<double>() < 0 || frame.get<double>() > rows))
        fail(fp, "frame " + num(frame.get<double>()) + " does not exist (frames are 0.." + std::to_string(rows) +
                     ": 0 the base, i the frame after DH row i)");
      link.frame = int(integer(frame, fp, 0, rows));
      const std::string sp = child(path, "shapes");
      const json& shapes = array(required(lj, path, "shapes"), sp);
      for (std::size_t k = 0; k < shapes.size(); ++k) link.shapes.push_back(load_shape(shapes[k], child(sp, k)));
      robot_.links.push_back(std::move(link));
    }
  }

  Shape load_shape(const json& sj, const std::string& path) const {
    fields(sj, path, "shape");
    Shape s;
    const std::string tp = child(path, "type");
    const std::string type = string(required(sj, path, "type"), tp);
    std::size_t sizes = 0;
    const char* size_names = "";
    if (type == "box") {
      s.type = Shape::Type::kBox;
      sizes = 3;
      size_names = "box: [x, y, z]";
    } else if (type == "cylinder" || type == "capsule") {
      s.type = type == "cylinder" ? Shape::Type::kCylinder : Shape::Type::kCapsule;
      sizes = 2;
      size_names = "cylinder and capsule: [radius, length]";
    } else if (type == "sphere") {
      s.type = Shape::Type::kSphere;
      sizes = 1;
      size_names = "sphere: [radius]";
    } else if (type == "mesh") {
      s.type = Shape::Type::kMesh;
    } else {
      fail(tp, "unknown shape type " + in_quotes(type) + " (expected box, cylinder, capsule, sphere or mesh)");
    }

    const std::string zp = child(path, "size"), mp = child(path, "mesh");
    if (s.type == Shape::Type::kMesh) {
      if (sj.contains("size")) fail(zp, "a mesh shape has no size (the mesh file gives it)");
      s.mesh = string(required(sj, path, "mesh"), mp);
      if (s.mesh.empty()) fail(mp, "the mesh file name must not be empty");
    } else {
      if (sj.contains("mesh")) fail(mp, "only a shape of type \"mesh\" has a mesh file");
      const json& size = array(required(sj, path, "size"), zp);
      if (size.size() != sizes)
        fail(zp, "expected " + std::to_string(sizes) + (sizes == 1 ? " number" : " numbers") + " (" + size_names +
                     "), got " + std::to_string(size.size()));
      for (std::size_t k = 0; k < sizes; ++k) s.size[k] = positive(size[k], child(zp, k), "a size");
    }
    s.T_frame_shape = pose(sj, path);

    const json* mass = member(sj, "mass");
    const json* density = member(sj, "density");
    if (mass && density) fail(child(path, "density"), "give \"mass\" or \"density\", not both");
    if (mass)
      s.mass = positive(*mass, child(path, "mass"), "a mass");
    else
      s.density = density ? positive(*density, child(path, "density"), "a density") : kDefaultDensity;
    return s;
  }

  void load_gripper(const json& g) {
    fields(g, "/gripper", "gripper");
    Gripper& out = robot_.gripper;
    out.present = true;
    out.max_opening_mm = positive(required(g, "/gripper", "max_opening"), "/gripper/max_opening", "max_opening");
    out.finger_length_mm = positive(required(g, "/gripper", "finger_length"), "/gripper/finger_length", "finger_length");
    if (const json* t = member(g, "finger_thickness"))
      out.finger_thickness_mm = positive(*t, "/gripper/finger_thickness", "finger_thickness");
    if (const json* h = member(g, "finger_height"))
      out.finger_height_mm = positive(*h, "/gripper/finger_height", "finger_height");
    out.servo_open_deg = servo_angle(required(g, "/gripper", "servo_open"), "/gripper/servo_open");
    out.servo_closed_deg = servo_angle(required(g, "/gripper", "servo_closed"), "/gripper/servo_closed");
  }

  double servo_angle(const json& j, const std::string& path) const {
    const double v = number(j, path);
    if (v < 0 || v > 180) fail(path, "a servo angle must be within 0..180 degrees (got " + num(v) + ")");
    return v;
  }

  std::string file_;
  Robot robot_;
  std::vector<JointInfo> joint_info_;
  std::vector<PendingLink> pending_links_;
};

}  // namespace

Robot parse_robot(const std::string& json_text, const std::string& name) {
  DocumentBuilder builder(name, json_text);
  json::sax_parse(json_text, &builder);
  return Loader(name).load(builder.root);
}

Robot load_robot_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw RobotFileError(path, "", "file not found");
  if (fs::is_directory(st)) throw RobotFileError(path, "", "cannot read: is a directory, not a robot file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RobotFileError(path, "", "cannot read the file (permission denied?)");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw RobotFileError(path, "", "error while reading the file");
  return parse_robot(text.str(), path);
}

std::string resolve_robot_path(const std::string& name_or_path) {
  const std::string ext = ".json";
  const bool is_path = name_or_path.find('/') != std::string::npos ||
                       (name_or_path.size() >= ext.size() &&
                        name_or_path.compare(name_or_path.size() - ext.size(), ext.size(), ext) == 0);
  if (is_path) return name_or_path;
  const char* env = std::getenv("ARTICULA_ROBOTS");
  const std::string dir = env && *env ? env : ARTICULA_ROBOTS_DIR;
  return dir + "/" + name_or_path + ext;
}

std::string file_number(double v) {
  std::ostringstream o;
  o.precision(10);
  o << (v == 0 ? 0.0 : v);  // (never "-0")
  return o.str();
}

}  // namespace articula::host
