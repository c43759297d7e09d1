// host/lib/run.cpp - programs on the kinematic model (run.h).
#include "run.h"

#include <articula/config.h>

#include <articula/line.h>
#include <articula/protocol.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace articula::host {

namespace {

void add_note(RunRecord& r, const std::string& note) { append_note(r.note, note); }

}  // namespace

KinematicModel::KinematicModel(const Robot& robot) : robot_(robot) {
  motors_ = robot.has_motors;
  n_ = motors_ ? robot.actuation.num_motors : robot.model.num_joints;
  offset_.assign(size_t(n_), 0);
  if (motors_) {
    commanded_.clear();
    for (int i = 0; i < n_; ++i) commanded_.push_back(robot.actuation.motors[i].zero);
    q_.assign(size_t(robot.model.num_joints), 0);
    q_from_commanded();
  } else {
    q_ = robot.home;
    commanded_from_q();
  }
}

std::vector<double> KinematicModel::q_of(const int64_t* thousandths) const {
  std::vector<double> q(size_t(robot_.model.num_joints), 0.0);
  if (motors_) {
    double u[kMaxJoints];
    for (int i = 0; i < n_; ++i) u[i] = deg_to_rad(double(thousandths[i] + offset_[size_t(i)]) / 1000.0);
    joints_from_actuators(q.data(), robot_.actuation, u);
  } else {
    for (int j = 0; j < n_; ++j) q[size_t(j)] = joint_to_model(robot_, j, double(thousandths[j] + offset_[size_t(j)]) / 1000.0);
  }
  return q;
}

std::vector<int64_t> KinematicModel::thousandths_of(const double* q) const {
  std::vector<int64_t> out(size_t(n_), 0);
  if (motors_) {
    double u[kMaxJoints];
    actuators_from_joints(u, robot_.actuation, q);
    for (int i = 0; i < n_; ++i) out[size_t(i)] = std::llround(rad_to_deg(u[i]) * 1000.0) - offset_[size_t(i)];
  } else {
    for (int j = 0; j < n_; ++j) out[size_t(j)] = std::llround(joint_from_model(robot_, j, q[j]) * 1000.0) - offset_[size_t(j)];
  }
  return out;
}

void KinematicModel::q_from_commanded() { q_ = q_of(commanded_.data()); }

void KinematicModel::commanded_from_q() { commanded_ = thousandths_of(q_.data()); }

// T on the kinematic model (articula/line.h's rule, as the Nano's): each end solved by the
// robot's IK from the last end (so the pose follows on), its commanded values to the
// thousandth; the tool of commanded values by the forward kinematics. For every robot.
struct RunLineSolver {
  KinematicModel* m;
  Status solve(Millideg* out, const double* p, const Millideg* near) const {
    int64_t at[kMaxJoints];
    for (int i = 0; i < m->n_; ++i) at[i] = near[i];
    if (!m->ik_) m->ik_.emplace(m->robot_);
    IkOptions opt;
    opt.weights = m->weights_;
    IkResult res;
    try {
      res = m->ik_->solve(IkTarget::at(make_vec3(p[0], p[1], p[2])), m->q_of(at), opt);
    } catch (const std::invalid_argument&) {
      return kUnreachable;
    }
    if (!res.reached()) return kUnreachable;
    const std::vector<int64_t> t = m->thousandths_of(res.q.data());
    for (int i = 0; i < m->n_; ++i) {
      if (m->motors_ && (t[size_t(i)] < m->robot_.actuation.motors[i].min || t[size_t(i)] > m->robot_.actuation.motors[i].max))
        return kJointLimit;
      if (t[size_t(i)] < -kMaxAbsMillideg || t[size_t(i)] > kMaxAbsMillideg) return kValueOutOfRange;
      out[i] = Millideg(t[size_t(i)]);
    }
    return kOk;
  }
  void tool(double* p, const Millideg* act) const {
    int64_t t[kMaxJoints];
    for (int i = 0; i < m->n_; ++i) t[i] = act[i];
    const Vec3<double> x = tool_position(m->robot_.model, m->q_of(t).data());
    p[0] = x.x, p[1] = x.y, p[2] = x.z;
  }
};

Status KinematicModel::line(RunRecord& r, const int32_t* arg) {
  RunLineSolver solver{this};
  Millideg at[kMaxJoints] = {}, end[kMaxJoints] = {};
  for (int i = 0; i < n_; ++i) at[i] = Millideg(commanded_[size_t(i)]);
  double from[3];
  solver.tool(from, at);
  const double to[3] = {arg[0] / 1000.0, arg[1] / 1000.0, arg[2] / 1000.0};
  const double tol = settings_.value[ControllerSettings::kChord] / 1000.0;
  LineCutter<double, kMaxJoints> cut;
  cut.start(from, to, at, uint8_t(n_), tol);
  while (!cut.done()) {
    const Status s = cut.next(solver, end);
    if (s == kOk) continue;
    const double f = cut.refused_fraction();
    add_note(r, std::string(s == kLineNotFollowed ? "the pose would jump" : s == kJointLimit ? "beyond a joint limit"
                                                                                              : "cannot be reached") +
                    " at " + number_text(std::round(f * cut.length() * 10) / 10) + " mm along the line of " +
                    number_text(std::round(cut.length() * 10) / 10) + " mm; nothing moves");
    return s;
  }
  cut.start(from, to, at, uint8_t(n_), tol);
  r.line_length_mm = cut.length();
  r.line_speed = arg[3] / 1000.0;
  double along = 0;
  std::vector<int64_t> last(commanded_);
  while (!cut.done()) {
    cut.next(solver, end);
    along += cut.segment_length();
    for (int i = 0; i < n_; ++i) last[size_t(i)] = end[i];
    const std::vector<double> q = q_of(last.data());
    std::vector<double> joints;
    for (int j = 0; j < robot_.model.num_joints; ++j) joints.push_back(joint_from_model(robot_, j, q[size_t(j)]));
    r.via_joints.push_back(std::move(joints));
    r.via_mm.push_back(along);
  }
  add_note(r, std::to_string(r.via_joints.size()) + " segments, each within " + number_text(tol) +
                  " mm ($7) of the line at its middle");
  return set_commanded(last);
}

// The controller's checks of a new commanded state (move_absolute for motors; the joint
// limits for a robot without), then the pose.
Status KinematicModel::set_commanded(const std::vector<int64_t>& target) {
  for (int i = 0; i < n_; ++i) {
    const int64_t v = target[size_t(i)];
    if (v < -kMaxAbsMillideg || v > kMaxAbsMillideg) return kValueOutOfRange;
    if (motors_) {
      if (v < robot_.actuation.motors[i].min || v > robot_.actuation.motors[i].max) return kJointLimit;
    } else {
      const double units = double(v + offset_[size_t(i)]) / 1000.0;
      const double q = joint_to_model(robot_, i, units);
      const auto& js = robot_.model.joints[i];
      const double slack = 1e-9 * (1 + std::fabs(q));
      if (q < js.lo - slack || q > js.hi + slack) return kJointLimit;
    }
  }
  commanded_ = target;
  q_from_commanded();
  return kOk;
}

IkResult KinematicModel::solve(const Vec3<double>& target, RunRecord& r) {
  if (!ik_) ik_.emplace(robot_);
  r.has_target = true;
  r.target = target;
  IkOptions opt;
  opt.weights = weights_;
  IkResult res = ik_->solve(IkTarget::at(target), q_, opt);  // throws std::invalid_argument
  r.ik_status = ik_status_name(res.status);
  return res;
}

Status KinematicModel::run_command(RunRecord& r, const std::string& text) {
  Command cmd;
  const Status parsed = parse_protocol_line(cmd, text, n_);
  if (parsed != kOk) return parsed;
  switch (cmd.type) {
    case kCmdNone:
    case kCmdInfo:
    case kCmdListSettings:
      return kOk;
    case kCmdDwell:  // (the parser checked its range)
      r.dwell_s = cmd.arg[0] / 1000.0;
      return kOk;
    case kCmdOutput:  // nothing on the model's pins: an output moves nothing
      return kOk;
    case kCmdWaitInput:
      // Nothing drives the model's inputs: each reads its pull-up, 1. A wait for 0 runs out.
      if (cmd.arg[1] == 0) {
        r.dwell_s = cmd.arg[2] / 1000.0;
        add_note(r, "nothing drives pin " + std::to_string(cmd.arg[0]) +
                        " here (it reads 1): the wait runs out, and the arm's firmware drops what follows (error 21)");
      }
      return kOk;
    case kCmdName:  // the robot configuration: nothing to run
      return config_check_name(text.data() + cmd.arg[0], uint8_t(cmd.arg[1]));
    case kCmdSetSetting: {
      if (cmd.arg[0] >= 100)
        return cmd.arg[0] == kCommitSetting ? kOk : config_check(uint16_t(cmd.arg[0]), cmd.arg[1]);
      const Status s = check_setting(n_, cmd.arg[0], cmd.arg[1]);
      if (s == kOk) settings_.value[size_t(cmd.arg[0])] = uint32_t(cmd.arg[1] / 1000);
      return s;
    }
    case kCmdRotate: {
      std::vector<int64_t> t = commanded_;
      t[size_t(cmd.arg[0])] += cmd.arg[1];
      return set_commanded(t);
    }
    case kCmdMoveAbsolute:
      return set_commanded(std::vector<int64_t>(cmd.arg, cmd.arg + n_));
    case kCmdLine:
      r.has_target = true;
      r.target = make_vec3(cmd.arg[0] / 1000.0, cmd.arg[1] / 1000.0, cmd.arg[2] / 1000.0);
      return line(r, cmd.arg);
    case kCmdMoveTool: {
      IkResult res;
      try {
        res = solve(make_vec3(cmd.arg[0] / 1000.0, cmd.arg[1] / 1000.0, cmd.arg[2] / 1000.0), r);
      } catch (const std::invalid_argument& e) {
        add_note(r, e.what());
        return kUnreachable;
      }
      if (!res.reached()) {
        add_note(r, "ik: " + r.ik_status + ", " + number_text(std::round(res.position_error_mm * 1000) / 1000) +
                        " mm from the target");
        return kUnreachable;
      }
      // As the controller does: the solution's commanded angles, to the thousandth, in limits.
      const std::vector<double> keep = q_;
      q_ = res.q;
      const std::vector<int64_t> before = commanded_;
      commanded_from_q();
      std::vector<int64_t> t = commanded_;
      commanded_ = before;
      q_ = keep;
      if (motors_)
        for (int i = 0; i < n_; ++i)
          t[size_t(i)] =
              std::clamp<int64_t>(t[size_t(i)], robot_.actuation.motors[i].min, robot_.actuation.motors[i].max);
      return set_commanded(t);
    }
    case kCmdHome: {
      // Switch motors ($3) end at their minimum angle, the others at the home pose.
      std::vector<int64_t> t(static_cast<size_t>(n_));
      const uint32_t mask = settings_.value[ControllerSettings::kEndstops];
      if (motors_) {
        double u[kMaxJoints];
        actuators_from_joints(u, robot_.actuation, robot_.home.data());
        for (int i = 0; i < n_; ++i) {
          const MotorSpec& m = robot_.actuation.motors[i];
          Millideg h = m.zero;
          to_millideg(h, rad_to_deg(u[i]));
          t[size_t(i)] = (mask & (1u << i)) ? m.min : clamp(h, m.min, m.max);
          if (mask & (1u << i)) offset_[size_t(i)] = 0;  // the switch finds the real position
        }
      } else {
        for (int j = 0; j < n_; ++j) {
          const double v = joint_from_model(robot_, j, robot_.home[size_t(j)]);
          t[size_t(j)] = std::llround(v * 1000.0) - offset_[size_t(j)];
        }
      }
      return set_commanded(t);
    }
    case kCmdSetZero: {
      // The arm stays; its commanded angles become the home pose's, shifted by where it is.
      std::vector<int64_t> physical(static_cast<size_t>(n_));
      for (int i = 0; i < n_; ++i) physical[size_t(i)] = commanded_[size_t(i)] + offset_[size_t(i)];
      const std::vector<double> q = q_;
      q_ = robot_.home;
      std::fill(offset_.begin(), offset_.end(), 0);
      commanded_from_q();
      for (int i = 0; i < n_; ++i) offset_[size_t(i)] = physical[size_t(i)] - commanded_[size_t(i)];
      q_ = q;
      add_note(r, "nothing moves: the commanded angles are now the home pose's");
      return kOk;
    }
    case kCmdGripper:
    case kCmdAperture: {
      gripper_percent_ = aperture_percent(command_aperture(cmd));
      return kOk;
    }
  }
  return kUnknownCommand;
}

void KinematicModel::robosim(RunRecord& r, const Statement& st) {
  const int nj = robot_.model.num_joints;
  switch (st.kind) {
    case Statement::Kind::kJoints: {
      for (int j = 0; j < nj; ++j)
        q_[size_t(j)] = joint_to_model(robot_, j, st.values[size_t(j)]);
      if (motors_) {
        double u[kMaxJoints];
        actuators_from_joints(u, robot_.actuation, q_.data());
        for (int i = 0; i < n_; ++i) {
          const MotorSpec& m = robot_.actuation.motors[i];
          const double deg = rad_to_deg(u[i]);
          if (deg * 1000 < m.min - 0.5 || deg * 1000 > m.max + 0.5)
            add_note(r, "motor " + robot_.motor_names[size_t(i)] + " at " + number_text(std::round(deg * 1000) / 1000) +
                            " deg is beyond its limits: the real arm refuses this (error:9)");
        }
      }
      std::fill(offset_.begin(), offset_.end(), 0);
      commanded_from_q();
      return;
    }
    case Statement::Kind::kTarget: {
      IkResult res;
      try {
        res = solve(make_vec3(st.values[0], st.values[1], st.values[2]), r);
      } catch (const std::invalid_argument& e) {
        r.reply = kUnreachable;
        add_note(r, e.what());
        return;
      }
      q_ = res.q;
      if (!res.reached())
        add_note(r, "ik: " + r.ik_status + ": moved to the best pose found, " +
                        number_text(std::round(res.position_error_mm * 1000) / 1000) + " mm from the target");
      std::fill(offset_.begin(), offset_.end(), 0);
      commanded_from_q();
      return;
    }
    case Statement::Kind::kLinkLengths: {
      set_link_lengths(robot_, st.values);
      ik_.reset();
      return;
    }
    case Statement::Kind::kWeights:
      weights_ = st.values;
      return;
    case Statement::Kind::kSpeed:
      add_note(r, "speed " + number_text(st.values[0]) + " of " + number_text(kRoboSimFastest) + ": no timing in the kinematic model");
      return;
    case Statement::Kind::kHand:
      gripper_percent_ = aperture_percent(robosim_hand_to_aperture(st.values[0]));
      return;
    case Statement::Kind::kZoom:
      add_note(r, "zoom is for a viewer");
      return;
    case Statement::Kind::kProtocol:
      break;
  }
}

void KinematicModel::finish(RunRecord& r) const {
  r.joints.clear();
  for (int j = 0; j < robot_.model.num_joints; ++j)
    r.joints.push_back(joint_from_model(robot_, j, q_[size_t(j)]));
  HostFrames f;
  forward_kinematics(f, robot_.model, q_.data());
  r.tool = f.T_base_tool;
  const Vec3<double> rpy = matrix_to_rpy(r.tool.R);
  r.rpy_deg = make_vec3(rad_to_deg(rpy.x), rad_to_deg(rpy.y), rad_to_deg(rpy.z));
  r.gripper_percent = gripper_percent_;
  if (r.has_target) r.target_error_mm = norm(r.tool.p - r.target);
}

RunRecord KinematicModel::execute_line(const std::string& line, int line_number) {
  RunRecord r;
  r.line = line_number;
  r.text = line;
  if (is_stop_line(line)) {  // each line runs to its end here: a '!' between two finds the arm at rest
    add_note(r, "stops the arm: between lines, at rest here, nothing changes (articula predict --sender stream "
                "says where a stream stops)");
    finish(r);
    return r;
  }
  KinematicModel saved = *this;
  r.reply = run_command(r, line);
  if (r.reply != kOk) *this = saved;  // a rejected line changes nothing
  finish(r);
  return r;
}

RunRecord KinematicModel::execute(const Statement& st) {
  if (st.kind == Statement::Kind::kProtocol) return execute_line(st.text, st.line);
  RunRecord r;
  r.line = st.line;
  r.text = std::string(1, robosim_letter(st.kind));
  for (double v : st.values) r.text += " " + number_text(v);
  KinematicModel saved = *this;
  robosim(r, st);
  if (r.reply != kOk) *this = saved;
  finish(r);
  return r;
}

std::vector<RunRecord> run_program(const Robot& robot, const Program& program) {
  KinematicModel model(robot);
  std::vector<RunRecord> out;
  for (const Statement& st : program.statements) out.push_back(model.execute(st));
  return out;
}

}  // namespace articula::host
