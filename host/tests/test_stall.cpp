// Tests of host/lib/stall.h: joint and motor torques (Newton-Euler through links, coupling
// and gears) against cases computed by hand, potential and kinetic energy, and the check of
// the controller's moves against the pull-out curves.
#include "stall.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>
#include <string>

#include "robot_file.h"

namespace {

using namespace articula;
using namespace articula::host;
using json = nlohmann::json;

const double kPi = 3.14159265358979323846;
const double g = 9.81;
const std::string kMk2 = std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json";

json curve() { return json::parse(R"({"pull_out": [[0, 0.40], [200, 0.36], [600, 0.30], [1200, 0.20], [2000, 0.10]]})"); }

// One link of length L mm and mass m kg (a 20 x 20 mm box centred on it) on one revolute
// joint with a 5:1 gear; the tool point at its end. vertical_axis: the joint turns about the
// base's z (gravity does no work); else about a horizontal axis, the link horizontal at 0.
Robot one_link(double L, double m, bool vertical_axis, double rotor_inertia = 0) {
  json torque = curve();
  torque["rotor_inertia"] = rotor_inertia;
  const json doc = {
      {"name", "one link"},
      {"dh", {{{"a", 0}, {"alpha", vertical_axis ? 0 : 90}, {"d", 0}, {"theta", {{"joint", "q"}, {"min", -180}, {"max", 180}}}}}},
      {"tool", {{"xyz", {L, 0, 0}}}},
      {"motors", {{{"name", "q"}, {"gear", {5, 1}}, {"torque", torque}}}},
      {"links", {{{"frame", 1}, {"shapes", {{{"type", "box"}, {"size", {L, 20, 20}}, {"xyz", {L / 2, 0, 0}}, {"mass", m}}}}}}}};
  return parse_robot(doc.dump(), "one-link.json");
}

TEST(PullOut, InterpolatesAndEndsAtZero) {
  MotorTorque t;
  const json c = curve();
  for (const auto& p : c["pull_out"]) t.pull_out.push_back({p[0].get<double>(), p[1].get<double>()});
  ASSERT_EQ(t.pull_out.size(), 5u);
  EXPECT_DOUBLE_EQ(pull_out_torque(t, 0), 0.40);          // holding
  EXPECT_DOUBLE_EQ(pull_out_torque(t, 100), 0.38);        // halfway between 0.40 and 0.36
  EXPECT_DOUBLE_EQ(pull_out_torque(t, 200), 0.36);
  EXPECT_DOUBLE_EQ(pull_out_torque(t, 900), 0.25);        // halfway between 0.30 and 0.20
  EXPECT_DOUBLE_EQ(pull_out_torque(t, 1600), 0.15);
  EXPECT_DOUBLE_EQ(pull_out_torque(t, 2000), 0.10);
  EXPECT_EQ(pull_out_torque(t, 2000.001), 0);             // beyond the curve: nothing promised
  EXPECT_DOUBLE_EQ(pull_out_torque(t, -900), 0.25);       // either direction
  EXPECT_EQ(pull_out_torque(MotorTorque{}, 0), 0);
}

// By hand: a horizontal link of length L = 0.2 m, mass m = 0.3 kg at its middle, holding
// M = 0.1 kg at its end, needs the joint torque (m L/2 + M L) g = (0.03 + 0.02) 9.81
// = 0.4905 N*m; through the 5:1 gear the motor supplies 0.0981 N*m. Raised by theta the
// lever arms shrink by cos(theta): straight up, nothing.
TEST(StallModel, HorizontalLinkHoldingAPayload) {
  const double L = 0.2, m = 0.3, M = 0.1;
  const StallModel sm(one_link(L * 1000, m, false));
  ASSERT_TRUE(sm.has_torque_curves());
  const double joint = (m * L / 2 + M * L) * g;
  EXPECT_NEAR(sm.joint_forces({0}, {0}, {0}, M)[0], joint, 1e-9);
  const std::vector<MotorLoad> l = sm.holding_loads({0}, M);
  EXPECT_NEAR(l[0].shaft_nm, joint / 5, 1e-9);
  EXPECT_NEAR(l[0].required_nm, 0.0981, 1e-9);
  EXPECT_EQ(l[0].full_steps_per_s, 0);
  EXPECT_DOUBLE_EQ(l[0].available_nm, 0.40);
  EXPECT_FALSE(l[0].skips());
  // Without the payload: m L/2 g only.
  EXPECT_NEAR(sm.holding_loads({0}, 0)[0].shaft_nm, m * L / 2 * g / 5, 1e-9);
  // Raised 30 deg, and vertical.
  EXPECT_NEAR(sm.holding_loads({deg_to_rad(30.0)}, M)[0].shaft_nm, joint * std::cos(deg_to_rad(30.0)) / 5, 1e-9);
  EXPECT_NEAR(sm.holding_loads({deg_to_rad(90.0)}, M)[0].shaft_nm, 0, 1e-12);
  // Hanging down, the link pulls the other way.
  EXPECT_NEAR(sm.holding_loads({deg_to_rad(-60.0)}, M)[0].shaft_nm, joint * 0.5 / 5, 1e-9);
  // A payload the motor cannot hold: (m L/2 + M L) g / 5 > 0.40 N*m for M > (2 - 0.03 * g) / (0.2 g).
  const double too_heavy = (0.40 * 5 / g - m * L / 2) / L * 1.01;
  EXPECT_TRUE(sm.holding_loads({0}, too_heavy)[0].skips());
  EXPECT_FALSE(sm.holding_loads({0}, too_heavy * 0.98)[0].skips());
}

// By hand: about a vertical axis gravity does nothing; the link (box L x w x h about its
// centre: m (L^2 + w^2) / 12 about z, moved L/2 out: + m L^2/4, i.e. m L^2/3 + m w^2/12)
// and the payload (M L^2) need (m L^2/3 + m w^2/12 + M L^2) alpha; the motor gets a fifth,
// plus its rotor J * 5 * alpha. Turning at a constant rate needs nothing.
TEST(StallModel, AccelerationTerm) {
  const double L = 0.2, w = 0.02, m = 0.3, M = 0.1, J = 5.4e-6, alpha = 7.0, rate = 2.0;
  const StallModel sm(one_link(L * 1000, m, true, J));
  const double joint = (m * L * L / 3 + m * w * w / 12 + M * L * L) * alpha;
  EXPECT_NEAR(sm.joint_forces({0.3}, {rate}, {alpha}, M)[0], joint, 1e-12);
  const MotorLoad l = sm.loads({0.3}, {rate}, {alpha}, M)[0];
  EXPECT_NEAR(l.shaft_nm, joint / 5 + J * 5 * alpha, 1e-12);
  // 2 rad/s at the joint is 10 rad/s at the motor: 10 / (2 pi) turns of 200 full steps.
  EXPECT_NEAR(l.full_steps_per_s, 10 / (2 * kPi) * 200, 1e-9);
  EXPECT_NEAR(l.available_nm, pull_out_torque(MotorTorque{{{0, 0.40}, {200, 0.36}, {600, 0.30}}, 0}, l.full_steps_per_s), 1e-12);
  EXPECT_NEAR(sm.joint_forces({0.3}, {rate}, {0}, M)[0], 0, 1e-12);
  EXPECT_NEAR(sm.joint_forces({0.3}, {0}, {-alpha}, M)[0], -joint, 1e-12);
}

// Potential energy of the robot's links and the payload at actuator angles u (rad).
double potential(const Robot& r, const std::vector<MassProperties>& bodies, const std::vector<double>& u, double payload) {
  double q[kMaxJoints];
  joints_from_actuators(q, r.actuation, u.data());
  HostFrames f;
  forward_kinematics(f, r.model, q);
  double v = 0;
  for (std::size_t i = 1; i < bodies.size(); ++i) {
    const Vec3<double> c = f.T_base_frame[i].R * bodies[i].com + 1e-3 * f.T_base_frame[i].p;
    v += bodies[i].mass * g * c.z;
  }
  return v + payload * g * 1e-3 * f.T_base_tool.p.z;
}

// The MK2's motors hold the gradient of the potential energy in actuator angles: the
// parallelogram's linked row and the coupling (q = C u) are both in the way, and the
// finite differences know nothing of either.
TEST(StallModel, Mk2HoldingTorquesAreThePotentialGradient) {
  const Robot r = load_robot_file(kMk2);
  const StallModel sm(r);
  const std::vector<MassProperties> bodies = frame_masses(r);
  for (const auto& deg : std::vector<std::array<double, 3>>{{0, 90, 0}, {30, 36, 0}, {-60, 120, -40}, {80, 50, 15}})
    for (double payload : {0.0, 0.05, 0.4}) {
      const std::vector<double> u = {deg_to_rad(deg[0]), deg_to_rad(deg[1]), deg_to_rad(deg[2])};
      double q[kMaxJoints];
      joints_from_actuators(q, r.actuation, u.data());
      const std::vector<MotorLoad> l = sm.holding_loads({q[0], q[1], q[2]}, payload);
      const std::vector<double> tu = sm.actuator_torques({q[0], q[1], q[2]}, {0, 0, 0}, {0, 0, 0}, payload);
      for (int k = 0; k < 3; ++k) {
        const double h = 1e-6;
        std::vector<double> up = u, down = u;
        up[k] += h;
        down[k] -= h;
        const double grad = (potential(r, bodies, up, payload) - potential(r, bodies, down, payload)) / (2 * h);
        EXPECT_NEAR(tu[k], grad, 1e-8) << "motor " << k << " at " << deg[0] << "," << deg[1] << "," << deg[2];
        const double ratio = double(r.actuation.motors[k].gear_num) / r.actuation.motors[k].gear_den;
        EXPECT_NEAR(l[k].shaft_nm, grad / ratio, 1e-8);
      }
    }
}

// A robot with every kind of variable: theta, alpha and d joints, linked theta and d
// (with mixed units), shapes turned and offset on four frames, a tool point off the axes.
Robot every_kind() {
  const json doc = json::parse(R"({
    "name": "every kind",
    "dh": [
      {"a": 0,   "alpha": 0, "d": 50, "theta": {"joint": "q1", "min": -180, "max": 180}},
      {"a": 30,  "alpha": {"joint": "q2", "min": -180, "max": 180}, "d": 10, "theta": {"joint": "q3", "min": -180, "max": 180}},
      {"a": 100, "alpha": 0, "d": {"joint": "q4", "min": 0, "max": 100},
                 "theta": {"linked": {"q1": 0.5, "q3": -1, "q4": 0.3}, "offset": 10}},
      {"a": 80,  "alpha": -90, "d": {"linked": {"q4": 0.5, "q2": 0.2}}, "theta": 20}
    ],
    "tool": {"xyz": [30, 10, 5]},
    "motors": [{"name": "m1"}, {"name": "m3"}, {"name": "m2"}, {"name": "m4"}],
    "links": [
      {"frame": 1, "shapes": [{"type": "box", "size": [40, 30, 20], "xyz": [5, 0, 10]}]},
      {"frame": 2, "shapes": [{"type": "cylinder", "size": [15, 100], "xyz": [50, 5, 0], "rpy": [0, 90, 10], "mass": 0.2}]},
      {"frame": 3, "shapes": [{"type": "box", "size": [80, 20, 25], "xyz": [40, -3, 7], "rpy": [10, 20, 30]},
                              {"type": "sphere", "size": [12], "xyz": [80, 0, 0], "density": 3000}]},
      {"frame": 4, "shapes": [{"type": "capsule", "size": [10, 30], "xyz": [10, 20, -5], "rpy": [40, 0, -20]}]}
    ]
  })");
  return parse_robot(doc.dump(), "every-kind.json");
}

struct Energy {
  double kinetic = 0, potential = 0;
};

// Energy at q moving at qd (model units), velocities by central differences of the core's
// forward kinematics along qd: nothing from the Newton-Euler code.
Energy energy(const Robot& r, const std::vector<MassProperties>& bodies, const std::vector<double>& q,
              const std::vector<double>& qd, double payload, double h = 1e-6) {
  std::vector<double> qp = q, qm = q;
  for (std::size_t j = 0; j < q.size(); ++j) qp[j] += h * qd[j], qm[j] -= h * qd[j];
  HostFrames f0, fp, fm;
  forward_kinematics(f0, r.model, q.data());
  forward_kinematics(fp, r.model, qp.data());
  forward_kinematics(fm, r.model, qm.data());
  Energy e;
  auto point = [](const HostFrames& f, int i, const Vec3<double>& local) {
    return f.T_base_frame[i].R * local + 1e-3 * f.T_base_frame[i].p;
  };
  for (std::size_t i = 1; i < bodies.size(); ++i) {
    const MassProperties& b = bodies[i];
    const Vec3<double> v = (0.5 / h) * (point(fp, int(i), b.com) - point(fm, int(i), b.com));
    // [w]x = (dR/dt) R^T, from R(+h) R(-h)^T = I + 2h [w]x + O(h^2).
    const Mat3<double> d = fp.T_base_frame[i].R * transpose(fm.T_base_frame[i].R);
    const Vec3<double> w = make_vec3(d.m[2][1] - d.m[1][2], d.m[0][2] - d.m[2][0], d.m[1][0] - d.m[0][1]);
    const Vec3<double> omega = (0.25 / h) * w;
    const Mat3<double>& R = f0.T_base_frame[i].R;
    const Mat3<double> Iw = R * b.inertia * transpose(R);
    e.kinetic += 0.5 * b.mass * dot(v, v) + 0.5 * dot(omega, Iw * omega);
    e.potential += b.mass * g * point(f0, int(i), b.com).z;
  }
  const Vec3<double> vt = (0.5e-3 / h) * (fp.T_base_tool.p - fm.T_base_tool.p);
  e.kinetic += 0.5 * payload * dot(vt, vt);
  e.potential += payload * g * 1e-3 * f0.T_base_tool.p.z;
  return e;
}

// The power the joints put in equals the rate of change of the energy, along random
// motions q(t) = q0 + qd0 t + qdd t^2 / 2: velocity, acceleration, gravity and the
// linked parameters' terms together.
TEST(StallModel, PowerIsTheRateOfChangeOfEnergy) {
  const Robot r = every_kind();
  const StallModel sm(r);
  const std::vector<MassProperties> bodies = frame_masses(r);
  ASSERT_GT(sm.total_link_mass_kg(), 0.2);
  const bool is_d[4] = {false, false, false, true};  // joint order q1, q3, q2, q4
  ASSERT_EQ(r.joint_names, (std::vector<std::string>{"q1", "q3", "q2", "q4"}));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-2, 2), length(20, 80), rate(-3, 3), mm_rate(-200, 200);
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<double> q(4), qd(4), qdd(4);
    for (int j = 0; j < 4; ++j) {
      q[j] = is_d[j] ? length(rng) : angle(rng);
      qd[j] = is_d[j] ? mm_rate(rng) : rate(rng);
      qdd[j] = is_d[j] ? mm_rate(rng) : rate(rng);
    }
    const double payload = trial % 2 ? 0.25 : 0;
    const std::vector<double> tau = sm.joint_forces(q, qd, qdd, payload);
    double power = 0;
    for (int j = 0; j < 4; ++j) power += tau[j] * qd[j] * (is_d[j] ? 1e-3 : 1);  // N*m * rad/s, N * m/s
    const double dt = 1e-4;
    auto at = [&](double t) {
      std::vector<double> qt(4), qdt(4);
      for (int j = 0; j < 4; ++j) qt[j] = q[j] + qd[j] * t + 0.5 * qdd[j] * t * t, qdt[j] = qd[j] + qdd[j] * t;
      const Energy e = energy(r, bodies, qt, qdt, payload);
      return e.kinetic + e.potential;
    };
    const double dEdt = (at(dt) - at(-dt)) / (2 * dt);
    EXPECT_NEAR(power, dEdt, 1e-6 * (1 + std::fabs(power))) << "trial " << trial;
    EXPECT_GT(std::fabs(power), 1e-3);  // not vacuous
  }
}

// Lagrange's equations joint by joint, tau_j = d/dt dT/dqd_j - dT/dq_j + dV/dq_j, every
// derivative a central difference of the energies above: this sees the forces that do no
// work in total (gyroscopic, Coriolis), which the power balance cannot.
TEST(StallModel, LagrangesEquationsJointByJoint) {
  const Robot r = every_kind();
  const StallModel sm(r);
  const std::vector<MassProperties> bodies = frame_masses(r);
  const bool is_d[4] = {false, false, false, true};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-2, 2), length(20, 80), rate(-3, 3), mm_rate(-200, 200);
  const double h = 1e-4;  // velocities of the energies
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<double> q(4), qd(4), qdd(4);
    for (int j = 0; j < 4; ++j) {
      q[j] = is_d[j] ? length(rng) : angle(rng);
      qd[j] = is_d[j] ? mm_rate(rng) : rate(rng);
      qdd[j] = is_d[j] ? mm_rate(rng) : rate(rng);
    }
    const double payload = trial % 2 ? 0.25 : 0;
    const std::vector<double> tau = sm.joint_forces(q, qd, qdd, payload);
    auto T = [&](const std::vector<double>& qq, const std::vector<double>& vv) {
      return energy(r, bodies, qq, vv, payload, h).kinetic;
    };
    auto V = [&](const std::vector<double>& qq) { return energy(r, bodies, qq, qd, payload, h).potential; };
    for (int j = 0; j < 4; ++j) {
      const double eps = is_d[j] ? 1 : 1e-2, eta = is_d[j] ? 1e-3 : 1e-5, dt = 1e-3;
      auto dT_dqd = [&](double t) {
        std::vector<double> qq(4), up(4), down(4);
        for (int k = 0; k < 4; ++k) qq[k] = q[k] + qd[k] * t + 0.5 * qdd[k] * t * t, up[k] = down[k] = qd[k] + qdd[k] * t;
        up[j] += eps, down[j] -= eps;
        return (T(qq, up) - T(qq, down)) / (2 * eps);
      };
      std::vector<double> qp = q, qm = q;
      qp[j] += eta, qm[j] -= eta;
      const double dL_dq = (T(qp, qd) - V(qp) - T(qm, qd) + V(qm)) / (2 * eta);
      // In model units: per rad, or per mm for the d joint (tau is N: 1e-3 N*m per mm).
      const double lagrange = (dT_dqd(dt) - dT_dqd(-dt)) / (2 * dt) - dL_dq;
      const double expected = tau[j] * (is_d[j] ? 1e-3 : 1);
      EXPECT_NEAR(expected, lagrange, 2e-6 * (1 + std::fabs(expected))) << "trial " << trial << " joint " << j;
    }
  }
}

// ---- the MK2's moves against its pull-out curves

struct Mk2 {
  Robot robot = load_robot_file(kMk2);
  StallModel sm{robot};
  // Joint values with the elbow motor at elevation u3 (deg), the shoulder vertical.
  std::vector<double> q_at(double u3) const {
    const double u[3] = {0, deg_to_rad(90.0), deg_to_rad(u3)};
    double q[kMaxJoints];
    joints_from_actuators(q, robot.actuation, u);
    return {q[0], q[1], q[2]};
  }
  // The static elbow motor torque with the forearm level is s0 + k * payload (linear in it):
  // the payload (kg) it takes to need exactly the pull-out torque at `rate` full steps/s.
  double payload_for(double rate) const {
    const double s0 = sm.holding_loads(q_at(0), 0)[2].required_nm;
    const double k = sm.holding_loads(q_at(0), 1)[2].required_nm - s0;
    return (pull_out_torque(robot.motor_torque[2], rate) - s0) / k;
  }
};

// Turning at a steady rate through the level forearm, centrifugal forces have no moment
// about the elbow's axis: the motor needs its static torque, and skips just above the
// payload computed from it.
TEST(StallModel, Mk2ElbowThresholdAtASteadyRate) {
  const Mk2 mk2;
  const double rate = 1000;  // full steps/s
  const double M = mk2.payload_for(rate);
  ASSERT_GT(M, 0.05);
  const MotorSpec& s = mk2.robot.actuation.motors[2];
  const double ud = rate * 2 * kPi / (s.full_steps_per_rev * double(s.gear_num) / s.gear_den);  // rad/s of the forearm
  double qd[kMaxJoints];
  const double u_d[3] = {0, 0, ud};
  joints_from_actuators(qd, mk2.robot.actuation, u_d);
  const std::vector<double> qdv = {qd[0], qd[1], qd[2]}, zero = {0, 0, 0};
  const MotorLoad over = mk2.sm.loads(mk2.q_at(0), qdv, zero, 1.02 * M)[2];
  const MotorLoad under = mk2.sm.loads(mk2.q_at(0), qdv, zero, 0.98 * M)[2];
  EXPECT_NEAR(over.full_steps_per_s, rate, 1e-9);
  EXPECT_TRUE(over.skips()) << over.required_nm << " vs " << over.available_nm;
  EXPECT_FALSE(under.skips()) << under.required_nm << " vs " << under.available_nm;
  // At rest the same payload is held: the holding torque is larger.
  EXPECT_FALSE(mk2.sm.holding_loads(mk2.q_at(0), 1.02 * M)[2].skips());
}

MoveCheck elbow_sweep(const Mk2& mk2, uint32_t max_rate, uint32_t accel, double payload) {
  ControllerSettings s;
  apply_settings_text(s, "0=" + std::to_string(max_rate) + ",1=" + std::to_string(accel), 3);
  const Prediction p = predict_program(mk2.robot, parse_protocol_program("M 0 90 -43\nM 0 90 15\n", "t.arm", mk2.robot), s);
  const PredictRecord& before = p.records[0];
  const PredictRecord& move = p.records[1];
  EXPECT_TRUE(move.queued);
  const MoveCheck c = mk2.sm.check_move(before, move, s, payload);
  EXPECT_NEAR(c.duration_s, move.seconds(), 1e-12);
  EXPECT_EQ(c.samples, int(move.dominant_steps) + 1);
  return c;
}

// The forearm swept from -43 to 15 deg through the level: fast (1000 full steps/s, reached
// within 25 steps at 20000 steps/s^2) with 20 % more than the payload the pull-out torque
// at that rate holds statically, the elbow motor skips; slowly (100 full steps/s), the
// same payload and no payload at all pass.
TEST(StallModel, Mk2CheckMoveFlagsAHeavyFastMoveOnly) {
  const Mk2 mk2;
  const double heavy = 1.2 * mk2.payload_for(1000);
  const MoveCheck fast = elbow_sweep(mk2, 1000, 20000, heavy);
  EXPECT_TRUE(fast.skips);
  ASSERT_EQ(fast.motors.size(), 3u);
  EXPECT_TRUE(fast.motors[2].skips);
  EXPECT_LT(fast.motors[2].worst_margin_nm, 0);
  EXPECT_GE(fast.motors[2].at_s, 0);
  EXPECT_LE(fast.motors[2].at_s, fast.duration_s);
  EXPECT_FALSE(fast.motors[0].skips);  // the base holds nothing against gravity
  EXPECT_GT(fast.motors[2].peak_required_nm, mk2.sm.holding_loads(mk2.q_at(0), heavy)[2].required_nm);

  for (double payload : {heavy, 0.0}) {
    const MoveCheck slow = elbow_sweep(mk2, 100, 2000, payload);
    EXPECT_FALSE(slow.skips) << payload << " kg: elbow margin " << slow.motors[2].worst_margin_nm << " at "
                             << slow.motors[2].at_s << " s";
    EXPECT_GT(slow.motors[2].worst_margin_nm, 0);
    EXPECT_LE(slow.motors[2].at_worst.full_steps_per_s, 100 + 1e-9);
  }
}

TEST(StallModel, ActionsThatMoveNothingAreCheckedAtRest) {
  const Mk2 mk2;
  const Prediction p = predict_program(mk2.robot, parse_protocol_program("M 0 90 0\nG 50\n", "t.arm", mk2.robot));
  const PredictRecord& before = p.records[0];
  const PredictRecord& grip = p.records[1];
  ASSERT_TRUE(grip.queued);
  const MoveCheck c = mk2.sm.check_move(before, grip, ControllerSettings{}, 0.05);
  EXPECT_EQ(c.samples, 1);
  EXPECT_NEAR(c.motors[2].at_worst.required_nm, mk2.sm.holding_loads(mk2.q_at(0), 0.05)[2].required_nm, 1e-12);
  EXPECT_EQ(c.motors[2].at_worst.full_steps_per_s, 0);
  EXPECT_NEAR(c.duration_s, grip.seconds(), 1e-12);
}

TEST(StallModel, RobotWithoutMotorsOrCurves) {
  const Robot thesis = load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/thesis-example.json");
  EXPECT_THROW(StallModel{thesis}, PredictError);
  Robot bare = one_link(200, 0.3, false);
  bare.motor_torque.clear();
  const StallModel sm(bare);
  EXPECT_FALSE(sm.has_torque_curves());
  const MotorLoad l = sm.holding_loads({0}, 10)[0];
  EXPECT_FALSE(l.rated);
  EXPECT_FALSE(l.skips());
  EXPECT_TRUE(std::isinf(l.available_nm));
  EXPECT_THROW(sm.holding_loads({0, 0}, 0), std::invalid_argument);
}

}  // namespace
