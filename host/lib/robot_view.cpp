#include "robot_view.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "geometry.h"

namespace articula::host {
namespace {

const char* param_name(uint8_t p) { return p == kParamTheta ? "theta" : (p == kParamD ? "d" : "alpha"); }
double param_out(uint8_t p, double v) { return p != kParamD ? rad_to_deg(v) : v; }

nlohmann::json flat(const Transform<double>& T) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) out.push_back(T.R.m[i][k]);
    out.push_back(T.p[i]);
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) out.push_back(v);
  return out;
}

}  // namespace

nlohmann::json dh_rows_json(const Robot& r) {
  const auto& m = r.model;
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < m.num_rows; ++i) {
    nlohmann::json row = {{"a", m.rows[i].a},
                          {"alpha", rad_to_deg(m.rows[i].alpha)},
                          {"d", m.rows[i].d},
                          {"theta", rad_to_deg(m.rows[i].theta)}};
    if (size_t(i) < r.length_ranges.size() && r.length_ranges[size_t(i)].adjustable)
      row["a"] = {{"value", m.rows[i].a}, {"min", r.length_ranges[size_t(i)].min}, {"max", r.length_ranges[size_t(i)].max}};
    for (int j = 0; j < m.num_joints; ++j) {
      if (m.joints[j].row != i) continue;
      row[param_name(m.joints[j].param)] = {{"joint", r.joint_names[size_t(j)]},
                                            {"min", param_out(m.joints[j].param, m.joints[j].lo)},
                                            {"max", param_out(m.joints[j].param, m.joints[j].hi)}};
    }
    for (int k = 0; k < m.num_linked; ++k) {
      const auto& l = m.linked[k];
      if (l.row != i) continue;
      nlohmann::json gains = nlohmann::json::object();
      for (int j = 0; j < m.num_joints; ++j)
        if (l.gain[j] != 0) gains[r.joint_names[size_t(j)]] = l.gain[j];
      row[param_name(l.param)] = {{"linked", gains}, {"offset", param_out(l.param, l.offset)}};
    }
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json joints_json(const Robot& r) {
  nlohmann::json out = nlohmann::json::array();
  for (int j = 0; j < r.model.num_joints; ++j) {
    const auto& js = r.model.joints[j];
    out.push_back({{"name", r.joint_names[size_t(j)]},
                   {"row", int(js.row) + 1},
                   {"param", param_name(js.param)},
                   {"unit", joint_unit(r, j)},
                   {"min", param_out(js.param, js.lo)},
                   {"max", param_out(js.param, js.hi)}});
  }
  return out;
}

nlohmann::json motors_json(const Robot& r) {
  nlohmann::json out = nlohmann::json::array();
  if (!r.has_motors) return out;
  for (int i = 0; i < r.actuation.num_motors; ++i) {
    const MotorSpec& s = r.actuation.motors[i];
    nlohmann::json curve = nlohmann::json::array();
    if (size_t(i) < r.motor_torque.size())
      for (const auto& pt : r.motor_torque[size_t(i)].pull_out) curve.push_back({pt[0], pt[1]});
    out.push_back({{"name", r.motor_names[size_t(i)]},
                   {"steps_per_rev", int(s.full_steps_per_rev)},
                   {"microsteps", int(s.microsteps)},
                   {"gear", {s.gear_num, s.gear_den}},
                   {"direction", int(s.direction)},
                   {"zero", s.zero / 1000.0},
                   {"min", s.min / 1000.0},
                   {"max", s.max / 1000.0},
                   {"deg_per_step", degrees_per_step<double>(s)},
                   {"step_range", {min_steps(s), max_steps(s)}},
                   {"pull_out", curve}});
  }
  return out;
}

nlohmann::json gripper_json(const Robot& r) {
  const Gripper& g = r.gripper;
  if (!g.present) return nullptr;
  return {{"max_opening_mm", g.max_opening_mm},       {"finger_length_mm", g.finger_length_mm},
          {"finger_thickness_mm", g.finger_thickness_mm}, {"finger_height_mm", g.finger_height_mm},
          {"servo_open_deg", g.servo_open_deg},       {"servo_closed_deg", g.servo_closed_deg}};
}

nlohmann::json links_json(const Robot& r) {
  static const char* kTypes[] = {"box", "cylinder", "capsule", "sphere", "mesh"};
  nlohmann::json out = nlohmann::json::array();
  for (const auto& l : arm_geometry(r)) {
    nlohmann::json shapes = nlohmann::json::array();
    for (const auto& s : l.shapes) {
      nlohmann::json d = {{"type", kTypes[int(s.type)]},
                          {"size", {s.size[0], s.size[1], s.size[2]}},
                          {"pose", flat(s.T_frame_shape)},
                          {"mass", s.mass},
                          {"density", s.density}};
      if (s.type == Shape::Type::kMesh) d["mesh"] = mesh_path(r, s);
      shapes.push_back(d);
    }
    out.push_back({{"frame", l.frame}, {"shapes", shapes}});
  }
  return out;
}

Robot with_link_lengths(const Robot& r, const std::vector<double>& values) {
  std::vector<int> rows;
  for (size_t i = 0; i < r.length_ranges.size(); ++i)
    if (r.length_ranges[i].adjustable) rows.push_back(int(i));
  if (values.size() != rows.size())
    throw std::invalid_argument(r.name + " has " + std::to_string(rows.size()) +
                                " adjustable link length(s) (rows with an 'a' range); " + std::to_string(values.size()) +
                                " given");
  for (size_t k = 0; k < values.size(); ++k) {
    const LengthRange& lr = r.length_ranges[size_t(rows[k])];
    if (!(values[k] >= lr.min && values[k] <= lr.max)) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "a of row %d: %g mm is outside its range %g .. %g mm", rows[k] + 1, values[k],
                    lr.min, lr.max);
      throw std::invalid_argument(buf);
    }
  }
  Robot copy = r;
  set_link_lengths(copy, values);
  return copy;
}

bool within_limits(const InverseKinematics& ik, const Robot& r, std::vector<double> q) {
  const auto& m = r.model;
  for (int j = 0; j < m.num_joints && size_t(j) < q.size(); ++j) {
    double& v = q[size_t(j)];
    const double slack = 1e-9 * std::max(1.0, std::fabs(v));
    if (v < m.joints[j].lo && v > m.joints[j].lo - slack) v = m.joints[j].lo;
    if (v > m.joints[j].hi && v < m.joints[j].hi + slack) v = m.joints[j].hi;
  }
  return ik.within_all_limits(q);
}

}  // namespace articula::host
