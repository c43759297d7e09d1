#include "robot_view.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "board.h"
#include "geometry.h"
#include "robot_file.h"

namespace articula::host {
namespace {

const char* param_name(uint8_t p) { return p == kParamTheta ? "theta" : (p == kParamD ? "d" : "alpha"); }
double param_out(uint8_t p, double v) { return p != kParamD ? rad_to_deg(v) : v; }

}  // namespace

nlohmann::json transform_json(const Transform<double>& T) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) out.push_back(T.R.m[i][k]);
    out.push_back(T.p[i]);
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) out.push_back(v);
  return out;
}

nlohmann::json frames_json(const Robot& r, const HostFrames& f) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i <= r.model.num_rows; ++i) out.push_back(transform_json(f.T_base_frame[i]));
  out.push_back(transform_json(f.T_base_tool));
  return out;
}

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

namespace {
// A motor's "driver" as the robot file gives it (robots/README.md, "Drive"), defaults filled in.
nlohmann::json driver_json(const Robot& r, int motor) {
  const MotorDriver d = size_t(motor) < r.drive.motors.size() ? r.drive.motors[size_t(motor)] : MotorDriver{};
  nlohmann::json j = {{"kind", kDriveKindInfo[d.kind].id}};
  if (d.kind == kDriveStepDir) j["chip"] = kStepDirChip[d.chip].id;
  if (d.kind == kDriveServo) {
    j["pin"] = board::kHeaderPin[d.pin].pin;
    j["pulse"] = {d.pulse_min_us, d.pulse_max_us};
    j["at"] = {{d.at[0][0], d.at[0][1]}, {d.at[1][0], d.at[1][1]}};
    j["speed"] = d.speed_deg_s;
    if (d.accel_deg_s2 > 0) j["accel"] = d.accel_deg_s2;
    j["deadband"] = d.deadband_us;
    j["top_speed"] = d.top_speed_deg_s;
  }
  return j;
}
}  // namespace

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
                   {"pull_out", curve},
                   {"driver", driver_json(r, i)}});
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
                          {"pose", transform_json(s.T_frame_shape)},
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

// ---- units and checks

namespace articula::host {
namespace {

std::string joint_list(const Robot& r) {
  std::string s;
  for (size_t j = 0; j < r.joint_names.size(); ++j) s += (j ? ", " : "") + r.joint_names[j];
  return s;
}

const char* not_finite(double v) { return std::isnan(v) ? "NaN" : "infinite"; }

void need_motors(const Robot& r) {
  if (!r.has_motors) throw std::invalid_argument(r.name + " has no motors");
}

}  // namespace

void joints_in(const Robot& r, const double* values, size_t count, const char* what, double* q) {
  const size_t n = size_t(r.model.num_joints);
  if (count != n)
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(count) + " value" + (count == 1 ? "" : "s") +
                                "; " + r.name + " has " + std::to_string(n) + " joint variables (" + joint_list(r) + ")");
  for (size_t j = 0; j < n; ++j) {
    if (!std::isfinite(values[j]))
      throw std::invalid_argument(std::string(what) + "[" + std::to_string(j) + "] (" + r.joint_names[j] + ") is " +
                                  not_finite(values[j]) + ": joint values must be finite numbers");
    q[j] = joint_to_model(r, int(j), values[j]);
  }
}

std::vector<double> joints_in(const Robot& r, const double* values, size_t count, const char* what) {
  std::vector<double> q(size_t(r.model.num_joints));
  joints_in(r, values, count, what, q.data());
  return q;
}

std::vector<double> joints_out(const Robot& r, const double* q_model) {
  std::vector<double> out(size_t(r.model.num_joints));
  for (int j = 0; j < r.model.num_joints; ++j) out[size_t(j)] = joint_from_model(r, j, q_model[j]);
  return out;
}

void check_finite(const double* values, size_t count, const char* what) {
  for (size_t i = 0; i < count; ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument(std::string(what) + "[" + std::to_string(i) + "] is " + not_finite(values[i]) +
                                  ": values must be finite numbers");
}

std::vector<std::array<double, 2>> joint_limits(const Robot& r) {
  std::vector<std::array<double, 2>> out;
  for (int j = 0; j < r.model.num_joints; ++j)
    out.push_back({joint_from_model(r, j, r.model.joints[j].lo), joint_from_model(r, j, r.model.joints[j].hi)});
  return out;
}

std::vector<double> home_pose(const Robot& r) {
  std::vector<double> out;
  for (int j = 0; j < r.model.num_joints; ++j)
    out.push_back(size_t(j) < r.home.size() ? joint_from_model(r, j, r.home[size_t(j)]) : 0.0);
  return out;
}

std::vector<double> power_up_pose(const Robot& r) {
  if (!r.has_motors) return home_pose(r);
  std::vector<double> zeros;
  for (int k = 0; k < r.actuation.num_motors; ++k) zeros.push_back(r.actuation.motors[k].zero / 1000.0);
  return joints_from_motors(r, zeros);
}

std::vector<double> joints_from_motors(const Robot& r, const std::vector<double>& motor_deg) {
  need_motors(r);
  check_finite(motor_deg.data(), motor_deg.size(), "motor angles");
  if (motor_deg.size() != size_t(r.actuation.num_motors))
    throw std::invalid_argument("motor angles has " + std::to_string(motor_deg.size()) + " values; " + r.name + " has " +
                                std::to_string(r.actuation.num_motors) + " motors");
  double u[kMaxJoints], q[kMaxJoints];
  for (size_t i = 0; i < motor_deg.size(); ++i) u[i] = deg_to_rad(motor_deg[i]);
  joints_from_actuators(q, r.actuation, u);
  return joints_out(r, q);
}

std::vector<double> motors_from_joints(const Robot& r, const std::vector<double>& q_model) {
  need_motors(r);
  double u[kMaxJoints];
  actuators_from_joints(u, r.actuation, q_model.data());
  std::vector<double> out;
  for (int i = 0; i < r.actuation.num_motors; ++i) out.push_back(rad_to_deg(u[i]));
  return out;
}

std::vector<std::array<double, 4>> dh_table_at(const Robot& r, const double* q_model) {
  DhRow<double> table[kMaxRows];
  dh_table(table, r.model, q_model);
  std::vector<std::array<double, 4>> out;
  for (int i = 0; i < r.model.num_rows; ++i)
    out.push_back({table[i].a, rad_to_deg(table[i].alpha), table[i].d, rad_to_deg(table[i].theta)});
  return out;
}

void jacobian_at(const Robot& r, const HostFrames& f, double* out) {
  const int n = r.model.num_joints;
  double J[6][kMaxJoints];
  jacobian(J, r.model, f);
  for (int j = 0; j < n; ++j) {
    const bool angle = joint_is_angle(r, j);
    for (int k = 0; k < 3; ++k) out[k * n + j] = J[k][j] * (angle ? M_PI / 180 : 1.0);
    for (int k = 3; k < 6; ++k) out[k * n + j] = J[k][j] * (angle ? 1.0 : 180 / M_PI);
  }
}

std::vector<double> jacobian_at(const Robot& r, const double* q_model) {
  HostFrames f;
  forward_kinematics(f, r.model, q_model);
  std::vector<double> out(size_t(6 * r.model.num_joints));
  jacobian_at(r, f, out.data());
  return out;
}

// ---- IK requests

IkTarget ik_target(const double* v, size_t count) {
  if (count != 3 && count != 6)
    throw std::invalid_argument(
        "target must be a position (x, y, z) in mm, a pose (x, y, z, roll, pitch, yaw) in mm and deg, or a 4x4 "
        "homogeneous matrix");
  for (size_t i = 0; i < count; ++i)
    if (!std::isfinite(v[i])) throw std::invalid_argument("target holds a NaN or an infinity: a target must be finite");
  IkTarget t = IkTarget::at(make_vec3(v[0], v[1], v[2]));
  if (count == 6) {
    t.has_rotation = true;
    t.rotation = rpy_to_matrix(deg_to_rad(v[3]), deg_to_rad(v[4]), deg_to_rad(v[5]));
  }
  return t;
}

IkTarget ik_target_pose(const double* m) {
  for (size_t i = 0; i < 16; ++i)
    if (!std::isfinite(m[i])) throw std::invalid_argument("target holds a NaN or an infinity: a target must be finite");
  Transform<double> T;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) T.R.m[i][k] = m[4 * i + k];
    T.p[i] = m[4 * i + 3];
  }
  return IkTarget::pose(T);
}

IkOptions ik_options(const std::string& solver, const std::vector<double>* weights, double tolerance_mm,
                     int max_iterations, uint64_t seed) {
  IkOptions o;
  if (!parse_ik_method(solver, o.method))
    throw std::invalid_argument("unknown solver '" + solver + "': one of auto, closed, lm, jt");
  if (weights) {
    check_finite(weights->data(), weights->size(), "weights");
    o.weights = *weights;
  }
  if (!(tolerance_mm > 0)) throw std::invalid_argument("tolerance_mm must be > 0");
  if (max_iterations < 0) throw std::invalid_argument("max_iterations must be >= 0 (0: the solver's default)");
  o.position_tolerance_mm = tolerance_mm;
  o.max_iterations = max_iterations;
  o.seed = seed;
  return o;
}

std::vector<double> ik_start(const Robot& r, const std::vector<double>* start) {
  if (start) return joints_in(r, *start, "start");
  std::vector<double> q(size_t(r.model.num_joints), 0.0);
  for (size_t j = 0; j < q.size() && j < r.home.size(); ++j) q[j] = r.home[j];
  return q;
}

namespace {
std::string one_decimal(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", std::fabs(v) < 0.05 ? 0.0 : v);
  return buf;
}
}  // namespace

std::string ik_miss_words(const Robot& r, const IkResult& res) {
  if (res.reached()) return "";
  const std::string near = "; the nearest the tool comes is " + one_decimal(res.position_error_mm) + " mm away";
  if (res.status == IkStatus::kBudget) return "the search ran out of iterations while still coming nearer" + near;
  if (res.beyond_reach) return "it is farther than the arm is long" + near;
  if (res.status == IkStatus::kUnreachable) return "no pose of this arm comes nearer (no joint is at a limit)" + near;
  const char* deg = "\xC2\xB0";
  std::string held;
  auto add = [&](const std::string& part) { held += (held.empty() ? "" : " and ") + part; };
  for (int k : res.limited_joints) {
    bool motor_too = false;  // a motor of the joint's name (the meArm's shoulder): said once, as the motor
    for (int m : res.limited_motors) motor_too |= r.motor_names[size_t(m)] == r.joint_names[size_t(k)];
    if (motor_too) continue;
    const auto& j = r.model.joints[size_t(k)];
    const char* unit = j.param == kParamD ? " mm" : deg;
    add("the " + r.joint_names[size_t(k)] + " joint at " + one_decimal(joint_from_model(r, k, res.q[size_t(k)])) + unit +
        " (its range " + file_number(joint_from_model(r, k, j.lo)) + unit + " to " + file_number(joint_from_model(r, k, j.hi)) +
        unit + ")");
  }
  if (!res.limited_motors.empty()) {
    const std::vector<double> m = motors_from_joints(r, res.q);
    for (int k : res.limited_motors) {
      const MotorSpec& spec = r.actuation.motors[size_t(k)];
      add("the " + r.motor_names[size_t(k)] + " motor at " + one_decimal(m[size_t(k)]) + deg + " (its range " +
          file_number(spec.min / 1000.0) + deg + " to " + file_number(spec.max / 1000.0) + deg + ")");
    }
  }
  return "held back by " + (held.empty() ? std::string("a joint's range") : held) + near;
}

}  // namespace articula::host
