// host/physics/scene.cpp - reads a scene file (scenes/README.md): every field checked, every
// error naming the file and the JSON pointer of the value at fault, as robot files do.
#include "scene.h"

#include "robot_file.h"
#include "world_detail.h"

#include <cstdlib>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace articula::host {

SceneError::SceneError(const std::string& file, const std::string& json_path, const std::string& problem)
    : std::runtime_error(file + ": " + (json_path.empty() ? std::string() : json_path + ": ") + problem),
      json_path_(json_path),
      problem_(problem) {}

double SceneObject::volume_m3() const {
  const double k = 1e-9;  // mm^3 -> m^3
  switch (type) {
    case Type::kBox: return size[0] * size[1] * size[2] * k;
    case Type::kCylinder: return M_PI * size[0] * size[0] * size[1] * k;
    case Type::kSphere: return 4.0 / 3.0 * M_PI * size[0] * size[0] * size[0] * k;
  }
  return 0;
}

Mat3<double> SceneObject::rotation() const {
  constexpr double k = M_PI / 180;
  return rpy_to_matrix(rpy_deg.x * k, rpy_deg.y * k, rpy_deg.z * k);
}

const std::map<std::string, std::vector<std::string>>& scene_file_fields() {
  static const std::map<std::string, std::vector<std::string>> fields = {
      {"scene", {"$schema", "name", "description", "sized_for", "gravity", "ground", "world_box", "objects"}},
      {"ground", {"friction"}},
      {"world_box", {"min", "max"}},
      {"object", {"name", "type", "size", "xyz", "rpy", "movable", "mass", "density", "friction", "belt"}},
  };
  return fields;
}

namespace {

using json = nlohmann::json;

std::string num(double v) { return file_number(v); }  // (robot_file.h: one writer for both files)

class Loader {
 public:
  Loader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw SceneError(file_, path, problem);
  }

  void check_fields(const json& j, const std::string& path, const std::string& kind) const {
    if (!j.is_object()) fail(path, "must be an object");
    const auto& allowed = scene_file_fields().at(kind);
    for (const auto& item : j.items()) {
      bool ok = false;
      for (const auto& a : allowed) ok = ok || a == item.key();
      if (!ok) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(path + "/" + item.key(), "unknown field \"" + item.key() + "\" (expected one of: " + list + ")");
      }
    }
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "must be finite");
    return v;
  }

  double positive(const json& j, const std::string& path) const {
    const double v = number(j, path);
    if (!(v > 0)) fail(path, "must be > 0 (got " + num(v) + ")");
    return v;
  }

  double non_negative(const json& j, const std::string& path) const {
    const double v = number(j, path);
    if (v < 0) fail(path, "must be >= 0 (got " + num(v) + ")");
    return v;
  }

  Vec3<double> vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, "must be an array of 3 numbers");
    return make_vec3(number(j[0], path + "/0"), number(j[1], path + "/1"), number(j[2], path + "/2"));
  }

  std::string text(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "must be a string");
    return j.get<std::string>();
  }

  SceneObject object(const json& j, const std::string& path, size_t index) const {
    check_fields(j, path, "object");
    SceneObject o;
    o.name = j.contains("name") ? text(j["name"], path + "/name") : "object " + std::to_string(index);
    if (o.name.empty()) fail(path + "/name", "must not be empty");
    if (!j.contains("type")) fail(path, "missing field \"type\" (box, cylinder or sphere)");
    const std::string type = text(j["type"], path + "/type");
    size_t n = 0;
    if (type == "box") {
      o.type = SceneObject::Type::kBox, n = 3;
    } else if (type == "cylinder") {
      o.type = SceneObject::Type::kCylinder, n = 2;
    } else if (type == "sphere") {
      o.type = SceneObject::Type::kSphere, n = 1;
    } else if (type == "capsule" || type == "mesh") {
      fail(path + "/type", "\"" + type + "\" is not supported in scenes (box, cylinder or sphere)");
    } else {
      fail(path + "/type", "unknown type \"" + type + "\" (box, cylinder or sphere)");
    }
    if (!j.contains("size")) fail(path, "missing field \"size\"");
    const json& s = j["size"];
    const std::string sp = path + "/size";
    if (!s.is_array() || s.size() != n)
      fail(sp, "a " + type + " takes " + std::to_string(n) + " size number" + (n > 1 ? "s" : "") +
                   (n == 3 ? " [x, y, z]" : n == 2 ? " [radius, length]" : " [radius]"));
    for (size_t i = 0; i < n; ++i) o.size[i] = positive(s[i], sp + "/" + std::to_string(i));
    if (j.contains("xyz")) o.xyz = vec3(j["xyz"], path + "/xyz");
    if (j.contains("rpy")) o.rpy_deg = vec3(j["rpy"], path + "/rpy");
    if (j.contains("movable")) {
      if (!j["movable"].is_boolean()) fail(path + "/movable", "must be true or false");
      o.movable = j["movable"].get<bool>();
    }
    if (j.contains("mass") && j.contains("density")) fail(path + "/density", "give mass or density, not both");
    if (j.contains("mass")) o.mass = positive(j["mass"], path + "/mass");
    if (j.contains("density")) o.density = positive(j["density"], path + "/density");
    if (!o.movable && (j.contains("mass") || j.contains("density")))
      fail(path + (j.contains("mass") ? "/mass" : "/density"), "a static object has no mass (set \"movable\": true)");
    if (o.movable && o.mass == 0 && o.density == 0) o.density = 700;  // wood, the thesis's blocks
    if (o.movable && !(o.mass_kg() >= 1e-5 && o.mass_kg() <= 100))
      fail(path + (j.contains("mass") ? "/mass" : "/density"),
           "mass " + num(o.mass_kg()) + " kg is outside 0.00001 .. 100 kg (the arm's world)");
    if (j.contains("friction")) o.friction = non_negative(j["friction"], path + "/friction");
    if (j.contains("belt")) {
      o.belt = number(j["belt"], path + "/belt");
      if (o.movable || o.type != SceneObject::Type::kBox) fail(path + "/belt", "a belt is a static box (its top face moves)");
      if (std::fabs(o.belt) > 1000) fail(path + "/belt", "a belt runs at most 1000 mm/s either way (got " + num(o.belt) + ")");
    }
    return o;
  }

  Scene scene(const json& j) const {
    check_fields(j, "", "scene");
    Scene sc;
    sc.source = file_;
    if (j.contains("name")) sc.name = text(j["name"], "/name");
    if (j.contains("description")) sc.description = text(j["description"], "/description");
    if (j.contains("sized_for")) {
      const json& f = j["sized_for"];
      if (!f.is_array()) fail("/sized_for", "must be an array of robot names");
      for (size_t k = 0; k < f.size(); ++k) sc.sized_for.push_back(text(f[k], "/sized_for/" + std::to_string(k)));
    }
    if (j.contains("gravity")) sc.gravity = vec3(j["gravity"], "/gravity");
    if (j.contains("ground")) {
      const json& g = j["ground"];
      if (g.is_boolean()) {
        sc.ground = g.get<bool>();
      } else {
        check_fields(g, "/ground", "ground");
        sc.ground = true;
        if (g.contains("friction")) sc.ground_friction = non_negative(g["friction"], "/ground/friction");
      }
    }
    if (j.contains("world_box")) {
      const json& b = j["world_box"];
      check_fields(b, "/world_box", "world_box");
      if (!b.contains("min") || !b.contains("max")) fail("/world_box", "needs both \"min\" and \"max\"");
      sc.world_min = vec3(b["min"], "/world_box/min");
      sc.world_max = vec3(b["max"], "/world_box/max");
      if (!(sc.world_min.x < sc.world_max.x && sc.world_min.y < sc.world_max.y && sc.world_min.z < sc.world_max.z))
        fail("/world_box", "min must be below max on every axis");
    }
    if (j.contains("objects")) {
      const json& objs = j["objects"];
      if (!objs.is_array()) fail("/objects", "must be an array");
      // (a class's table holds tens; each object is tried against every other at the start)
      if (objs.size() > kMaxSceneObjects)
        fail("/objects", "a scene holds at most " + std::to_string(kMaxSceneObjects) + " objects (got " + std::to_string(objs.size()) + ")");
      std::set<std::string> names;
      for (size_t i = 0; i < objs.size(); ++i) {
        const std::string p = "/objects/" + std::to_string(i);
        sc.objects.push_back(object(objs[i], p, i));
        if (!names.insert(sc.objects.back().name).second)
          fail(p + "/name", "duplicate name \"" + sc.objects.back().name + "\"");
      }
    }
    for (size_t i = 0; i < sc.objects.size(); ++i) {
      const Vec3<double>& c = sc.objects[i].xyz;
      if (c.x < sc.world_min.x || c.y < sc.world_min.y || c.z < sc.world_min.z || c.x > sc.world_max.x ||
          c.y > sc.world_max.y || c.z > sc.world_max.z)
        fail("/objects/" + std::to_string(i) + "/xyz", "outside the world box");
    }
    return sc;
  }

 private:
  std::string file_;
};

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& name) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::parse_error& e) {
    // nlohmann's byte offset -> line and column.
    size_t line = 1, col = 1;
    for (size_t i = 0; i + 1 < e.byte && i < json_text.size(); ++i) {
      if (json_text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw SceneError(name, "", "not valid JSON at line " + std::to_string(line) + ", column " + std::to_string(col));
  }
  Scene scene = Loader(name).scene(j);
  const SceneOverlap o = first_overlap(scene);
  if (o.object >= 0) throw SceneError(name, "/objects/" + std::to_string(o.object), o.problem);
  return scene;
}

Scene scene_from_json(const nlohmann::json& j, const std::string& name) { return Loader(name).scene(j); }

SceneOverlap first_overlap(const Scene& scene, const std::vector<int>& left_out) {
  detail::init_ode();
  // (collision only, so in the file's mm: a depth comes out in mm)
  std::vector<dGeomID> g(scene.objects.size(), nullptr);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (std::find(left_out.begin(), left_out.end(), int(i)) != left_out.end()) continue;
    const SceneObject& o = scene.objects[i];
    switch (o.type) {
      case SceneObject::Type::kBox: g[i] = dCreateBox(nullptr, o.size[0], o.size[1], o.size[2]); break;
      case SceneObject::Type::kCylinder: g[i] = dCreateCylinder(nullptr, o.size[0], o.size[1]); break;
      case SceneObject::Type::kSphere: g[i] = dCreateSphere(nullptr, o.size[0]); break;
    }
    dMatrix3 R;
    detail::to_ode(o.rotation(), R);
    dGeomSetPosition(g[i], o.xyz.x, o.xyz.y, o.xyz.z);
    dGeomSetRotation(g[i], R);
  }
  dGeomID ground = scene.ground ? dCreatePlane(nullptr, 0, 0, 1, 0) : nullptr;
  auto depth = [](dGeomID a, dGeomID b) {
    dContactGeom c[8];
    const int n = dCollide(a, b, 8, c, sizeof(dContactGeom));
    double d = 0;
    for (int k = 0; k < n; ++k) d = std::max(d, double(c[k].depth));
    return d;
  };
  auto mm = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return std::string(buf);
  };
  SceneOverlap out;
  for (size_t j = 0; j < g.size() && out.object < 0; ++j) {
    if (!g[j]) continue;
    const SceneObject& b = scene.objects[j];
    if (b.movable && ground) {
      const double d = depth(g[j], ground);
      if (d > 0.5)
        out = {int(j), "\"" + b.name + "\" is sunk " + mm(d) + " mm into the ground at the start: raise it (its lowest point at z = 0 or above)"};
    }
    for (size_t i = 0; i < j && out.object < 0; ++i) {
      if (!g[i] || (!b.movable && !scene.objects[i].movable)) continue;
      const double d = depth(g[i], g[j]);
      if (d > 0.5)
        out = {int(j), "\"" + b.name + "\" stands " + mm(d) + " mm inside \"" + scene.objects[i].name + "\" (/objects/" +
                           std::to_string(i) + ") at the start: move one of them"};
    }
  }
  for (dGeomID x : g)
    if (x) dGeomDestroy(x);
  if (ground) dGeomDestroy(ground);
  return out;
}

Scene load_scene_file(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw SceneError(path, "", std::filesystem::exists(path) ? "cannot be read" : "file not found");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_scene(ss.str(), path);
}

std::string resolve_scene_path(const std::string& name_or_path) {
  if (name_or_path.find('/') != std::string::npos || name_or_path.find('.') != std::string::npos)
    return name_or_path;
  const char* env = std::getenv("ARTICULA_SCENES");
  const std::string dir = env && *env ? env : ARTICULA_SCENES_DIR;
  return dir + "/" + name_or_path + ".json";
}

}  // namespace articula::host
