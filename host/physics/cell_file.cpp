// host/physics/cell_file.cpp - see cell_file.h; cells/README.md is the format.
#include "cell_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "geometry.h"
#include "mesh.h"
#include "robot_file.h"

namespace articula::host {

CellError::CellError(const std::string& file, const std::string& json_path, const std::string& problem)
    : std::runtime_error(file + ": " + (json_path.empty() ? std::string() : json_path + ": ") + problem),
      json_path_(json_path),
      problem_(problem) {}

const std::map<std::string, std::vector<std::string>>& cell_file_fields() {
  static const std::map<std::string, std::vector<std::string>> fields = {
      {"cell", {"$schema", "name", "description", "scene", "arms", "devices", "wires"}},
      {"device", {"name", "kind", "object", "from", "to", "objects", "at", "every", "size"}},
      {"arm", {"name", "robot", "io", "base", "program"}},
      {"base", {"xyz", "yaw"}},
      {"wire", {"from", "to"}},
  };
  return fields;
}

Transform<double> CellArm::T_world_base() const {
  return make_transform(rpy_to_matrix(0.0, 0.0, yaw_deg * M_PI / 180), xyz);
}

int Cell::arm_index(const std::string& arm) const {
  for (size_t i = 0; i < arms.size(); ++i)
    if (arms[i].name == arm) return int(i);
  return -1;
}

int Cell::device_index(const std::string& device) const {
  for (size_t i = 0; i < devices.size(); ++i)
    if (devices[i].name == device) return int(i);
  return -1;
}

double base_footprint_mm(const Robot& robot) {
  double r = 0;
  for (const LinkGeometry& l : arm_geometry(robot)) {
    if (l.frame != 0) continue;
    for (const Shape& s : l.shapes) {
      const Transform<double>& T = s.T_frame_shape;
      const double centre = std::hypot(T.p.x, T.p.y);
      const bool upright = std::fabs(T.R.m[2][2]) > 1 - 1e-9;  // the shape's z along the table's
      std::vector<Vec3<double>> corners;  // of the shape's own box, where a bound needs them
      switch (s.type) {
        case Shape::Type::kSphere: r = std::max(r, centre + s.size[0]); continue;
        case Shape::Type::kCylinder:
        case Shape::Type::kCapsule:
          if (upright) {
            r = std::max(r, centre + s.size[0]);
            continue;
          }
          for (int k = 0; k < 8; ++k) {
            const double half = s.size[1] / 2 + (s.type == Shape::Type::kCapsule ? s.size[0] : 0);
            corners.push_back(make_vec3((k & 1 ? 1 : -1) * s.size[0], (k & 2 ? 1 : -1) * s.size[0], (k & 4 ? 1 : -1) * half));
          }
          break;
        case Shape::Type::kBox:
          for (int k = 0; k < 8; ++k)
            corners.push_back(make_vec3((k & 1 ? 0.5 : -0.5) * s.size[0], (k & 2 ? 0.5 : -0.5) * s.size[1],
                                        (k & 4 ? 0.5 : -0.5) * s.size[2]));
          break;
        case Shape::Type::kMesh:
          for (const auto& v : load_mesh_file(mesh_path(robot, s)).vertices) corners.push_back(make_vec3(v.x, v.y, v.z));
          break;
      }
      for (const Vec3<double>& c : corners) {
        const Vec3<double> p = T.R * c + T.p;
        r = std::max(r, std::hypot(p.x, p.y));
      }
    }
  }
  return r;
}

namespace cell_loader {  // (named: the unity build puts scene.cpp's Loader beside this one)

using json = nlohmann::json;

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string child(const std::string& path, const std::string& key) { return path + "/" + key; }
std::string child(const std::string& path, size_t i) { return path + "/" + std::to_string(i); }

std::string read_file(const std::string& path, bool& ok) {
  std::ifstream f(path, std::ios::binary);
  ok = bool(f);
  std::ostringstream ss;
  if (ok) ss << f.rdbuf();
  return ss.str();
}

std::string names_of(const Cell& cell) {
  std::string out;
  for (const auto& a : cell.arms) out += (out.empty() ? "" : ", ") + a.name;
  return out;
}

// A name for an arm or a pin: what wires write as "arm.pin".
bool good_name(const std::string& s) {
  bool ok = !s.empty() && s.size() <= 16 && std::isalpha(static_cast<unsigned char>(s[0]));
  for (char c : s) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
  return ok;
}

class Loader {
 public:
  Loader(std::string file, std::string dir) : file_(std::move(file)), dir_(std::move(dir)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw CellError(file_, path, problem);
  }

  Cell load(const json& j) {
    fields(j, "", "cell");
    cell_.source = file_;
    if (j.contains("$schema")) text(j["$schema"], "/$schema");
    if (!j.contains("name")) fail("", "missing field \"name\"");
    cell_.name = text(j["name"], "/name");
    if (cell_.name.empty()) fail("/name", "must not be empty");
    if (j.contains("description")) cell_.description = text(j["description"], "/description");
    load_scene(j.contains("scene") ? &j["scene"] : nullptr);
    if (!j.contains("arms")) fail("", "missing field \"arms\" (the arms on the table: name, robot, base, program)");
    const json& arms = j["arms"];
    if (!arms.is_array() || arms.empty()) fail("/arms", "must be an array of at least one arm");
    if (arms.size() > size_t(kMaxCellArms))
      fail("/arms", "at most " + std::to_string(kMaxCellArms) + " arms (got " + std::to_string(arms.size()) + ")");
    for (size_t k = 0; k < arms.size(); ++k) load_arm(arms[k], child("/arms", k));
    if (j.contains("devices")) load_devices(j["devices"]);
    // (its objects inside one another: a scene written in place is checked here, where the
    // feeders' magazines, out of the world at the start, are known)
    std::vector<int> stowed;
    for (const CellDevice& d : cell_.devices) stowed.insert(stowed.end(), d.magazine.begin(), d.magazine.end());
    const SceneOverlap overlap = first_overlap(cell_.scene, stowed);
    if (overlap.object >= 0)
      fail((j.contains("scene") && j["scene"].is_object() ? "/scene" : "") + std::string("/objects/") + std::to_string(overlap.object),
           overlap.problem);
    if (j.contains("wires")) load_wires(j["wires"]);
    return std::move(cell_);
  }

 private:
  void fields(const json& j, const std::string& path, const std::string& kind) const {
    if (!j.is_object()) fail(path, "must be an object");
    const auto& allowed = cell_file_fields().at(kind);
    for (const auto& item : j.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(child(path, item.key()), "unknown field " + in_quotes(item.key()) + " (expected one of: " + list + ")");
    }
  }

  std::string text(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "must be a string");
    return j.get<std::string>();
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "must be finite");
    return v;
  }

  // A path the file gives, from the file's folder.
  std::string relative(const std::string& p) const {
    if (p.empty() || p[0] == '/' || dir_.empty()) return p;
    return (std::filesystem::path(dir_) / p).lexically_normal().string();
  }

  // "scene": a shipped scene's name, a scene file (from the cell's folder), or a scene written
  // in place (scenes/README.md's format). None: the ground only.
  void load_scene(const json* s) {
    cell_.scene.name = "ground only";
    if (!s) return;
    try {
      if (s->is_string()) {
        const std::string ref = s->get<std::string>();
        const bool path = ref.find('/') != std::string::npos || ref.find('.') != std::string::npos;
        cell_.scene = load_scene_file(path ? relative(ref) : resolve_scene_path(ref));
      } else if (s->is_object()) {
        cell_.scene = scene_from_json(*s, file_);
      } else {
        fail("/scene", "must be a scene's name or file, or a scene (an object: scenes/README.md)");
      }
    } catch (const SceneError& e) {
      if (s->is_object()) fail("/scene" + e.json_path(), e.problem());
      fail("/scene", e.what());
    }
  }

  void load_arm(const json& j, const std::string& path) {
    fields(j, path, "arm");
    CellArm arm;
    arm.name = name_field(j, path, "arm", "what events, wires and programs call the arm");
    const int twin = cell_.arm_index(arm.name);
    if (twin >= 0) fail(child(path, "name"), "two arms are called " + in_quotes(arm.name) + " (/arms/" + std::to_string(twin) + ")");
    if (!j.contains("robot")) fail(path, "missing field \"robot\" (a shipped robot's name or a robot file)");
    arm.robot_ref = text(j["robot"], child(path, "robot"));
    const bool robot_path = arm.robot_ref.find('/') != std::string::npos || arm.robot_ref.find(".json") != std::string::npos;
    const std::string robot_file = robot_path ? relative(arm.robot_ref) : resolve_robot_path(arm.robot_ref);
    try {
      arm.robot = load_robot_file(robot_file);
    } catch (const RobotFileError& e) {
      fail(child(path, "robot"), std::string("the robot cannot be used: ") + e.what());
    }
    // "io": the robot's I/O pins for this cell (as a robot file's "io", in its place), so a
    // shipped robot is wired without a copy of its file; the robot file's reader checks them.
    if (j.contains("io")) {
      json r = json::parse(std::ifstream(robot_file));
      r["io"] = j["io"];
      try {
        arm.robot = parse_robot(r.dump(), robot_file);
      } catch (const RobotFileError& e) {
        fail(child(path, "io"), std::string("the robot cannot have these I/O pins: ") + e.what());
      }
    }
    if (j.contains("base")) {
      const std::string bp = child(path, "base");
      const json& b = j["base"];
      fields(b, bp, "base");
      if (b.contains("xyz")) {
        const json& x = b["xyz"];
        if (!x.is_array() || x.size() != 3) fail(child(bp, "xyz"), "must be [x, y, z] in mm (3 numbers)");
        arm.xyz = make_vec3(number(x[0], child(bp, "xyz") + "/0"), number(x[1], child(bp, "xyz") + "/1"),
                            number(x[2], child(bp, "xyz") + "/2"));
      }
      if (b.contains("yaw")) arm.yaw_deg = number(b["yaw"], child(bp, "yaw"));
    }
    try {
      arm.footprint_mm = base_footprint_mm(arm.robot);
    } catch (const MeshError& e) {
      fail(child(path, "robot"), std::string("its base's mesh cannot be read: ") + e.what());
    }
    for (const CellArm& other : cell_.arms) {
      const double apart = std::hypot(arm.xyz.x - other.xyz.x, arm.xyz.y - other.xyz.y);
      const double need = arm.footprint_mm + other.footprint_mm;
      if (apart < need)
        fail(child(path, "base"), "the bases of " + in_quotes(arm.name) + " and " + in_quotes(other.name) +
                                      " overlap: they stand " + fmt(apart) + " mm apart, and their bases need " +
                                      fmt(need) + " mm (" + fmt(arm.footprint_mm) + " + " + fmt(other.footprint_mm) +
                                      " mm around each base's centre)");
    }
    if (j.contains("program")) load_program_of(arm, j["program"], child(path, "program"));
    cell_.arms.push_back(std::move(arm));
  }

  static std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }

  // "program": a program file (from the cell's folder), or its lines written in place.
  void load_program_of(CellArm& arm, const json& p, const std::string& path) {
    std::string source, body;
    bool inline_lines = false;
    if (p.is_string()) {
      source = relative(p.get<std::string>());
      bool ok = false;
      body = read_file(source, ok);
      if (!ok)
        fail(path, "cannot read the program " + in_quotes(source) +
                       (std::filesystem::exists(source) ? "" : " (no such file; a path is taken from the cell file's folder)"));
    } else if (p.is_array()) {
      inline_lines = true;
      for (size_t k = 0; k < p.size(); ++k) body += text(p[k], child(path, k)) + "\n";
      source = file_ + "#" + path;
    } else {
      fail(path, "must be a program file or its lines (an array of strings)");
    }
    try {
      arm.program = parse_program(body, source, arm.robot);
    } catch (const ProgramError& e) {
      // a line in place is its array entry (the first that cannot be read)
      const std::string& problem = e.problems().front().problem;
      if (inline_lines && e.line() > 0) fail(child(path, size_t(e.line() - 1)), "for " + arm.robot.name + ": " + problem);
      fail(path, "for " + arm.robot.name + ": " + e.what());
    }
    arm.program_ref = source;
  }

  Vec3<double> point(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, "must be [x, y, z] in mm (3 numbers)");
    return make_vec3(number(j[0], child(path, 0)), number(j[1], child(path, 1)), number(j[2], child(path, 2)));
  }

  // "devices": belts and light barriers the wires reach (cell_file.h's CellDevice).
  void load_devices(const json& d) {
    if (!d.is_array()) fail("/devices", "must be an array of devices ({\"name\": \"gate\", \"kind\": \"barrier\", ...})");
    for (size_t k = 0; k < d.size(); ++k) {
      const std::string path = child("/devices", k);
      const json& j = d[k];
      fields(j, path, "device");
      CellDevice dev;
      dev.name = name_field(j, path, "device", "what wires call the device");
      if (cell_.arm_index(dev.name) >= 0 || cell_.device_index(dev.name) >= 0)
        fail(child(path, "name"), "the cell already has an arm or a device called " + in_quotes(dev.name));
      if (!j.contains("kind")) fail(path, "missing field \"kind\" (\"belt\", \"barrier\", \"switch\" or \"feeder\")");
      const std::string kind = text(j["kind"], child(path, "kind"));
      auto only = [&](std::initializer_list<const char*> needs, std::initializer_list<const char*> not_for) {
        for (const char* f : needs)
          if (!j.contains(f)) fail(path, "a " + kind + " needs the field " + in_quotes(f));
        for (const char* f : not_for)
          if (j.contains(f)) fail(child(path, f), "a " + kind + " has no field " + in_quotes(f));
      };
      if (kind == "belt") {
        dev.kind = CellDevice::Kind::kBelt;
        only({"object"}, {"from", "to", "objects", "at", "every", "size"});
        const std::string obj = text(j["object"], child(path, "object"));
        std::string belts;
        for (const SceneObject& so : cell_.scene.objects)
          if (so.belt != 0) belts += (belts.empty() ? "" : ", ") + so.name;
        dev.object = scene_object(obj);
        if (dev.object < 0 || cell_.scene.objects[size_t(dev.object)].belt == 0)
          fail(child(path, "object"), "the scene has no belt " + in_quotes(obj) +
                                          (belts.empty() ? " (none of its objects is a belt: an object's \"belt\" speed)"
                                                         : " (its belts: " + belts + ")"));
        for (const CellDevice& other : cell_.devices)
          if (other.kind == CellDevice::Kind::kBelt && other.object == dev.object)
            fail(child(path, "object"), "the belt " + in_quotes(obj) + " is already the device " + in_quotes(other.name));
      } else if (kind == "barrier") {
        dev.kind = CellDevice::Kind::kBarrier;
        only({"from", "to"}, {"object", "objects", "at", "every", "size"});
        dev.from = point(j["from"], child(path, "from"));
        dev.to = point(j["to"], child(path, "to"));
        const double len = norm(dev.to - dev.from);
        if (len < 1) fail(child(path, "to"), "a beam is at least 1 mm long (its ends are " + fmt(len) + " mm apart)");
        if (len > 5000) fail(child(path, "to"), "a beam is at most 5 m long (its ends are " + fmt(len) + " mm apart)");
      } else if (kind == "feeder") {
        dev.kind = CellDevice::Kind::kFeeder;
        only({"objects", "at"}, {"object", "from", "to", "size"});
        const json& objs = j["objects"];
        const std::string op = child(path, "objects");
        if (!objs.is_array() || objs.empty() || objs.size() > 50)
          fail(op, "must be the names of 1 to 50 of the scene's movable objects, in the order it puts them out");
        for (size_t m = 0; m < objs.size(); ++m) {
          const std::string name = text(objs[m], child(op, m));
          const int found = scene_object(name);
          if (found < 0) fail(child(op, m), "the scene has no object " + in_quotes(name));
          if (!cell_.scene.objects[size_t(found)].movable)
            fail(child(op, m), in_quotes(name) + " is not movable: a feeder puts out movable objects");
          for (const CellDevice& other : cell_.devices)
            if (std::find(other.magazine.begin(), other.magazine.end(), found) != other.magazine.end())
              fail(child(op, m), in_quotes(name) + " is already in the feeder " + in_quotes(other.name));
          if (std::find(dev.magazine.begin(), dev.magazine.end(), found) != dev.magazine.end())
            fail(child(op, m), in_quotes(name) + " is twice in this feeder");
          dev.magazine.push_back(found);
        }
        dev.at = point(j["at"], child(path, "at"));
        if (j.contains("every")) {
          dev.every_s = number(j["every"], child(path, "every"));
          if (dev.every_s < 0.5 || dev.every_s > 3600)
            fail(child(path, "every"), "a feeder puts one out every 0.5 to 3600 seconds (got " + fmt(dev.every_s) + ")");
        }
      } else if (kind == "switch") {
        dev.kind = CellDevice::Kind::kSwitch;
        only({"at", "size"}, {"object", "from", "to", "objects", "every"});
        dev.at = point(j["at"], child(path, "at"));
        dev.size = point(j["size"], child(path, "size"));
        for (const double v : {dev.size.x, dev.size.y, dev.size.z})
          if (!(v >= 1 && v <= 500)) fail(child(path, "size"), "a switch's box is 1 to 500 mm each way");
      } else {
        fail(child(path, "kind"), "must be \"belt\", \"barrier\", \"switch\" or \"feeder\" (got " + in_quotes(kind) + ")");
      }
      cell_.devices.push_back(std::move(dev));
    }
  }

  // A device's end of a wire, as End's first: past the arms (kDevice + its index).
  static constexpr int kDevice = 1000;

  // "arm.pin" or "device.pin" -> (arm, pin) or (kDevice + device, 0), or a refusal that says
  // what the cell has.
  std::pair<int, int> end_of(const json& j, const std::string& path) const {
    const std::string s = text(j, path);
    const size_t dot = s.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == s.size())
      fail(path, "a wire's end is \"arm.pin\" or \"device.pin\" (got " + in_quotes(s) + ")");
    const std::string arm = s.substr(0, dot), pin = s.substr(dot + 1);
    const int dev = cell_.device_index(arm);
    if (dev >= 0) {
      const CellDevice& d = cell_.devices[size_t(dev)];
      if (pin != d.pin())
        fail(path, "the " + std::string(d.kind_name()) + " " + in_quotes(arm) + " has one pin, " + in_quotes(d.pin()) +
                       " (got " + in_quotes(pin) + ")");
      return {kDevice + dev, 0};
    }
    const int a = cell_.arm_index(arm);
    if (a < 0)
      fail(path, "the cell has no arm or device " + in_quotes(arm) + " (its arms: " + names_of(cell_) +
                     (cell_.devices.empty() ? "" : "; its devices: " + device_names()) + ")");
    const Robot& r = cell_.arms[size_t(a)].robot;
    for (size_t k = 0; k < r.io.size(); ++k)
      if (r.io[k].name == pin) return {a, int(k)};
    std::string pins;
    for (const IoPin& p : r.io) pins += (pins.empty() ? "" : ", ") + p.name + " (" + io_mode_id(p.mode) + ")";
    fail(path, "arm " + in_quotes(arm) + " has no I/O pin " + in_quotes(pin) +
                   (pins.empty() ? " (its robot, " + r.name + ", names none: a robot file's \"io\")" : " (its pins: " + pins + ")"));
  }

  // Wires join pins into nets; each net is driven by exactly one output, and the cell keeps a
  // wire from that output to each input on its net.
  void load_wires(const json& w) {
    if (!w.is_array()) fail("/wires", "must be an array of wires ({\"from\": \"arm.pin\", \"to\": \"arm.pin\"})");
    using End = std::pair<int, int>;  // (arm, pin)
    std::vector<End> ends;            // every pin a wire touches
    std::vector<int> up;              // union-find over ends
    std::vector<std::string> first_wire;  // the path of the wire that first touched each end
    auto index_of = [&](End e, const std::string& path) {
      for (size_t i = 0; i < ends.size(); ++i)
        if (ends[i] == e) return int(i);
      ends.push_back(e);
      up.push_back(int(up.size()));
      first_wire.push_back(path);
      return int(ends.size() - 1);
    };
    auto root = [&](int i) {
      while (up[size_t(i)] != i) i = up[size_t(i)];
      return i;
    };
    auto label = [&](End e) {
      if (e.first >= kDevice) {
        const CellDevice& d = cell_.devices[size_t(e.first - kDevice)];
        return d.name + "." + d.pin();
      }
      return cell_.arms[size_t(e.first)].name + "." + cell_.arms[size_t(e.first)].robot.io[size_t(e.second)].name;
    };
    auto is_output = [&](End e) {
      if (e.first >= kDevice) return cell_.devices[size_t(e.first - kDevice)].output();
      return !cell_.arms[size_t(e.first)].robot.io[size_t(e.second)].input();
    };
    for (size_t k = 0; k < w.size(); ++k) {
      const std::string path = child("/wires", k);
      fields(w[k], path, "wire");
      for (const char* f : {"from", "to"})
        if (!w[k].contains(f)) fail(path, std::string("missing field \"") + f + "\" (\"arm.pin\")");
      const End a = end_of(w[k]["from"], child(path, "from")), b = end_of(w[k]["to"], child(path, "to"));
      if (a == b) fail(path, "joins " + label(a) + " to itself");
      const int ra = root(index_of(a, path)), rb = root(index_of(b, path));
      std::vector<End> outputs;
      for (size_t i = 0; i < ends.size(); ++i) {
        const int r = root(int(i));
        if ((r == ra || r == rb) && is_output(ends[i])) outputs.push_back(ends[i]);
      }
      if (outputs.size() > 1)
        fail(path, "joins two outputs, " + label(outputs[0]) + " and " + label(outputs[1]) +
                       ": an output drives a wire, and the other ends must be inputs");
      up[size_t(rb)] = ra;
    }
    for (size_t i = 0; i < ends.size(); ++i) {
      if (is_output(ends[i])) continue;
      int driver = -1;
      for (size_t o = 0; o < ends.size(); ++o)
        if (root(int(o)) == root(int(i)) && is_output(ends[o])) driver = int(o);
      if (driver < 0) fail(first_wire[i], "joins only inputs (" + label(ends[i]) + " among them): no output drives it");
      CellWire cw;
      const End from = ends[size_t(driver)], to = ends[i];
      if (from.first >= kDevice) cw.from_device = from.first - kDevice;
      else cw.from_arm = from.first, cw.from_pin = from.second;
      if (to.first >= kDevice) cw.to_device = to.first - kDevice;
      else cw.to_arm = to.first, cw.to_pin = to.second;
      cell_.wires.push_back(cw);
    }
  }

  // An arm's or a device's "name": present, and a name wires can write ("arm.pin").
  std::string name_field(const json& j, const std::string& path, const std::string& what, const char* used_for) {
    if (!j.contains("name")) fail(path, "missing field \"name\" (" + std::string(used_for) + ")");
    std::string name = text(j["name"], child(path, "name"));
    if (!good_name(name))
      fail(child(path, "name"), "a" + std::string(what == "arm" ? "n " : " ") + what +
                                    "'s name is 1 to 16 letters, digits, _ or -, starting with a letter (got " +
                                    in_quotes(name) + ")");
    return name;
  }

  // The scene's object called name, -1 if none (the last one, should two share it).
  int scene_object(const std::string& name) const {
    for (size_t o = cell_.scene.objects.size(); o-- > 0;)
      if (cell_.scene.objects[o].name == name) return int(o);
    return -1;
  }

  std::string device_names() const {
    std::string out;
    for (const CellDevice& d : cell_.devices) out += (out.empty() ? "" : ", ") + d.name;
    return out;
  }

  std::string file_, dir_;
  Cell cell_;
};

}  // namespace cell_loader

using cell_loader::json;

Cell parse_cell(const std::string& json_text, const std::string& name, const std::string& dir) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::parse_error& e) {
    size_t line = 1, col = 1;
    for (size_t i = 0; i + 1 < e.byte && i < json_text.size(); ++i) {
      if (json_text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw CellError(name, "", "not valid JSON at line " + std::to_string(line) + ", column " + std::to_string(col));
  }
  return cell_loader::Loader(name, dir).load(j);
}

Cell load_cell_file(const std::string& path) {
  bool ok = false;
  const std::string text = cell_loader::read_file(path, ok);
  if (!ok || std::filesystem::is_directory(path))
    throw CellError(path, "", std::filesystem::exists(path) ? "cannot be read" : "file not found");
  return parse_cell(text, path, std::filesystem::path(path).parent_path().string());
}

std::string resolve_cell_path(const std::string& name_or_path) {
  if (name_or_path.find('/') != std::string::npos || name_or_path.find('.') != std::string::npos) return name_or_path;
  const char* env = std::getenv("ARTICULA_CELLS");
  const std::string dir = env && *env ? env : ARTICULA_CELLS_DIR;
  return dir + "/" + name_or_path + ".json";
}

bool is_cell_reference(const std::string& ref) {
  namespace fs = std::filesystem;
  const bool path = ref.find('/') != std::string::npos || ref.find('.') != std::string::npos;
  if (!path) return fs::exists(resolve_cell_path(ref)) && !fs::exists(resolve_robot_path(ref));
  if (!fs::is_regular_file(ref)) return false;
  bool ok = false;
  const std::string text = cell_loader::read_file(ref, ok);
  const json j = json::parse(text, nullptr, false);
  return ok && j.is_object() && j.contains("arms");
}

std::string cell_arm_names(const Cell& cell) { return cell_loader::names_of(cell); }

int cell_arm_index(const Cell& cell, const std::string& arm) {
  const int a = cell.arm_index(arm);
  if (a < 0)
    throw std::invalid_argument("the cell " + cell_loader::in_quotes(cell.name) + " has no arm " + cell_loader::in_quotes(arm) + " (its arms: " +
                                cell_loader::names_of(cell) + ")");
  return a;
}

void set_cell_program(Cell& cell, const std::string& arm, const Program& program) {
  const int a = cell_arm_index(cell, arm);
  cell.arms[size_t(a)].program = program;
  cell.arms[size_t(a)].program_ref = program.source;
}

}  // namespace articula::host
