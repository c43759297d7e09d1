// wasm/src/robot.h - a robot for JavaScript: the robot file loaded, its IK prepared on first
// use, what an import left out; its description, poses, IK, motors and hot paths (robot.cpp
// binds it; program.cpp and sim.cpp take it).
#ifndef ARTICULA_WASM_ROBOT_H
#define ARTICULA_WASM_ROBOT_H

#include <algorithm>
#include <cstdint>
#include <memory>

#include "blocks.h"
#include "common.h"
#include "geometry.h"
#include "ik.h"
#include "legacy.h"
#include "nano_config.h"
#include "records_json.h"
#include "robot.h"
#include "urdf.h"
#include "wiring.h"

namespace articula::web {

using host::HostFrames;

constexpr size_t kScratch = 1024;  // doubles of the hot paths' scratch array
constexpr size_t kOut = 64;        // where results start in it (joint values and targets before)

// A robot: the robot file loaded, its IK prepared on first use, what an import left out.
class WebRobot {
 public:
  // Loaders: "" when the robot is loaded, else the error as JSON text ({"error", "file",
  // "json_path", "problem"}). A failed load keeps the robot that was there.
  std::string load(const std::string& path) {
    return adopt([&] { return host::load_robot_file(host::resolve_robot_path(path)); }, {});
  }
  std::string parse(const std::string& text, const std::string& name) {
    return adopt([&] { return host::parse_robot(text, name); }, {});
  }
  std::string from_legacy(const std::string& text, const std::string& name, double scale) {
    if (!(scale > 0) || !std::isfinite(scale)) return error_json("scale (mm per unit) must be > 0");
    std::vector<std::string> notes;
    return adopt(
        [&] {
          const host::LegacyImport imp = host::import_legacy(text, name, scale);
          notes = imp.dropped;
          return host::parse_robot(imp.robot.dump(), name);
        },
        notes);
  }
  // RoboSim's l: other lengths a(i-1) for the adjustable rows, in row order.
  std::string set_link_lengths(const std::string& values) {
    return adopt([&] { return host::with_link_lengths(*robot_, finite_numbers(json::parse(values), "lengths")); },
                 notes_);
  }

  bool loaded() const { return robot_ != nullptr; }

  // The robot as the studio draws and describes it.
  std::string info() const {
    return guarded([&] {
      const Robot& r = *robot_;
      return json{{"name", r.name},
                  {"description", r.description},
                  {"source", r.source},
                  {"num_rows", r.model.num_rows},
                  {"num_joints", r.model.num_joints},
                  {"num_motors", r.has_motors ? int(r.actuation.num_motors) : 0},
                  {"joint_names", r.joint_names},
                  {"motor_names", r.motor_names},
                  {"joints", host::joints_json(r)},
                  {"dh", host::dh_rows_json(r)},
                  {"home", host::home_pose(r)},
                  {"limits", host::joint_limits(r)},
                  {"motors", host::motors_json(r)},
                  {"links", host::links_json(r)},
                  {"gripper", host::gripper_json(r)},
                  {"wiring", host::wiring_json(r)},
                  {"tool_offset", host::transform_json(r.model.T_last_tool)},
                  {"reach_mm", ik().reach_bound()},
                  {"places", host::example_places_json(r, ik())},
                  {"import_notes", notes_}}
          .dump();
    });
  }

  // The Nano's robot configuration for this robot (host/lib/nano_config.h): {name, checksum,
  // lines, has_point}, or {"error"} with the reason a Nano cannot drive it.
  std::string nano_config() const {
    return guarded([&] { return host::nano_config_json(host::nano_config(*robot_)).dump(); });
  }

  // Everything a drawing of the arm at q (deg or mm) needs, in one crossing: every frame
  // (base, rows, tool; 16 numbers each), the tool's position and rpy, the DH table at q,
  // whether q is within the limits, and with a gripper opened opening_mm, its two fingers.
  std::string pose(const std::string& q_json, double opening_mm) const {
    return guarded([&] {
      const Robot& r = *robot_;
      const std::vector<double> q = model_joints(json::parse(q_json), "q");
      HostFrames f;
      forward_kinematics(f, r.model, q.data());
      const Vec3<double> rpy = matrix_to_rpy(f.T_base_tool.R);
      json out = {{"frames", host::frames_json(r, f)},
                  {"tool", {{"xyz", {f.T_base_tool.p.x, f.T_base_tool.p.y, f.T_base_tool.p.z}},
                            {"rpy", {rad_to_deg(rpy.x), rad_to_deg(rpy.y), rad_to_deg(rpy.z)}}}},
                  {"dh_table", host::dh_table_at(r, q.data())},
                  {"within_limits", host::within_limits(ik(), r, q)}};
      if (r.gripper.present && std::isfinite(opening_mm))
        out["fingers"] = {host::transform_json(host::finger_pose(r.gripper, f.T_base_tool, opening_mm, +1)),
                          host::transform_json(host::finger_pose(r.gripper, f.T_base_tool, opening_mm, -1))};
      return out.dump();
    });
  }

  // The Jacobian of the tool point at q: 6 rows of num_joints, per deg or mm of q.
  std::string jacobian(const std::string& q_json) const {
    return guarded([&] {
      const std::vector<double> q = model_joints(json::parse(q_json), "q");
      const std::vector<double> J = host::jacobian_at(*robot_, q.data());
      const size_t n = q.size();
      json out = json::array();
      for (size_t k = 0; k < 6; ++k) out.push_back(std::vector<double>(J.begin() + long(k * n), J.begin() + long((k + 1) * n)));
      return out.dump();
    });
  }

  // IK (docs/ik.md): {"target": [x,y,z(,roll,pitch,yaw)], "solver", "start", "weights",
  // "max_iterations", "tolerance_mm", "seed"} -> `articula ik --json`'s result, plus
  // beyond_reach.
  std::string ik_solve(const std::string& args_json) const {
    return guarded([&] {
      const Robot& r = *robot_;
      const json a = json::parse(args_json);
      const std::vector<double> t = numbers(a.at("target"), "target");
      const host::IkTarget target = host::ik_target(t.data(), t.size());
      std::vector<double> weights;
      const bool weighted = a.contains("weights") && !a["weights"].is_null();
      if (weighted) weights = numbers(a["weights"], "weights");
      const host::IkOptions o = host::ik_options(a.value("solver", "auto"), weighted ? &weights : nullptr,
                                                 a.value("tolerance_mm", 0.01), a.value("max_iterations", 0),
                                                 a.value("seed", uint64_t(1)));
      std::vector<double> start;
      const bool started = a.contains("start") && !a["start"].is_null();
      if (started) start = numbers(a["start"], "start");
      const std::vector<double> q0 = host::ik_start(r, started ? &start : nullptr);
      const host::IkResult res = ik().solve(target, q0, o);
      json j = host::ik_result_json(r, res);
      j["beyond_reach"] = res.beyond_reach;
      return j.dump();
    });
  }

  std::string urdf() const {
    return guarded([&] { return json{{"xml", host::export_urdf(*robot_).xml}}.dump(); });
  }

  // q = C u and u = C^-1 q: joint variables (deg or mm) from motor angles (deg) and back.
  std::string joints_from_motors(const std::string& u_json) const {
    return guarded([&] { return json(host::joints_from_motors(*robot_, numbers(json::parse(u_json), "motor angles"))).dump(); });
  }
  std::string motors_from_joints(const std::string& q_json) const {
    return guarded([&] {
      const Robot& r = *robot_;
      return json(host::motors_from_joints(r, model_joints(json::parse(q_json), "q"))).dump();
    });
  }

  // ---- the hot paths, on the scratch array (scratch(): its address in the heap, in bytes)

  uintptr_t scratch() const { return reinterpret_cast<uintptr_t>(scratch_.data()); }
  // The tool pose at the joint values in scratch[0..n) (model units: rad or mm), into
  // scratch[64..80) as a row-major 4x4.
  void fk_scratch() const {
    HostFrames f;
    forward_kinematics(f, robot_->model, scratch_.data());
    const Transform<double>& T = f.T_base_tool;
    double* out = scratch_.data() + kOut;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) out[4 * i + k] = T.R.m[i][k];
      out[4 * i + 3] = T.p[i];
    }
    out[12] = out[13] = out[14] = 0;
    out[15] = 1;
  }
  // IK from the start in scratch[0..n) to the target in scratch[32..32+len) (mm; rpy in rad
  // when len is 6), solver 0 auto, 1 closed, 2 lm, 3 jt: q into scratch[64..64+n), the
  // position error into scratch[63]; returns the status (0 reached ... 3 budget).
  int ik_scratch(int len, int solver) const {
    const double* t = scratch_.data() + 32;
    host::IkTarget target = host::IkTarget::at(make_vec3(t[0], t[1], t[2]));
    if (len == 6) {
      target.has_rotation = true;
      target.rotation = rpy_to_matrix(t[3], t[4], t[5]);
    }
    host::IkOptions o;
    static const host::IkMethod kMethods[] = {host::IkMethod::kAuto, host::IkMethod::kClosedForm, host::IkMethod::kLevenbergMarquardt,
                                              host::IkMethod::kJacobianTranspose};
    o.method = kMethods[solver & 3];
    const size_t n = size_t(robot_->model.num_joints);
    const std::vector<double> q0(scratch_.data(), scratch_.data() + n);
    const host::IkResult res = ik().solve(target, q0, o);
    std::copy(res.q.begin(), res.q.end(), scratch_.data() + kOut);
    scratch_[kOut - 1] = res.position_error_mm;
    return int(res.status);
  }

  std::shared_ptr<const Robot> shared() const { return robot_; }
  const Robot& robot() const { return *robot_; }
  // Its IK, prepared on first use.
  const host::InverseKinematics& ik() const {
    if (!ik_) ik_ = std::make_shared<const host::InverseKinematics>(*robot_);
    return *ik_;
  }

 private:
  template <typename F>
  std::string adopt(F&& make, const std::vector<std::string>& notes) {
    std::string err = guarded([&] {
      auto r = std::make_shared<const Robot>(make());
      robot_ = std::move(r);
      ik_.reset();
      return std::string();
    });
    if (err.empty()) notes_ = notes;
    return err;
  }

  // Joint values (deg or mm, one per joint variable) into model units, checked.
  std::vector<double> model_joints(const json& j, const char* what) const {
    return host::joints_in(*robot_, numbers(j, what), what);
  }

  std::shared_ptr<const Robot> robot_;
  std::vector<std::string> notes_;
  mutable std::shared_ptr<const host::InverseKinematics> ik_;
  mutable std::vector<double> scratch_ = std::vector<double>(kScratch, 0.0);
};

}  // namespace articula::web

#endif  // ARTICULA_WASM_ROBOT_H
