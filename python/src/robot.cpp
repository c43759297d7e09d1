// python/src/robot.cpp - articula.Robot: the robot file, the kinematics (one pose and
// batches), the IK, URDF and the legacy import. Every pose is the core's (shared/articula/dh.h).
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "bindings.h"
#include "geometry.h"
#include "legacy.h"
#include "nano_config.h"
#include "records_json.h"
#include "robot_file.h"
#include "robot_view.h"
#include "urdf.h"
#include "wiring.h"

namespace articula::python {
namespace {

using namespace nb::literals;
using host::HostFrames;


PyRobot make_robot(Robot r) {
  PyRobot p;
  p.robot = std::make_shared<const Robot>(std::move(r));
  return p;
}

// The robot's description is host/lib/robot_view.h's (the web engine hands out the same);
// Python gets tuples where a pair is fixed (gear, step_range, pull-out points).
nb::object motors_info(const Robot& r) {
  nb::list out;
  for (const auto& m : host::motors_json(r)) {
    nb::dict d = nb::borrow<nb::dict>(json_to_python(m));
    d["gear"] = nb::make_tuple(m["gear"][0].get<int>(), m["gear"][1].get<int>());
    d["step_range"] = nb::make_tuple(m["step_range"][0].get<int>(), m["step_range"][1].get<int>());
    nb::list curve;
    for (const auto& pt : m["pull_out"]) curve.append(nb::make_tuple(pt[0].get<double>(), pt[1].get<double>()));
    d["pull_out"] = curve;
    out.append(d);
  }
  return out;
}

nb::list links_info(const Robot& r) {
  nb::list out;
  for (const auto& l : host::links_json(r)) {
    nb::list shapes;
    for (const auto& s : l["shapes"]) {
      nb::dict d = nb::borrow<nb::dict>(json_to_python(s));
      d["size"] = nb::make_tuple(s["size"][0].get<double>(), s["size"][1].get<double>(), s["size"][2].get<double>());
      Array44 pose = new_array44();
      for (int k = 0; k < 16; ++k) pose.data()[k] = s["pose"][size_t(k)].get<double>();
      d["pose"] = pose;
      shapes.append(d);
    }
    nb::dict d;
    d["frame"] = l["frame"].get<int>();
    d["shapes"] = shapes;
    out.append(d);
  }
  return out;
}

Array joints_array(const Robot& r, const std::vector<double>& q_model) {
  const std::vector<double> q = host::joints_out(r, q_model.data());
  Array a = new_array({q.size()});
  std::copy(q.begin(), q.end(), a.data());
  return a;
}

// Every frame at joint values from Python (checked, deg or mm).
HostFrames frames_at(const Robot& r, nb::handle q_in) {
  double q[host::kMaxJoints];
  read_joints(q, q_in, r, "q");
  HostFrames f;
  forward_kinematics(f, r.model, q);
  return f;
}

Array44 fk(const PyRobot& self, nb::handle q_in) { return transform_array(frames_at(self.r(), q_in).T_base_tool); }

Array frames(const PyRobot& self, nb::handle q_in) {
  const Robot& r = self.r();
  const HostFrames f = frames_at(r, q_in);
  const size_t n = size_t(r.model.num_rows);
  Array a = new_array({n + 2, 4, 4});
  for (size_t i = 0; i <= n; ++i) write_transform(a.data() + 16 * i, f.T_base_frame[i]);
  write_transform(a.data() + 16 * (n + 1), f.T_base_tool);
  return a;
}

// The Jacobian per unit of q as the interfaces give it (host/lib/robot_view.h).
void write_jacobian(double* out, const Robot& r, const HostFrames& f) { host::jacobian_at(r, f, out); }

Array jacobian_one(const PyRobot& self, nb::handle q_in) {
  const Robot& r = self.r();
  const HostFrames f = frames_at(r, q_in);
  Array a = new_array({6, size_t(r.model.num_joints)});
  write_jacobian(a.data(), r, f);
  return a;
}

// (N, n) joint values, checked and converted to model units in place in a copy.
std::vector<double> read_batch(nb::handle Q_in, const Robot& r, size_t& N) {
  auto Q = read_array(Q_in, "Q");
  const size_t n = size_t(r.model.num_joints);
  if (Q.ndim() != 2 || Q.shape(1) != n) {
    std::string shape = "(";
    for (size_t k = 0; k < Q.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(Q.shape(k));
    shape += Q.ndim() == 1 ? ",)" : ")";
    throw nb::value_error(("Q must have shape (N, " + std::to_string(n) + "): one row of " + std::to_string(n) +
                           " joint values per pose for " + r.name + ", got " + shape)
                              .c_str());
  }
  N = Q.shape(0);
  std::vector<double> q(Q.data(), Q.data() + N * n);
  for (size_t i = 0; i < N; ++i)
    for (size_t j = 0; j < n; ++j) {
      double& v = q[i * n + j];
      if (!std::isfinite(v))
        throw nb::value_error(("Q[" + std::to_string(i) + ", " + std::to_string(j) + "] (" + r.joint_names[j] + ") is " +
                               (std::isnan(v) ? "NaN" : "infinite") + ": joint values must be finite numbers")
                                  .c_str());
      v = host::joint_to_model(r, int(j), v);
    }
  return q;
}

// A batch: FK of each row of Q (model units after read_batch), `write` puts what one pose
// gives (`per_pose` numbers) into its place of an (N, tail...) array; without the GIL.
template <typename Write>
Array batch(const PyRobot& self, nb::handle Q_in, std::initializer_list<size_t> tail, size_t per_pose, Write write) {
  const Robot& r = self.r();
  size_t N = 0;
  const std::vector<double> q = read_batch(Q_in, r, N);
  const size_t n = size_t(r.model.num_joints);
  std::vector<size_t> shape{N};
  shape.insert(shape.end(), tail);
  Array a = shape.size() == 3 ? new_array({shape[0], shape[1], shape[2]}) : new_array({shape[0], shape[1]});
  double* out = a.data();
  {
    nb::gil_scoped_release release;
    HostFrames f;
    for (size_t i = 0; i < N; ++i) {
      forward_kinematics(f, r.model, q.data() + i * n);
      write(out + per_pose * i, r, f);
    }
  }
  return a;
}

Array fk_batch(const PyRobot& self, nb::handle Q_in) {
  return batch(self, Q_in, {4, 4}, 16,
               [](double* out, const Robot&, const HostFrames& f) { write_transform(out, f.T_base_tool); });
}

Array jacobian_batch(const PyRobot& self, nb::handle Q_in) {
  const size_t n = size_t(self.r().model.num_joints);
  return batch(self, Q_in, {6, n}, 6 * n, write_jacobian);
}

Array dh_table(const PyRobot& self, nb::handle q_in) {
  const Robot& r = self.r();
  double q[host::kMaxJoints];
  read_joints(q, q_in, r, "q");
  const auto table = host::dh_table_at(r, q);
  Array a = new_array({table.size(), 4});
  for (size_t i = 0; i < table.size(); ++i) std::copy(table[i].begin(), table[i].end(), a.data() + 4 * i);
  return a;
}

// ---- IK ----

// An IK result: the C++ result and the robot it names joints and motors of.
struct PyIkResult {
  host::IkResult r;
  std::shared_ptr<const Robot> robot;
};

// A target as Python gives it: (x, y, z), (x, y, z, roll, pitch, yaw) or a 4x4 pose; read and
// checked by the shared layer (host/lib/robot_view.h), as the web engine's are.
host::IkTarget read_target(nb::handle t_in) {
  auto t = read_array(t_in, "target");
  if (t.ndim() == 2 && t.shape(0) == 4 && t.shape(1) == 4) return host::ik_target_pose(t.data());
  return host::ik_target(t.data(), t.ndim() == 1 ? t.size() : 0);
}

// The solver's defaults, from the C++ option struct (the binding restates none of them).
const host::IkOptions kIkDefaults;

host::IkOptions ik_options(const std::string& solver, nb::handle weights, double tolerance_mm, int max_iterations,
                           uint64_t seed) {
  std::vector<double> w;
  if (!weights.is_none()) w = read_vector(weights, "weights");
  return host::ik_options(solver, weights.is_none() ? nullptr : &w, tolerance_mm, max_iterations, seed);
}

std::vector<double> ik_start(const PyRobot& self, nb::handle start) {
  if (start.is_none()) return host::ik_start(self.r(), nullptr);
  std::vector<double> q(size_t(self.r().model.num_joints));
  read_joints(q.data(), start, self.r(), "start");
  return q;
}

PyIkResult ik(const PyRobot& self, nb::handle target, const std::string& solver, nb::handle start, nb::handle weights,
              double tolerance_mm, int max_iterations, uint64_t seed) {
  const host::IkTarget t = read_target(target);
  const host::IkOptions o = ik_options(solver, weights, tolerance_mm, max_iterations, seed);
  const std::vector<double> q0 = ik_start(self, start);
  // One solve is microseconds (the GIL's release would cost a tenth of it); batches let go of it.
  return {self.ik().solve(t, q0, o), self.robot};
}

nb::dict ik_batch(const PyRobot& self, nb::handle targets_in, const std::string& solver, nb::handle start,
                  nb::handle weights, double tolerance_mm, int max_iterations, uint64_t seed, bool chain) {
  const Robot& r = self.r();
  auto T = read_array(targets_in, "targets");
  size_t N = 0, stride = 0;
  bool pose = false, rpy = false;
  if (T.ndim() == 2 && (T.shape(1) == 3 || T.shape(1) == 6)) {
    N = T.shape(0), stride = T.shape(1), rpy = stride == 6;
  } else if (T.ndim() == 3 && T.shape(1) == 4 && T.shape(2) == 4) {
    N = T.shape(0), stride = 16, pose = true;
  } else {
    throw nb::value_error("targets must have shape (N, 3) positions, (N, 6) x y z roll pitch yaw, or (N, 4, 4) poses");
  }
  std::vector<host::IkTarget> targets(N);
  for (size_t i = 0; i < N; ++i) {
    const double* v = T.data() + stride * i;
    for (size_t k = 0; k < stride; ++k)
      if (!std::isfinite(v[k])) throw nb::value_error(("targets[" + std::to_string(i) + "] holds a NaN or an infinity").c_str());
    targets[i] = pose ? host::ik_target_pose(v) : host::ik_target(v, rpy ? 6 : 3);
  }
  const host::IkOptions o = ik_options(solver, weights, tolerance_mm, max_iterations, seed);
  const std::vector<double> q0 = ik_start(self, start);
  const host::InverseKinematics& ik = self.ik();
  const size_t n = size_t(r.model.num_joints);
  Array q = new_array({N, n}), pos_err = new_array({N}), rot_err = new_array({N});
  IntArray iters = new_int_array(N), status = new_int_array(N);
  {
    nb::gil_scoped_release release;
    std::vector<double> from = q0;
    for (size_t i = 0; i < N; ++i) {
      const host::IkResult res = ik.solve(targets[i], from, o);
      for (size_t j = 0; j < n; ++j) q.data()[i * n + j] = host::joint_from_model(r, int(j), res.q[j]);
      pos_err.data()[i] = res.position_error_mm;
      rot_err.data()[i] = rad_to_deg(res.orientation_error_rad);
      iters.data()[i] = res.iterations;
      status.data()[i] = int32_t(res.status);
      if (chain) from = res.q;
    }
  }
  nb::dict d;
  d["q"] = q;
  d["status"] = status;
  d["position_error_mm"] = pos_err;
  d["orientation_error_deg"] = rot_err;
  d["iterations"] = iters;
  return d;
}

}  // namespace

nb::class_<PyRobot> bind_robot(nb::module_& m) {
  nb::class_<PyIkResult>(m, "IkResult",
                         "What robot.ik() found: status ('reached', 'unreachable', 'limited', 'budget'), the best "
                         "pose q within the limits (deg or mm), the tool pose there, the errors and the effort.")
      .def_prop_ro("status", [](const PyIkResult& s) { return host::ik_status_name(s.r.status); },
                   "'reached', 'unreachable' (the arm stretches toward it), 'limited' (a limit holds it back: "
                   "limited_by says which) or 'budget' (out of iterations while still improving)")
      .def_prop_ro("reached", [](const PyIkResult& s) { return s.r.reached(); })
      .def_prop_ro("solver", [](const PyIkResult& s) { return host::ik_method_name(s.r.method); },
                   "the solver that ran: 'closed', 'lm' or 'jt'")
      .def_prop_ro("q", [](const PyIkResult& s) { return joints_array(*s.robot, s.r.q); },
                   "the best pose found, one value per joint variable (deg or mm), within the limits")
      .def_prop_ro("tool", [](const PyIkResult& s) { return transform_array(s.r.tool); }, "the tool pose at q (4x4, mm)")
      .def_prop_ro("position_error_mm", [](const PyIkResult& s) { return s.r.position_error_mm; })
      .def_prop_ro("orientation_error_deg", [](const PyIkResult& s) { return rad_to_deg(s.r.orientation_error_rad); })
      .def_prop_ro("iterations", [](const PyIkResult& s) { return s.r.iterations; })
      .def_prop_ro("attempts", [](const PyIkResult& s) { return s.r.attempts; })
      .def_prop_ro("beyond_reach", [](const PyIkResult& s) { return s.r.beyond_reach; },
                   "the target is provably out of reach (farther than the chain can be long)")
      .def_prop_ro("limited_by",
                   [](const PyIkResult& s) {
                     std::vector<std::string> names;
                     for (int k : s.r.limited_joints) names.push_back(s.robot->joint_names[size_t(k)]);
                     return names;
                   },
                   "the joint variables whose limits hold the arm back (status 'limited')")
      .def_prop_ro("limited_by_motors",
                   [](const PyIkResult& s) {
                     std::vector<std::string> names;
                     for (int k : s.r.limited_motors) names.push_back(s.robot->motor_names[size_t(k)]);
                     return names;
                   })
      .def_prop_ro("why", [](const PyIkResult& s) { return host::ik_miss_words(*s.robot, s.r); },
                   "not reached: what holds the tool back (each joint or motor at a limit, where it stands and its "
                   "range) and how near it comes, in words; '' when reached")
      .def("to_dict", [](const PyIkResult& s) { return json_to_python(host::ik_result_json(*s.robot, s.r)); },
           "the result as `articula ik --json` prints it")
      .def("__repr__", [](const PyIkResult& s) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "<IkResult %s (%s, %d iterations), position error %.4f mm>",
                      host::ik_status_name(s.r.status), host::ik_method_name(s.r.method), s.r.iterations,
                      s.r.position_error_mm);
        return std::string(buf);
      });

  return nb::class_<PyRobot>(m, "Robot",
                      "A robot: its modified DH table, joint variables and limits, motors, links and gripper, "
                      "as a robot file (robots/README.md) describes it. Lengths in mm, angles in degrees.\n\n"
                      ">>> mk2 = Robot.load('mk2plus')\n>>> mk2.fk([0, 90, -90])[:3, 3]\narray([235.,   0., 213.])")
      .def_static("load", [](const std::string& name) { return make_robot(host::load_robot_file(host::resolve_robot_path(name))); },
                  "name_or_path"_a,
                  "A shipped robot by name ('mk2plus', 'panda', ...) or a robot file by path. A file that cannot be "
                  "used raises RobotFileError naming the file, the JSON path and the problem.")
      .def_static("parse", [](const std::string& text, const std::string& name) { return make_robot(host::parse_robot(text, name)); },
                  "text"_a, "name"_a = "<text>", "A robot file's JSON text; `name` stands for the file in messages.")
      .def_static("from_legacy",
                  [](const std::string& path, double scale) {
                    if (!(scale > 0) || !std::isfinite(scale)) throw nb::value_error("scale (mm per unit) must be > 0");
                    std::ifstream in(path);
                    if (!in) throw nb::value_error((path + ": cannot read the file").c_str());
                    std::stringstream ss;
                    ss << in.rdbuf();
                    const host::LegacyImport imp = host::import_legacy(ss.str(), path, scale);
                    PyRobot p = make_robot(host::parse_robot(imp.robot.dump(), path));
                    p.import_notes = imp.dropped;
                    return p;
                  },
                  "path"_a, "scale"_a,
                  "A robot file of the thesis's original system (appendix C) at `scale` mm per Unity unit. What has "
                  "no place in a robot file is listed in import_notes.")
      .def_prop_ro("name", [](const PyRobot& s) { return s.r().name; })
      .def_prop_ro("description", [](const PyRobot& s) { return s.r().description; })
      .def_prop_ro("source", [](const PyRobot& s) { return s.r().source; }, "the file it was loaded from")
      .def_prop_ro("import_notes", [](const PyRobot& s) { return s.import_notes; })
      .def(
          "nano_config",
          [](const PyRobot& s) {
            try {
              return json_to_python(host::nano_config_json(host::nano_config(s.r())));
            } catch (const host::NanoConfigError& e) {
              throw nb::value_error(e.what());
            }
          },
          "The Nano's robot configuration for this robot (docs/protocol.md, 'Robot configuration'): {'name', "
          "'checksum' (the I banner's K), 'lines' (the protocol lines that write it, $199 last), 'has_point'}. "
          "ValueError, with the reason, for a robot the Nano cannot drive.")
      .def(
          "wiring", [](const PyRobot& s) { return json_to_python(host::wiring_json(s.r())); },
          "Every wire of the arm (robots/README.md, 'Drive'; docs/drives.md): {'board', 'board_title', 'given' (the "
          "file names its drive), 'wires': [{'pin', 'signal', 'part', 'motor'}]}, and 'error' for an arm its board "
          "cannot wire.")
      .def_prop_ro("num_joints", [](const PyRobot& s) { return int(s.r().model.num_joints); })
      .def_prop_ro("num_rows", [](const PyRobot& s) { return int(s.r().model.num_rows); })
      .def_prop_ro("num_motors", [](const PyRobot& s) { return s.r().has_motors ? int(s.r().actuation.num_motors) : 0; })
      .def_prop_ro("joint_names", [](const PyRobot& s) { return s.r().joint_names; })
      .def_prop_ro("motor_names", [](const PyRobot& s) { return s.r().motor_names; })
      .def_prop_ro("dh", [](const PyRobot& s) { return json_to_python(host::dh_rows_json(s.r())); },
                   "the DH table, row i holding a(i-1), alpha(i-1), d(i), theta(i) as the robot file writes them: "
                   "a constant (mm, deg), {'joint', 'min', 'max'} or {'linked': {joint: gain}, 'offset'}")
      .def_prop_ro("joints", [](const PyRobot& s) { return json_to_python(host::joints_json(s.r())); },
                   "the joint variables: name, row (1-based), param ('theta', 'd', 'alpha'), unit, min, max")
      .def_prop_ro("limits",
                   [](const PyRobot& s) {
                     const auto limits = host::joint_limits(s.r());
                     Array a = new_array({limits.size(), 2});
                     for (size_t j = 0; j < limits.size(); ++j) std::copy(limits[j].begin(), limits[j].end(), a.data() + 2 * j);
                     return a;
                   },
                   "(n, 2) array of each joint variable's min and max (deg or mm)")
      .def_prop_ro("home",
                   [](const PyRobot& s) {
                     const std::vector<double> home = host::home_pose(s.r());
                     Array a = new_array({home.size()});
                     std::copy(home.begin(), home.end(), a.data());
                     return a;
                   },
                   "the home pose (deg or mm)")
      .def_prop_ro("motors", [](const PyRobot& s) { return motors_info(s.r()); },
                   "the motors (empty for a purely kinematic robot): steps, gear, limits, deg_per_step, step_range")
      .def_prop_ro("coupling",
                   [](const PyRobot& s) {
                     const Robot& r = s.r();
                     const size_t n = r.has_motors ? size_t(r.actuation.num_motors) : 0;
                     Array a = new_array({n, n});
                     for (size_t i = 0; i < n; ++i)
                       for (size_t j = 0; j < n; ++j) a.data()[i * n + j] = r.actuation.coupling[i][j];
                     return a;
                   },
                   "C in q = C u: joint variables from motor angles (empty without motors)")
      .def_prop_ro("links", [](const PyRobot& s) { return links_info(s.r()); },
                   "link shapes per DH frame, as the physics collides them and the studio draws them: type, size "
                   "(mm: box x y z; cylinder and capsule radius, length along z; sphere radius), mesh (its path), "
                   "pose in the frame (4x4), mass, density. A robot file without shapes gets a capsule along each row.")
      .def("finger_poses",
           [](const PyRobot& s, nb::handle q_in, double opening_mm) {
             const Robot& r = s.r();
             if (!r.gripper.present) throw nb::value_error((r.name + " has no gripper").c_str());
             if (!std::isfinite(opening_mm)) throw nb::value_error("opening_mm must be finite");
             const HostFrames f = frames_at(r, q_in);
             Array a = new_array({2, 4, 4});
             write_transform(a.data(), host::finger_pose(r.gripper, f.T_base_tool, opening_mm, +1));
             write_transform(a.data() + 16, host::finger_pose(r.gripper, f.T_base_tool, opening_mm, -1));
             return a;
           },
           "q"_a, "opening_mm"_a,
           "The gripper's two fingers at q and an opening (mm): (2, 4, 4), the left (+y) then the right, each the "
           "centre of a box finger_length x finger_thickness x finger_height.")
      .def_prop_ro("gripper", [](const PyRobot& s) { return json_to_python(host::gripper_json(s.r())); })
      .def_prop_ro("tool_offset", [](const PyRobot& s) { return transform_array(s.r().model.T_last_tool); },
                   "the fixed tool transform after the last row (4x4, mm)")
      .def_prop_ro("reach_mm", [](const PyRobot& s) { return s.ik().reach_bound(); },
                   "the longest distance from the first joint the tool can be")
      .def("fk", &fk, "q"_a,
           "The tool pose at joint values q (deg or mm, one per joint variable) as a 4x4 homogeneous matrix, mm.\n\n"
           ">>> Robot.load('mk2plus').fk([0, 90, -90])[:3, 3]\narray([235.,   0., 213.])")
      .def("frames", &frames, "q"_a,
           "Every frame at q: an (num_rows + 2, 4, 4) array, [0] the base, [i] the frame of DH row i, [-1] the tool.")
      .def("jacobian", &jacobian_one, "q"_a,
           "The geometric Jacobian of the tool point at q, (6, n): rows 0-2 the tool's velocity in mm per unit of "
           "q[j] (deg or mm), rows 3-5 its rotation per unit (deg per deg for an angle).")
      .def("fk_batch", &fk_batch, "Q"_a, "Tool poses of many poses at once: (N, n) joint values -> (N, 4, 4).")
      .def("jacobian_batch", &jacobian_batch, "Q"_a, "Jacobians of many poses: (N, n) -> (N, 6, n).")
      .def("dh_table", &dh_table, "q"_a,
           "The DH table at q, (num_rows, 4): a(i-1) mm, alpha(i-1) deg, d(i) mm, theta(i) deg, with every "
           "variable and linked parameter filled in.")
      .def("within_limits",
           [](const PyRobot& s, nb::handle q_in) {
             std::vector<double> q(size_t(s.r().model.num_joints));
             read_joints(q.data(), q_in, s.r(), "q");
             return host::within_limits(s.ik(), s.r(), std::move(q));
           },
           "q"_a,
           "Whether q is within every joint limit and, with motors, every motor limit (a value on a limit "
           "passes, to 1e-9 of rounding).")
      .def("with_link_lengths",
           [](const PyRobot& s, nb::handle values_in) {
             try {
               return make_robot(host::with_link_lengths(s.r(), read_vector(values_in, "lengths")));
             } catch (const std::invalid_argument& e) {
               throw nb::value_error(e.what());
             }
           },
           "lengths"_a,
           "A copy with other link lengths: a(i-1) of each row the robot file gives a range ({'value', 'min', "
           "'max'}), in row order, mm (RoboSim's l).")
      .def("joints_from_motors",
           [](const PyRobot& s, nb::handle u_in) {
             const std::vector<double> q = host::joints_from_motors(s.r(), read_vector(u_in, "motor angles"));
             Array a = new_array({q.size()});
             std::copy(q.begin(), q.end(), a.data());
             return a;
           },
           "motor_deg"_a, "The joint variables (deg or mm) that motor angles (deg, at the gears' outputs) give: q = C u.")
      .def("motors_from_joints",
           [](const PyRobot& s, nb::handle q_in) {
             const Robot& r = s.r();
             if (!r.has_motors) throw nb::value_error((r.name + " has no motors").c_str());
             std::vector<double> q(size_t(r.model.num_joints));
             read_joints(q.data(), q_in, r, "q");
             const std::vector<double> u = host::motors_from_joints(r, q);
             Array a = new_array({u.size()});
             std::copy(u.begin(), u.end(), a.data());
             return a;
           },
           "q"_a, "The motor angles (deg) that give joint values q: u = C^-1 q.")
      .def("ik", &ik, "target"_a, "solver"_a = "auto", "start"_a = nb::none(), "weights"_a = nb::none(),
           "tolerance_mm"_a = kIkDefaults.position_tolerance_mm, "max_iterations"_a = kIkDefaults.max_iterations,
           "seed"_a = kIkDefaults.seed,
           "Inverse kinematics (docs/ik.md). target: (x, y, z) mm, (x, y, z, roll, pitch, yaw) mm and deg, or a "
           "4x4 pose. solver: 'auto', 'closed', 'lm' or 'jt' (the thesis's Jacobian transpose). start: joint "
           "values to start from (default: home). weights: per joint variable (per motor with a coupling), 0 "
           "freezes one.\n\n>>> Robot.load('mk2plus').ik([200, 0, 150]).status\n'reached'")
      .def("ik_batch", &ik_batch, "targets"_a, "solver"_a = "auto", "start"_a = nb::none(), "weights"_a = nb::none(),
           "tolerance_mm"_a = kIkDefaults.position_tolerance_mm, "max_iterations"_a = kIkDefaults.max_iterations,
           "seed"_a = kIkDefaults.seed, "chain"_a = false,
           "IK for (N, 3), (N, 6) or (N, 4, 4) targets without a Python loop. Returns a dict of arrays: q (N, n), "
           "status (N,) codes (0 reached, 1 unreachable, 2 limited, 3 budget), position_error_mm, "
           "orientation_error_deg, iterations. chain=True starts each solve from the previous answer.")
      .def("to_urdf", [](const PyRobot& s) { return host::export_urdf(s.r()).xml; },
           "The robot as URDF (metres, radians), as `articula export-urdf` writes it.")
      .def("__repr__", [](const PyRobot& s) {
        return "<Robot '" + s.r().name + "': " + std::to_string(s.r().model.num_rows) + " DH rows, " +
               std::to_string(s.r().model.num_joints) + " joint variables, " +
               (s.r().has_motors ? std::to_string(s.r().actuation.num_motors) + " motors" : std::string("no motors")) +
               ">";
      });
}

}  // namespace articula::python
