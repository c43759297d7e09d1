// host/physics/sim.cpp - see sim.h; docs/physics.md explains the choices.
#include "sim.h"

#include <algorithm>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "geometry.h"
#include "mesh.h"
#include "run.h"

namespace articula::host {

namespace {

constexpr double kMm = 0.001;  // mm -> m
constexpr int kMaxContacts = 4;
// A mesh against the ground gives its vertices below it in file order, not the deepest first:
// the step check asks for more of them.
constexpr int kMaxMeshContacts = 32;
constexpr double kArmFriction = 0.6;
constexpr double kFingerFriction = 1.0;

void init_ode() {
  static std::once_flag once;
  std::call_once(once, [] {
    dInitODE2(0);
    // ODE's notes on degenerate contact sets (a body squeezed between two immovable ones) go
    // to stderr by default, in the middle of our output: the simulation checks its state itself.
    dSetMessageHandler([](int, const char*, va_list) {});
  });
}

void to_ode(const Mat3<double>& R, dMatrix3 out) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out[i * 4 + j] = R.m[i][j];
    out[i * 4 + 3] = 0;
  }
}

Mat3<double> from_ode(const dReal* R) {
  Mat3<double> m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.m[i][j] = R[i * 4 + j];
  return m;
}

Transform<double> inverse(const Transform<double>& T) {
  const Mat3<double> Rt = transpose(T.R);
  const Vec3<double> p = Rt * T.p;
  return make_transform(Rt, make_vec3(-p.x, -p.y, -p.z));
}

bool aabb_overlap(dGeomID a, dGeomID b) {
  dReal x[6], y[6];
  dGeomGetAABB(a, x);
  dGeomGetAABB(b, y);
  return x[0] <= y[1] && y[0] <= x[1] && x[2] <= y[3] && y[2] <= x[3] && x[4] <= y[5] && y[4] <= x[5];
}

// The rotation R_new R_old^T as a rotation vector (axis * angle), rad.
Vec3<double> rotation_vector(const Mat3<double>& R_new, const Mat3<double>& R_old) {
  const Mat3<double> D = R_new * transpose(R_old);
  const double c = std::clamp((D.m[0][0] + D.m[1][1] + D.m[2][2] - 1) / 2, -1.0, 1.0);
  const double angle = std::acos(c);
  const Vec3<double> w = make_vec3(D.m[2][1] - D.m[1][2], D.m[0][2] - D.m[2][0], D.m[1][0] - D.m[0][1]);
  const double s = std::sin(angle);
  if (s < 1e-9) return make_vec3(w.x / 2, w.y / 2, w.z / 2);  // small angle (or 180 deg: not a step's worth)
  const double k = angle / (2 * s);
  return make_vec3(w.x * k, w.y * k, w.z * k);
}

// A distance in an event's message ("the gripper hit the cube 3.2 mm above the table"): one
// decimal, what the physics' own accuracy supports (not a protocol number).
std::string fmt_mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

bool is_mesh(dGeomID g) { return dGeomGetClass(g) == dTriMeshClass; }

}  // namespace

const char* event_kind_name(SimEvent::Kind k) {
  switch (k) {
    case SimEvent::Kind::kContactStarted: return "contact_started";
    case SimEvent::Kind::kContactEnded: return "contact_ended";
    case SimEvent::Kind::kCollision: return "collision";
    case SimEvent::Kind::kSelfCollision: return "self_collision";
    case SimEvent::Kind::kSqueeze: return "squeeze";
    case SimEvent::Kind::kStepsLost: return "steps_lost";
    case SimEvent::Kind::kBlocked: return "blocked";
    case SimEvent::Kind::kGrasp: return "grasp";
    case SimEvent::Kind::kRelease: return "release";
    case SimEvent::Kind::kGripperBlocked: return "gripper_blocked";
    case SimEvent::Kind::kRejected: return "rejected";
    case SimEvent::Kind::kObjectRemoved: return "object_removed";
    case SimEvent::Kind::kNote: return "note";
    case SimEvent::Kind::kStall: return "stall";
  }
  return "?";
}

struct Simulation::Part {
  std::string name;
  int frame = -1;  // DH frame; -1 a finger
  int side = 0;    // finger: -1 right, +1 left (along the tool's y)
  int chain = 0;   // position along the arm: parts one apart are adjacent
  double mu = kArmFriction;
  dBodyID body = nullptr;
  std::vector<dGeomID> geoms;
  Transform<double> T = Transform<double>::identity();       // accepted pose, mm
  Transform<double> T_prev = Transform<double>::identity();  // at the start of the world step
  bool moved = false;
  Transform<double> T_set{};  // the pose last given to ODE
  double t_last_move = 0;  // when it last moved (s): a step's displacement is spread over the time since
};

struct Simulation::Object {
  dBodyID body = nullptr;  // null: static
  dGeomID geom = nullptr;
  bool movable = false, removed = false, carried = false;
  double mu = 0.8;
  Transform<double> T_tool_obj = Transform<double>::identity();  // carried: pose in the tool frame, mm
  Transform<double> T_carry = Transform<double>::identity();     // carried: accepted pose, mm
  Transform<double> T_carry_prev = Transform<double>::identity();
  double last_good[3] = {0, 0, 0};
};

struct Simulation::Pair {
  enum Kind { kGround, kStatic, kSelf, kMovable, kCarriedGround, kCarriedStatic } kind;
  dGeomID a = nullptr, b = nullptr;
  int max_contacts = kMaxContacts;  // kMaxMeshContacts when a or b is a mesh
  int part_a = -1;    // arm part (or -1: the carried object object_a)
  int object_a = -1;
  int part_b = -1;    // kSelf
  int object_b = -1;  // kStatic, kMovable, kCarriedStatic
  double accepted = 0;  // depth at the last accepted pose, mm
  double settled = 0;   // kMovable: depth after the last world step, mm
};

// A mesh file's triangles as ODE reads them (it keeps pointers to these arrays, so they live
// as long as the geoms: Simulation::meshes_ is destroyed after the geoms).
struct Simulation::MeshData {
  std::string path;
  std::vector<dReal> vertices;  // x y z, m
  std::vector<dTriIndex> indices;
  dTriMeshDataID data = nullptr;
  ~MeshData() {
    if (data) dGeomTriMeshDataDestroy(data);
  }
};

// An action of the kinematic model (a robot without motors; the firmware's own actions come
// from its session, FirmwareSession::Event).
struct Simulation::Action {
  enum Kind { kGripper, kJoints, kDwell } kind = kJoints;
  int line = 0;
  uint64_t start_tick = 0, end_tick = 0;
  double opening_to = 0;             // kGripper, mm
  std::vector<double> q_from, q_to;  // kJoints, model units
};

Simulation::Simulation(const Robot& robot, const Scene& scene, const SimOptions& options)
    : robot_(robot), scene_(scene), opt_(options) {
  init_ode();
  if (!(opt_.dt > 0 && opt_.dt <= 0.01)) throw std::invalid_argument("the world step must be in (0, 10] ms");
  motors_ = robot_.has_motors;
  n_motors_ = motors_ ? robot_.actuation.num_motors : 0;
  n_joints_ = robot_.model.num_joints;
  if (n_motors_ > 8) throw std::invalid_argument("more than 8 motors: the step replay handles 8 (as the firmware)");
  for (int i = 0; i < n_motors_ && size_t(i) < robot_.drive.motors.size(); ++i) {
    const MotorDriver& d = robot_.drive.motors[size_t(i)];
    if (d.kind != kDriveServo) continue;
    const MotorSpec& m = robot_.actuation.motors[i];
    const double ticks_per_deg = servo_ticks_per_deg(m);
    servo_[i] = has_servos_ = true;
    servo_rate_[i] = d.top_speed_deg_s * ticks_per_deg;
    servo_band_[i] = int32_t(std::floor(d.deadband_us * kServoTicksPerUs / 2));
  }
  // Mesh shapes: read every file once, before anything of ODE's exists to leak on an error.
  for (size_t li = 0; li < robot_.links.size(); ++li) {
    for (size_t si = 0; si < robot_.links[li].shapes.size(); ++si) {
      const Shape& s = robot_.links[li].shapes[si];
      if (s.type != Shape::Type::kMesh) continue;
      const std::string path = mesh_path(robot_, s);
      if (std::any_of(meshes_.begin(), meshes_.end(), [&](const auto& m) { return m->path == path; })) continue;
      TriangleMesh tm;
      try {
        tm = load_mesh_file(path);
      } catch (const MeshError& e) {
        throw std::invalid_argument(robot_.source + ": /links/" + std::to_string(li) + "/shapes/" + std::to_string(si) +
                                    ": " + e.what());
      }
      auto m = std::make_unique<MeshData>();
      m->path = path;
      for (const auto& v : tm.vertices)
        for (double c : {v.x, v.y, v.z}) m->vertices.push_back(c * kMm);
      for (const auto& t : tm.triangles)
        for (uint32_t i : t) m->indices.push_back(dTriIndex(i));
      meshes_.push_back(std::move(m));
    }
  }
  // The stall model needs every link's mass (a mesh's given "mass"): only when there are
  // pull-out curves to check against.
  if (motors_ && opt_.stall_check &&
      std::any_of(robot_.motor_torque.begin(), robot_.motor_torque.end(), [](const MotorTorque& t) { return t.given(); }))
    stall_ = std::make_unique<StallModel>(robot_);
  ticks_per_step_ = uint64_t(std::llround(opt_.dt * kStepTickHz));
  if (ticks_per_step_ == 0) ticks_per_step_ = 1;

  world_ = dWorldCreate();
  dWorldSetGravity(world_, scene_.gravity.x, scene_.gravity.y, scene_.gravity.z);
  dWorldSetERP(world_, 0.2);
  dWorldSetCFM(world_, 1e-6);
  dWorldSetContactMaxCorrectingVel(world_, 0.2);
  dWorldSetContactSurfaceLayer(world_, 0.0002);
  dWorldSetQuickStepNumIterations(world_, 20);
  dWorldSetAutoDisableFlag(world_, 1);
  dWorldSetAutoDisableLinearThreshold(world_, 0.002);
  dWorldSetAutoDisableAngularThreshold(world_, 0.02);
  dWorldSetAutoDisableSteps(world_, 10);
  dWorldSetAutoDisableTime(world_, 0);
  contacts_ = dJointGroupCreate(0);

  q_.assign(size_t(n_joints_), 0.0);
  q_try_ = q_;
  if (motors_) {
    joints_from_steps(q_.data(), robot_.actuation, counted_);
  } else {
    for (int j = 0; j < n_joints_ && size_t(j) < robot_.home.size(); ++j) q_[size_t(j)] = robot_.home[size_t(j)];
  }
  q_try_ = q_cmd_ = q_cmd_want_ = q_;
  opening_mm_ = opening_from_mm_ = robot_.gripper.present ? robot_.gripper.max_opening_mm : 0;
  grip_from_ = grip_to_ = opening_mm_;  // open until a program or a command says otherwise
  build_arm();
  build_scene();
  build_pairs();
  place_arm(q_.data(), opening_mm_);
  accept_pose();
  for (auto& p : parts_) p->T_prev = p->T;
  reset_controller();  // ready for command() without a program
}

Simulation::~Simulation() {
  dJointGroupDestroy(contacts_);
  for (auto& p : parts_)
    for (dGeomID g : p->geoms) dGeomDestroy(g);
  for (auto& o : objects_) dGeomDestroy(o.geom);
  if (ground_) dGeomDestroy(ground_);
  dWorldDestroy(world_);
}

// ---- building ----

void Simulation::build_arm() {
  const std::vector<LinkGeometry> links = arm_geometry(robot_);
  int chain = 0;
  for (const auto& l : links) {
    if (!parts_.empty() && parts_.back()->frame == l.frame) {
      // Two entries for one frame: one part.
    } else {
      auto p = std::make_unique<Part>();
      p->frame = l.frame;
      p->name = l.frame == 0 ? "base" : "link " + std::to_string(l.frame);
      p->chain = chain++;
      p->body = dBodyCreate(world_);
      dBodySetKinematic(p->body);
      dBodySetAutoDisableFlag(p->body, 1);
      parts_.push_back(std::move(p));
    }
    Part& p = *parts_.back();
    for (const Shape& s : l.shapes) {
      dGeomID g = nullptr;
      switch (s.type) {
        case Shape::Type::kBox: g = dCreateBox(nullptr, s.size[0] * kMm, s.size[1] * kMm, s.size[2] * kMm); break;
        case Shape::Type::kCylinder: g = dCreateCylinder(nullptr, s.size[0] * kMm, s.size[1] * kMm); break;
        case Shape::Type::kCapsule: g = dCreateCapsule(nullptr, s.size[0] * kMm, s.size[1] * kMm); break;
        case Shape::Type::kSphere: g = dCreateSphere(nullptr, s.size[0] * kMm); break;
        case Shape::Type::kMesh: {
          const std::string path = mesh_path(robot_, s);
          MeshData& m = **std::find_if(meshes_.begin(), meshes_.end(), [&](const auto& x) { return x->path == path; });
          if (!m.data) {
            m.data = dGeomTriMeshDataCreate();
            dGeomTriMeshDataBuildDouble(m.data, m.vertices.data(), 3 * sizeof(dReal), int(m.vertices.size() / 3),
                                        m.indices.data(), int(m.indices.size()), 3 * sizeof(dTriIndex));
            dGeomTriMeshDataPreprocess2(m.data, 1U << dTRIDATAPREPROCESS_BUILD_CONCAVE_EDGES, nullptr);
          }
          g = dCreateTriMesh(nullptr, m.data, nullptr, nullptr, nullptr);
          break;
        }
      }
      dGeomSetBody(g, p.body);
      dGeomSetOffsetPosition(g, s.T_frame_shape.p.x * kMm, s.T_frame_shape.p.y * kMm, s.T_frame_shape.p.z * kMm);
      dMatrix3 R;
      to_ode(s.T_frame_shape.R, R);
      dGeomSetOffsetRotation(g, R);
      p.geoms.push_back(g);
    }
  }
  if (robot_.gripper.present) {
    const Gripper& gr = robot_.gripper;
    for (int side : {+1, -1}) {
      auto p = std::make_unique<Part>();
      p->name = side > 0 ? "finger left" : "finger right";
      p->side = side;
      p->chain = chain;  // both adjacent to the last link and to each other
      p->mu = kFingerFriction;
      p->body = dBodyCreate(world_);
      dBodySetKinematic(p->body);
      dBodySetAutoDisableFlag(p->body, 1);
      dGeomID g = dCreateBox(nullptr, gr.finger_length_mm * kMm, robot_.gripper.finger_thickness_mm * kMm,
                             robot_.gripper.finger_height_mm * kMm);
      dGeomSetBody(g, p->body);
      p->geoms.push_back(g);
      finger_[side > 0 ? 0 : 1] = int(parts_.size());
      parts_.push_back(std::move(p));
    }
  }
}

void Simulation::build_scene() {
  if (scene_.ground) ground_ = dCreatePlane(nullptr, 0, 0, 1, 0);
  for (const SceneObject& so : scene_.objects) {
    Object o;
    o.movable = so.movable;
    o.mu = so.friction;
    switch (so.type) {
      case SceneObject::Type::kBox: o.geom = dCreateBox(nullptr, so.size[0] * kMm, so.size[1] * kMm, so.size[2] * kMm); break;
      case SceneObject::Type::kCylinder: o.geom = dCreateCylinder(nullptr, so.size[0] * kMm, so.size[1] * kMm); break;
      case SceneObject::Type::kSphere: o.geom = dCreateSphere(nullptr, so.size[0] * kMm); break;
    }
    const Mat3<double> R = rpy_to_matrix(so.rpy_deg.x * M_PI / 180, so.rpy_deg.y * M_PI / 180, so.rpy_deg.z * M_PI / 180);
    dMatrix3 Rd;
    to_ode(R, Rd);
    if (so.movable) {
      o.body = dBodyCreate(world_);
      dMass m;
      const double kg = so.mass_kg();
      switch (so.type) {
        case SceneObject::Type::kBox: dMassSetBoxTotal(&m, kg, so.size[0] * kMm, so.size[1] * kMm, so.size[2] * kMm); break;
        case SceneObject::Type::kCylinder: dMassSetCylinderTotal(&m, kg, 3, so.size[0] * kMm, so.size[1] * kMm); break;
        case SceneObject::Type::kSphere: dMassSetSphereTotal(&m, kg, so.size[0] * kMm); break;
      }
      dBodySetMass(o.body, &m);
      dGeomSetBody(o.geom, o.body);
      dBodySetPosition(o.body, so.xyz.x * kMm, so.xyz.y * kMm, so.xyz.z * kMm);
      dBodySetRotation(o.body, Rd);
      o.last_good[0] = so.xyz.x * kMm, o.last_good[1] = so.xyz.y * kMm, o.last_good[2] = so.xyz.z * kMm;
    } else {
      dGeomSetPosition(o.geom, so.xyz.x * kMm, so.xyz.y * kMm, so.xyz.z * kMm);
      dGeomSetRotation(o.geom, Rd);
    }
    objects_.push_back(o);
  }
  // Contact bookkeeping: others = ground, every object, every arm part.
  n_others_ = 1 + int(objects_.size()) + int(parts_.size());
  other_names_.push_back("ground");
  for (const auto& so : scene_.objects) other_names_.push_back(so.name);
  for (const auto& p : parts_) other_names_.push_back(p->name);
  touching_.assign(objects_.size() * size_t(n_others_), 0);
  touched_now_ = touching_;
  touch_point_.assign(touching_.size(), dContactGeom{});
  last_touch_.assign(touching_.size(), 0);
}

void Simulation::build_pairs() {
  for (size_t pi = 0; pi < parts_.size(); ++pi) {
    const Part& p = *parts_[pi];
    if (p.frame == 0) continue;  // the base never moves: nothing to refuse
    for (dGeomID g : p.geoms) {
      if (ground_) {
        Pair q{Pair::kGround};
        q.a = g, q.b = ground_, q.part_a = int(pi);
        block_pairs_.push_back(q);
      }
      for (size_t oi = 0; oi < objects_.size(); ++oi) {
        Pair q{objects_[oi].movable ? Pair::kMovable : Pair::kStatic};
        q.a = g, q.b = objects_[oi].geom, q.part_a = int(pi), q.object_b = int(oi);
        block_pairs_.push_back(q);
      }
    }
  }
  // Self pairs: parts not adjacent along the arm, and not overlapping where the arm starts
  // (rough shapes often overlap at a joint by design: a note says which were left out).
  place_arm(q_.data(), opening_mm_);
  for (size_t i = 0; i < parts_.size(); ++i) {
    for (size_t j = i + 1; j < parts_.size(); ++j) {
      if (std::abs(parts_[i]->chain - parts_[j]->chain) <= 1) continue;
      bool overlap = false;
      std::vector<Pair> these;
      for (dGeomID a : parts_[i]->geoms) {
        for (dGeomID b : parts_[j]->geoms) {
          dContactGeom c[kMaxContacts];
          if (aabb_overlap(a, b) && dCollide(a, b, kMaxContacts, c, sizeof(dContactGeom)) > 0) overlap = true;
          Pair q{Pair::kSelf};
          q.a = a, q.b = b, q.part_a = int(parts_[i]->frame == 0 ? j : i), q.part_b = int(parts_[i]->frame == 0 ? i : j);
          if (parts_[i]->frame == 0) std::swap(q.a, q.b);  // part_a is the one that moves
          these.push_back(q);
        }
      }
      if (overlap) {
        SimEvent e;
        e.kind = SimEvent::Kind::kNote;
        e.a = parts_[i]->name, e.b = parts_[j]->name;
        e.detail = "overlap where the arm starts: their collisions are not checked";
        events_.push_back(e);
      } else {
        block_pairs_.insert(block_pairs_.end(), these.begin(), these.end());
      }
    }
  }
  // A carried object becomes part of the arm: it may not go into the ground or a static object.
  for (size_t oi = 0; oi < objects_.size(); ++oi) {
    if (!objects_[oi].movable) continue;
    if (ground_) {
      Pair q{Pair::kCarriedGround};
      q.a = objects_[oi].geom, q.b = ground_, q.object_a = int(oi);
      block_pairs_.push_back(q);
    }
    for (size_t si = 0; si < objects_.size(); ++si) {
      if (objects_[si].movable) continue;
      Pair q{Pair::kCarriedStatic};
      q.a = objects_[oi].geom, q.b = objects_[si].geom, q.object_a = int(oi), q.object_b = int(si);
      block_pairs_.push_back(q);
    }
  }
  // Mesh pairs: more contacts (see kMaxMeshContacts). Mesh against mesh collides in ODE, but
  // its depth is the size of the triangles touching rather than the overlap (20 mm for
  // 0.5 mm): the step check then stops the arm at their first touch, and says so once.
  bool mesh_mesh_noted = false;
  for (auto& q : block_pairs_) {
    if (!is_mesh(q.a) && !is_mesh(q.b)) continue;
    q.max_contacts = kMaxMeshContacts;
    if (q.kind == Pair::kSelf && is_mesh(q.a) && is_mesh(q.b) && !mesh_mesh_noted) {
      mesh_mesh_noted = true;
      SimEvent e;
      e.kind = SimEvent::Kind::kNote;
      e.a = parts_[size_t(q.part_a)]->name, e.b = parts_[size_t(q.part_b)]->name;
      e.detail = "mesh against mesh: ODE gives no true depth for it, so such parts are stopped at their first touch "
                 "(and the depth the event gives is not the overlap)";
      events_.push_back(e);
    }
  }
  block_depth_.assign(block_pairs_.size(), 0.0);
}

// ---- the arm's pose ----

void Simulation::set_part_pose(Part& p, const Transform<double>& T) {
  if (std::memcmp(&T, &p.T_set, sizeof T) == 0) return;  // ODE re-normalises a rotation it is given: skip
  p.T_set = T;
  dBodySetPosition(p.body, T.p.x * kMm, T.p.y * kMm, T.p.z * kMm);
  dMatrix3 R;
  to_ode(T.R, R);
  dBodySetRotation(p.body, R);
}

void Simulation::place_arm(const double* q, double opening_mm) {
  HostFrames f;
  forward_kinematics(f, robot_.model, q);
  for (auto& pp : parts_) {
    Part& p = *pp;
    Transform<double> T;
    if (p.frame >= 0) {
      T = f.T_base_frame[p.frame];
    } else {
      T = finger_pose(robot_.gripper, f.T_base_tool, opening_mm, p.side);
    }
    set_part_pose(p, T);
  }
  for (auto& o : objects_) {
    if (!o.carried) continue;
    const Transform<double> T = f.T_base_tool * o.T_tool_obj;
    dBodySetPosition(o.body, T.p.x * kMm, T.p.y * kMm, T.p.z * kMm);
    dMatrix3 R;
    to_ode(T.R, R);
    dBodySetRotation(o.body, R);
  }
  frames_try_ = f;
}

// The candidate pose (placed) against every block pair: false and an event (once per
// action) when a step would push the arm into something.
bool Simulation::check_pose(int line) {
  const double tol = opt_.touch_tolerance_mm;
  int worst = -1;
  dContactGeom worst_c{};
  for (size_t k = 0; k < block_pairs_.size(); ++k) {
    Pair& q = block_pairs_[k];
    block_depth_[k] = 0;
    if (q.object_a >= 0 && !objects_[size_t(q.object_a)].carried) continue;
    if (q.kind == Pair::kMovable) {
      const Object& o = objects_[size_t(q.object_b)];
      if (o.removed || o.carried) continue;
    }
    if (!aabb_overlap(q.a, q.b)) continue;
    dContactGeom c[kMaxMeshContacts];
    const int n = dCollide(q.a, q.b, q.max_contacts, c, sizeof(dContactGeom));
    double depth = 0;
    int deepest = -1;
    for (int i = 0; i < n; ++i)
      if (c[i].depth / kMm > depth) depth = c[i].depth / kMm, deepest = i;
    block_depth_[k] = depth;
    const bool refuse = q.kind == Pair::kMovable ? (q.settled > opt_.squeeze_mm && depth > q.settled + 1e-6)
                                                 : (depth > tol && depth > q.accepted + 1e-6);
    if (refuse && worst < 0) {
      worst = int(k);
      worst_c = c[deepest];
    }
  }
  if (worst < 0) return true;
  if (!blocked_reported_) {
    blocked_reported_ = true;
    const Pair& q = block_pairs_[size_t(worst)];
    const std::string a = q.part_a >= 0 ? parts_[size_t(q.part_a)]->name : scene_.objects[size_t(q.object_a)].name +
                                                                                 " (carried)";
    std::string b;
    SimEvent::Kind kind = SimEvent::Kind::kCollision;
    switch (q.kind) {
      case Pair::kGround:
      case Pair::kCarriedGround: b = "ground"; break;
      case Pair::kStatic:
      case Pair::kCarriedStatic: b = scene_.objects[size_t(q.object_b)].name; break;
      case Pair::kSelf: b = parts_[size_t(q.part_b)]->name, kind = SimEvent::Kind::kSelfCollision; break;
      case Pair::kMovable: b = scene_.objects[size_t(q.object_b)].name, kind = SimEvent::Kind::kSqueeze; break;
    }
    current_line_ = line;
    event(kind, a, b,
          "the next step would go " + fmt_mm(block_depth_[size_t(worst)]) + " mm deep: the arm holds at contact" +
              (motors_ ? ", the motors skip the steps" : ""),
          &worst_c);
    events_.back().depth_mm = block_depth_[size_t(worst)];
  }
  return false;
}

void Simulation::accept_pose() {
  for (size_t k = 0; k < block_pairs_.size(); ++k) block_pairs_[k].accepted = block_depth_[k];
  frames_ = frames_try_;
  for (auto& pp : parts_) {
    Part& p = *pp;
    const Transform<double> T = p.frame >= 0 ? frames_.T_base_frame[p.frame]
                                             : finger_pose(robot_.gripper, frames_.T_base_tool, opening_mm_, p.side);
    if (!p.moved) {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) p.moved = p.moved || T.R.m[i][j] != p.T.R.m[i][j];
      p.moved = p.moved || T.p.x != p.T.p.x || T.p.y != p.T.p.y || T.p.z != p.T.p.z;
    }
    p.T = T;
    arm_moved_ = arm_moved_ || p.moved;
  }
  for (auto& o : objects_)
    if (o.carried) o.T_carry = frames_.T_base_tool * o.T_tool_obj;
}

// Back to the accepted pose, without the kinematics.
void Simulation::restore_arm() {
  for (auto& p : parts_) set_part_pose(*p, p->T);
  for (auto& o : objects_) {
    if (!o.carried) continue;
    dBodySetPosition(o.body, o.T_carry.p.x * kMm, o.T_carry.p.y * kMm, o.T_carry.p.z * kMm);
    dMatrix3 R;
    to_ode(o.T_carry.R, R);
    dBodySetRotation(o.body, R);
  }
  frames_try_ = frames_;
}

// Places the arm at (q, opening) and keeps it there unless a step would push it into something.
bool Simulation::try_joints(const double* q, double opening_mm) {
  place_arm(q, opening_mm);
  if (!check_pose(current_line_)) {
    restore_arm();
    return false;
  }
  opening_mm_ = opening_mm;
  std::copy(q, q + n_joints_, q_.begin());
  accept_pose();
  return true;
}

// ---- the program ----

void Simulation::reset_controller() {
  if (motors_) {
    if (!firmware_) {  // one firmware for the simulation's life: it goes on from where it is
      firmware_ = std::make_unique<FirmwareSession>(robot_, opt_.settings);
      lines_robot_ = robot_;
      FirmwareSession* fw = firmware_.get();
      lines_ = std::make_unique<StatementLines>(lines_robot_, opt_.settings.value[ControllerSettings::kMaxRate],
                                                [fw] { return fw->commanded(); });
    }
  } else {
    kinematic_ = std::make_unique<KinematicModel>(robot_);
  }
  queued_q_ = q_;
  queued_percent_ = -1;
}

void Simulation::load_program(const Program& program) {
  actions_.clear();
  action_ = 0;
  action_running_ = false;
  pending_.clear();
  pending_next_ = 0;
  reset_controller();
  const uint64_t now = steps_ * ticks_per_step_;
  queue_end_tick_ = now;
  grip_from_ = grip_to_ = opening_mm_;
  if (motors_) {  // each line once the arm is at rest after the one before, as the harness sends
    for (const Statement& st : program.statements) send(st, now, FirmwareSession::kAtRest);
    program_end_s_ = double(firmware_->run_to_rest()) / kStepTickHz;
    return;
  }
  for (const Statement& st : program.statements) enqueue(st, now);
  program_end_s_ = double(queue_end_tick_) / kStepTickHz;
}

Status Simulation::command(const std::string& line) {
  Statement st{Statement::Kind::kProtocol, {}, line, 0};
  if (motors_) {  // as soon as the reply before is off the wire: a streamed program
    const Status s = send(st, steps_ * ticks_per_step_, FirmwareSession::kStreamed);
    program_end_s_ = std::max(program_end_s_, double(firmware_->now()) / kStepTickHz);
    return s;
  }
  const size_t rejected_before = pending_.size();
  enqueue(st, steps_ * ticks_per_step_);
  return pending_.size() > rejected_before ? pending_.back().reply : kOk;
}

// A rejected line: an event at `tick`.
SimEvent Simulation::rejection(uint64_t tick, int line, const std::string& text, Status s, const std::string& note) {
  SimEvent e;
  e.kind = SimEvent::Kind::kRejected;
  e.t = double(tick) / kStepTickHz;
  e.line = line;
  e.a = text;
  e.reply = s;
  e.detail = std::string("error:") + std::to_string(int(s)) + " " + status_text(s) + ", nothing moves" +
             (note.empty() ? "" : "; " + note);
  return e;
}

// ... shown when the clock reaches it.
void Simulation::rejected(uint64_t tick, int line, const std::string& text, Status s, const std::string& note) {
  pending_.push_back(rejection(tick, line, text, s, note));
}

// One statement to the firmware, as `sender` sends it. Its reply; a refusal, the firmware's or
// the host's own (a line that does not parse, an a without a solution), is an event at the
// reply's tick.
Status Simulation::send(const Statement& st, uint64_t now_tick, FirmwareSession::Sender sender) {
  PredictRecord r;
  std::string line;
  if (!lines_->begin(st, r, line)) {
    if (r.reply != kOk) rejected(std::max(now_tick, firmware_->now()), r.line, r.text, r.reply, r.note);
    return r.reply;
  }
  const Status s = firmware_->send(line, st.line, now_tick, sender);
  if (s != kOk) rejected(firmware_->now(), st.line, r.text, s, "");  // (at its reply, in the order sent)
  return s;
}

// One statement through the kinematic model; an accepted one becomes an action that starts
// when the queue before it ends (or now, when the arm is idle) and lasts as long as the model
// says. A whole program at t = 0 is so queued back to back from rest to rest.
void Simulation::enqueue(const Statement& st, uint64_t now_tick) {
  const uint64_t start = std::max(now_tick, queue_end_tick_);
  {
    const RunRecord r = kinematic_->execute(st);
    if (r.reply != kOk) {
      rejected(start, r.line, r.text, r.reply, r.note);
      return;
    }
    Action a;
    a.line = r.line;
    if (!r.via_joints.empty() && r.line_speed > 0) {  // T: a move per segment, along its line at its speed
      uint64_t t = start;
      for (size_t k = 0; k < r.via_joints.size(); ++k) {
        Action seg = a;
        seg.kind = Action::kJoints;
        seg.q_from = queued_q_;
        seg.q_to.resize(size_t(n_joints_));
        for (int j = 0; j < n_joints_; ++j) seg.q_to[size_t(j)] = joint_to_model(robot_, j, r.via_joints[k][size_t(j)]);
        seg.start_tick = t;
        seg.end_tick = t = start + uint64_t(std::ceil((r.via_mm[k] / r.line_speed) * kStepTickHz));
        queued_q_ = seg.q_to;
        actions_.push_back(seg);
      }
      queue_end_tick_ = t;
      program_end_s_ = double(queue_end_tick_) / kStepTickHz;
      return;
    }
    std::vector<double> q_to(static_cast<size_t>(n_joints_));
    for (int j = 0; j < n_joints_; ++j) q_to[size_t(j)] = joint_to_model(robot_, j, r.joints[size_t(j)]);
    double duration = opt_.joints.move_s(robot_, queued_q_.data(), q_to.data());
    if (duration > 0) {
      a.kind = Action::kJoints;
      a.q_from = queued_q_;
      a.q_to = q_to;
      queued_q_ = q_to;
    } else if (r.gripper_percent != queued_percent_ || is_gripper_statement(st)) {
      a.kind = Action::kGripper;
      duration = opt_.joints.gripper_settle_s;
      queued_percent_ = r.gripper_percent;
      a.opening_to = robot_.gripper.max_opening_mm * (queued_percent_ < 0 ? 100 : queued_percent_) / 100.0;
    } else if (r.dwell_s > 0) {
      a.kind = Action::kDwell;
      duration = r.dwell_s;
    } else {
      return;
    }
    a.start_tick = start;
    a.end_tick = start + uint64_t(std::ceil(duration * kStepTickHz));
    actions_.push_back(a);
    queue_end_tick_ = a.end_tick;
  }
  program_end_s_ = double(queue_end_tick_) / kStepTickHz;
}

void Simulation::begin_action(size_t index) {
  Action& a = actions_[index];
  action_running_ = true;
  blocked_reported_ = false;
  current_line_ = a.line;
  event_tick_ = a.start_tick;
  std::fill(std::begin(lost_in_action_), std::end(lost_in_action_), 0);
  switch (a.kind) {
    case Action::kGripper:
      grip_from_ = target_opening(double(a.start_tick) / kStepTickHz);
      grip_to_ = a.opening_to;
      grip_t0_ = double(a.start_tick) / kStepTickHz;
      grip_t1_ = double(a.end_tick) / kStepTickHz;
      return;
    case Action::kJoints:
    case Action::kDwell: return;
  }
}

// Will the motors keep up with this move? The stall model (stall.h) samples it at the
// firmware's step times from the counted steps, with whatever the gripper carries as the
// payload; a motor that needs more than its pull-out torque gives a `stall` event at the
// start of the move, saying when in the move it happens.
void Simulation::stall_check(const std::vector<int32_t>& delta, const MotionSettings& motion) {
  if (!stall_) return;
  std::vector<double> start_deg(static_cast<size_t>(n_motors_));
  for (int i = 0; i < n_motors_; ++i)
    start_deg[size_t(i)] = steps_to_degrees<double>(robot_.actuation.motors[i], counted_[i]);
  ControllerSettings settings = opt_.settings;
  settings.value[ControllerSettings::kMaxRate] = motion.max_rate;
  settings.value[ControllerSettings::kAccel] = motion.accel;
  double payload_kg = 0;
  for (size_t i = 0; i < objects_.size(); ++i)
    if (objects_[i].carried) payload_kg += scene_.objects[i].mass_kg();
  const MoveCheck check = stall_->check_steps(start_deg, delta, settings, payload_kg);
  if (!check.skips) return;
  for (int i = 0; i < n_motors_; ++i) {
    const MotorCheck& m = check.motors[size_t(i)];
    if (!m.skips) continue;
    char text[200];
    std::snprintf(text, sizeof text,
                  "would skip steps %.3f s into the move: needs %.3f N*m, its pull-out torque at %.0f full steps/s is "
                  "%.3f N*m (payload %.0f g)",
                  m.at_s, m.at_worst.required_nm, m.at_worst.full_steps_per_s, m.at_worst.available_nm,
                  payload_kg * 1000);
    event(SimEvent::Kind::kStall, "motor " + robot_.motor_names[size_t(i)], "", text);
  }
}

// The firmware's action running ended at `tick` (the next one began, or its step timer
// stopped): the steps the arm could not make, if any, as an event.
void Simulation::firmware_action_ends(uint64_t tick) {
  if (!firmware_action_) return;
  firmware_action_ = false;
  std::string lost;
  for (int i = 0; i < n_motors_; ++i) {
    if (lost_in_action_[i] == 0) continue;
    const double deg = steps_to_degrees<double>(robot_.actuation.motors[i], lost_in_action_[i]) -
                       steps_to_degrees<double>(robot_.actuation.motors[i], 0);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%s %d steps (%.2f deg)", lost.empty() ? "" : ", ",
                  robot_.motor_names[size_t(i)].c_str(), int(std::abs(lost_in_action_[i])), std::fabs(deg));
    lost += buf;
  }
  if (lost.empty()) return;
  SimEvent e;
  e.kind = SimEvent::Kind::kStepsLost;
  e.t = double(tick) / kStepTickHz;
  e.line = current_line_;
  e.detail = "skipped " + lost +
             ": the controller does not know (open loop), so the arm stays that far off its counted "
             "position until it is homed against endstops (H) or re-zeroed (Z)";
  events_.push_back(e);
}

// The firmware's step counts now `counted` (Z, homing, each action's start): the arm stays
// where it is, so what it is off its counts changes by as much.
void Simulation::recount(const std::vector<int32_t>& counted) {
  for (int i = 0; i < n_motors_ && i < int(counted.size()); ++i) {
    offset_[i] += counted_[i] - counted[size_t(i)];
    counted_[i] = counted[size_t(i)];
  }
}

void Simulation::end_action() {
  const Action& a = actions_[action_];
  if (a.kind == Action::kJoints) {
    double worst = 0;
    for (int j = 0; j < n_joints_; ++j) worst = std::max(worst, std::fabs(q_[size_t(j)] - a.q_to[size_t(j)]));
    if (worst > 1e-9) {
      SimEvent e;
      e.kind = SimEvent::Kind::kBlocked;
      e.t = double(a.end_tick) / kStepTickHz;
      e.line = a.line;
      char buf[120];
      std::snprintf(buf, sizeof buf, "the move ended %.3f (deg or mm) short of its target; the joints follow later", 
                    robot_.model.joints[0].param != kParamD ? worst * 180 / M_PI : worst);
      e.detail = buf;
      events_.push_back(e);
    }
  }
  action_running_ = false;
  ++action_;
}

// ---- motion within a world step ----

bool Simulation::try_steps(const int32_t* steps) {
  joints_from_steps(q_try_.data(), robot_.actuation, steps);
  return try_joints(q_try_.data(), opening_mm_);
}

// One step event of the firmware: the counts always change; the arm follows unless blocked,
// motor by motor.
void Simulation::apply_steps(uint8_t mask, uint8_t negative) {
  // A servo's step changes its command only: servo_follow() turns it.
  for (int i = 0; i < n_motors_; ++i) {
    if (!servo_[i] || !(mask & (1u << i))) continue;
    const int32_t d = (negative & (1u << i)) ? -1 : 1;
    counted_[i] += d;
    offset_[i] -= d;
    mask = uint8_t(mask & ~(1u << i));
  }
  if (mask == 0) return;
  int32_t phys[8], delta[8] = {0};
  for (int i = 0; i < n_motors_; ++i) {
    phys[i] = counted_[i] + offset_[i];
    if (mask & (1u << i)) {
      delta[i] = (negative & (1u << i)) ? -1 : 1;
      counted_[i] += delta[i];
    }
  }
  int32_t cand[8];
  for (int i = 0; i < n_motors_; ++i) cand[i] = phys[i] + delta[i];
  if (try_steps(cand)) return;
  // more than one motor: perhaps some can go on
  const uint8_t accepted = (mask & (mask - 1)) ? try_motor_by_motor(phys, delta, mask) : 0;
  for (int i = 0; i < n_motors_; ++i) {
    if (!(mask & (1u << i)) || (accepted & (1u << i))) continue;
    offset_[i] -= delta[i];
    lost_in_action_[i] += delta[i];
  }
}

// A servo arm's servos over one world step: each one whose command (its pulse's ticks) lies
// beyond half its dead band of where it stands turns towards it at its top speed, and stops as
// soon as it is within the band; a blocked one stays.
void Simulation::servo_follow(double dt) {
  int32_t cand[8], move[8] = {0};
  uint8_t moving = 0;  // the servos that turn this step
  for (int i = 0; i < n_motors_; ++i) {
    cand[i] = counted_[i] + offset_[i];
    if (!servo_[i]) continue;
    const int32_t err = -offset_[i];  // command less position
    if (std::abs(err) <= servo_band_[i]) {
      servo_carry_[i] = 0;
      continue;
    }
    servo_carry_[i] += servo_rate_[i] * dt;
    const int32_t n = std::min<int32_t>(int32_t(servo_carry_[i]), std::abs(err) - servo_band_[i]);
    servo_carry_[i] -= n;
    if (n == 0) continue;
    move[i] = err > 0 ? n : -n;
    cand[i] += move[i];
    moving = uint8_t(moving | (1u << i));
  }
  if (!moving) return;
  if (!try_steps(cand)) {  // blocked: the servos that can go on alone
    int32_t from[8];
    for (int i = 0; i < n_motors_; ++i) from[i] = counted_[i] + offset_[i];
    moving = try_motor_by_motor(from, move, moving);
  }
  for (int i = 0; i < n_motors_; ++i)
    if (moving & (1u << i)) offset_[i] += move[i];
}

// After a blocked move of the motors in `mask` from `from` by `move` (steps): which of them can
// go on, tried one by one in motor order, each beside those already let go.
uint8_t Simulation::try_motor_by_motor(const int32_t* from, const int32_t* move, uint8_t mask) {
  int32_t cand[8];
  uint8_t accepted = 0;
  for (int i = 0; i < n_motors_; ++i) {
    if (!(mask & (1u << i))) continue;
    for (int k = 0; k < n_motors_; ++k) cand[k] = from[k] + ((accepted & (1u << k)) ? move[k] : 0);
    cand[i] += move[i];
    if (try_steps(cand)) accepted = uint8_t(accepted | (1u << i));
  }
  return accepted;
}

// The firmware's events up to `until`, each at its tick: its coils' steps move the arm (unless
// something blocks it), its actions say which line runs and what the gripper does.
void Simulation::motor_events(uint64_t until) {
  firmware_->run_to(until);
  for (const FirmwareSession::Event& e : firmware_->take(until)) {
    event_tick_ = e.tick;
    switch (e.kind) {
      case FirmwareSession::Event::kStep:
        apply_steps(e.mask, e.negative);
        break;
      case FirmwareSession::Event::kBegin:
        firmware_action_ends(e.tick);
        recount(e.counted);
        firmware_action_ = true;
        blocked_reported_ = false;
        current_line_ = e.line;
        std::fill(std::begin(lost_in_action_), std::end(lost_in_action_), 0);
        if (e.action == FirmwareSession::Event::kMove || e.action == FirmwareSession::Event::kHome)
          stall_check(e.delta, e.motion);
        if (e.action == FirmwareSession::Event::kGripper) {
          grip_from_ = target_opening(double(e.tick) / kStepTickHz);
          grip_to_ = robot_.gripper.max_opening_mm * e.percent / 100.0;
          grip_t0_ = double(e.tick) / kStepTickHz;
          grip_t1_ = double(e.tick + e.settle_ticks) / kStepTickHz;
        }
        break;
      case FirmwareSession::Event::kIdle:
        firmware_action_ends(e.tick);
        recount(e.counted);
        break;
      case FirmwareSession::Event::kReply:
        if (!e.counted.empty()) recount(e.counted);  // (a refused line: an event since it was sent)
        break;
    }
  }
}

// Robots without motors: ideal position servos; after a block they catch up at twice the speed.
void Simulation::follow_joints(const std::vector<double>& q_cmd, double dt) {
  bool moves = false;
  for (int j = 0; j < n_joints_; ++j) {
    const bool angle = joint_is_angle(robot_, j);
    const double max = 2 * dt * (angle ? deg_to_rad(opt_.joints.speed_deg) : opt_.joints.speed_mm);
    const double d = std::clamp(q_cmd[size_t(j)] - q_[size_t(j)], -max, max);
    q_try_[size_t(j)] = q_[size_t(j)] + d;
    moves = moves || d != 0;
  }
  if (!moves) return;
  if (steps_ < retry_after_step_) return;
  std::vector<double>& cand = q_try_;
  if (try_joints(cand.data(), opening_mm_)) return;
  // Blocked: joint by joint, those that can go on do; then wait 10 ms before trying again.
  retry_after_step_ = steps_ + std::max<uint64_t>(1, uint64_t(std::llround(0.01 / opt_.dt)));
  std::vector<double>& want = q_cmd_want_;
  want = cand;
  for (int j = 0; j < n_joints_; ++j) {
    if (want[size_t(j)] == q_[size_t(j)]) continue;
    cand = q_;
    cand[size_t(j)] = want[size_t(j)];
    try_joints(cand.data(), opening_mm_);
  }
}

void Simulation::joint_follow(double t_end) {
  const uint64_t until = uint64_t(std::llround(t_end * kStepTickHz));
  for (;;) {
    if (!action_running_) {
      if (action_ >= actions_.size() || actions_[action_].start_tick > until) break;
      begin_action(action_);
      continue;
    }
    Action& a = actions_[action_];
    if (a.end_tick > until) break;
    if (a.kind == Action::kJoints) follow_joints(a.q_to, opt_.dt);
    end_action();
  }
  if (action_running_ && actions_[action_].kind == Action::kJoints) {
    const Action& a = actions_[action_];
    const double f = double(until - a.start_tick) / double(a.end_tick - a.start_tick);
    std::vector<double>& cmd = q_cmd_;
    for (int j = 0; j < n_joints_; ++j)
      cmd[size_t(j)] = a.q_from[size_t(j)] + f * (a.q_to[size_t(j)] - a.q_from[size_t(j)]);
    follow_joints(cmd, opt_.dt);
  } else if (action_ > 0 && !action_running_) {
    follow_joints(actions_[action_ - 1].kind == Action::kJoints ? actions_[action_ - 1].q_to : q_, opt_.dt);
  }
}

double Simulation::target_opening(double t) const {
  if (t >= grip_t1_ || grip_t1_ <= grip_t0_) return grip_to_;
  if (t <= grip_t0_) return grip_from_;
  return grip_from_ + (grip_to_ - grip_from_) * (t - grip_t0_) / (grip_t1_ - grip_t0_);
}

void Simulation::gripper_follow(double t_end) {
  if (!robot_.gripper.present) return;
  double cand = target_opening(t_end);
  bool carrying = false;
  for (const auto& o : objects_) carrying = carrying || o.carried;
  if (grip_stalled_) {
    if (cand > grip_stall_mm_ + 1e-9) {
      grip_stalled_ = false;
      for (size_t i = 0; i < objects_.size(); ++i) {
        Object& o = objects_[i];
        if (!o.carried) continue;
        o.carried = false;
        dBodySetDynamic(o.body);
        dBodyEnable(o.body);
        current_line_ = action_running_ ? actions_[action_].line : current_line_;
        const Transform<double> T = object_pose(int(i));
        SimEvent e;
        e.kind = SimEvent::Kind::kRelease;
        e.t = t_end, e.line = current_line_, e.a = "gripper", e.b = scene_.objects[i].name;
        e.has_point = true, e.point_mm = T.p;
        e.detail = "the gripper opens: the object is free";
        events_.push_back(e);
      }
    } else {
      cand = opening_mm_;
    }
  }
  if (std::fabs(cand - opening_mm_) < 1e-12) return;
  const bool closing = cand < opening_mm_;
  const bool reported = blocked_reported_;
  blocked_reported_ = true;  // the gripper's own event below
  const bool ok = try_joints(q_.data(), cand);
  blocked_reported_ = reported;
  if (!ok) {
    grip_stalled_ = true;
    grip_stall_mm_ = opening_mm_;
    event(SimEvent::Kind::kGripperBlocked, "gripper", "",
          "the fingers stop at " + fmt_mm(opening_mm_) + " mm: something they cannot grasp is in the way");
    return;
  }
  if (closing && !carrying) grasp_check();
}

void Simulation::grasp_check() {
  for (size_t i = 0; i < objects_.size(); ++i) {
    Object& o = objects_[i];
    if (!o.movable || o.removed || o.carried) continue;
    bool touch[2] = {false, false};
    for (int f = 0; f < 2; ++f) {
      for (dGeomID g : parts_[size_t(finger_[f])]->geoms) {
        dContactGeom c[kMaxContacts];
        if (aabb_overlap(g, o.geom) && dCollide(g, o.geom, kMaxContacts, c, sizeof(dContactGeom)) > 0) touch[f] = true;
      }
    }
    if (!(touch[0] && touch[1])) continue;
    const Transform<double> T = object_pose(int(i));
    o.carried = true;
    dBodySetLinearVel(o.body, 0, 0, 0);
    dBodySetAngularVel(o.body, 0, 0, 0);
    dBodySetKinematic(o.body);
    o.T_tool_obj = inverse(frames_.T_base_tool) * T;
    o.T_carry = o.T_carry_prev = T;
    grip_stalled_ = true;
    grip_stall_mm_ = opening_mm_;
    SimEvent e;
    e.kind = SimEvent::Kind::kGrasp;
    e.t = time() + opt_.dt, e.line = current_line_, e.a = "gripper", e.b = scene_.objects[i].name;
    e.has_point = true, e.point_mm = T.p;
    e.detail = "both fingers touch it while closing: the servo stalls at " + fmt_mm(opening_mm_) +
               " mm and the object moves with the tool";
    events_.push_back(e);
    return;
  }
}

// ---- the world step ----

void Simulation::event(SimEvent::Kind k, const std::string& a, const std::string& b, const std::string& detail,
                       const dContactGeom* c) {
  SimEvent e;
  e.kind = k;
  e.t = motors_ && k != SimEvent::Kind::kContactStarted && k != SimEvent::Kind::kContactEnded
            ? double(event_tick_) / kStepTickHz
            : time() + opt_.dt;
  e.line = current_line_;
  e.a = a, e.b = b, e.detail = detail;
  if (c) {
    e.has_point = true;
    e.point_mm = make_vec3(c->pos[0] / kMm, c->pos[1] / kMm, c->pos[2] / kMm);
  }
  events_.push_back(e);
}

void Simulation::add_contact(dGeomID a, dGeomID b, double mu, int touch_index, bool joints) {
  if (!aabb_overlap(a, b)) {
    if (touched_now_[size_t(touch_index)] == 2) touched_now_[size_t(touch_index)] = 0;
    return;
  }
  dContactGeom cg[kMaxContacts];
  const int n = dCollide(a, b, kMaxContacts, cg, sizeof(dContactGeom));
  if (n <= 0) {
    if (touched_now_[size_t(touch_index)] == 2) touched_now_[size_t(touch_index)] = 0;
    return;
  }
  if (touched_now_[size_t(touch_index)] != 1) touch_point_[size_t(touch_index)] = cg[0];
  touched_now_[size_t(touch_index)] = 1;
  if (!joints) return;
  dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
  if (ba && !dBodyIsEnabled(ba)) {
    // Asleep and only grazed (an arm creeping along it, a step away from it): let it sleep;
    // a real push goes deeper than the surface layer within a step.
    double depth = 0;
    for (int i = 0; i < n; ++i) depth = std::max(depth, double(cg[i].depth));
    if (depth < 0.0005) return;
  }
  if (ba && !dBodyIsEnabled(ba)) dBodyEnable(ba);
  if (bb && !dBodyIsEnabled(bb) && !dBodyIsKinematic(bb)) dBodyEnable(bb);
  for (int i = 0; i < n; ++i) {
    dContact c;
    std::memset(&c, 0, sizeof c);
    c.geom = cg[i];
    c.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    c.surface.mu = mu;
    c.surface.soft_erp = 0.2;
    c.surface.soft_cfm = 1e-5;
    dJointID j = dJointCreateContact(world_, contacts_, &c);
    dJointAttach(j, ba, bb);
  }
}

void Simulation::collide_objects() {
  std::fill(touched_now_.begin(), touched_now_.end(), uint8_t(2));
  const int n_obj = int(objects_.size());
  for (int oi = 0; oi < n_obj; ++oi) {
    Object& o = objects_[size_t(oi)];
    if (!o.movable || o.removed) continue;
    const int base = oi * n_others_;
    if (o.carried) {  // held: its contacts are the arm's; only whether it touches the world
      if (ground_) add_contact(o.geom, ground_, 0, base, false);
      for (int oj = 0; oj < n_obj; ++oj)
        if (oj != oi && !objects_[size_t(oj)].removed && !objects_[size_t(oj)].movable)
          add_contact(o.geom, objects_[size_t(oj)].geom, 0, base + 1 + oj, false);
      continue;
    }
    if (ground_ && dBodyIsEnabled(o.body)) add_contact(o.geom, ground_, std::sqrt(o.mu * scene_.ground_friction), base);
    for (int oj = 0; oj < n_obj; ++oj) {
      if (oj == oi) continue;
      Object& p = objects_[size_t(oj)];
      if (p.removed) continue;
      const double mu = std::sqrt(o.mu * p.mu);
      if (!p.movable) {
        if (dBodyIsEnabled(o.body)) add_contact(o.geom, p.geom, mu, base + 1 + oj);
      } else if (p.carried) {
        if (dBodyIsEnabled(o.body) || arm_moved_) add_contact(o.geom, p.geom, mu, base + 1 + oj);
      } else if (oj > oi) {
        if (dBodyIsEnabled(o.body) || dBodyIsEnabled(p.body)) add_contact(o.geom, p.geom, mu, base + 1 + oj);
      }
    }
    for (size_t pi = 0; pi < parts_.size(); ++pi) {
      const Part& p = *parts_[pi];
      if (!dBodyIsEnabled(o.body) && !p.moved) continue;
      for (dGeomID g : p.geoms) add_contact(o.geom, g, std::sqrt(o.mu * p.mu), base + 1 + n_obj + int(pi));
    }
  }
  // Contacts flicker while a stepper pushes (a step, a gap, a step): a contact ends only
  // after 50 ms without a touch, and the event is dated at the last touch.
  const uint64_t debounce = std::max<uint64_t>(1, uint64_t(std::llround(0.05 / opt_.dt)));
  for (size_t k = 0; k < touching_.size(); ++k) {
    const uint8_t now = touched_now_[k];
    const size_t oi = k / size_t(n_others_), other = k % size_t(n_others_);
    if (now == 1) {
      last_touch_[k] = steps_;
      if (!touching_[k]) {
        touching_[k] = 1;
        event(SimEvent::Kind::kContactStarted, scene_.objects[oi].name, other_names_[other], "", &touch_point_[k]);
      }
    } else if (now == 0 && touching_[k] && steps_ - last_touch_[k] >= debounce) {
      touching_[k] = 0;
      event(SimEvent::Kind::kContactEnded, scene_.objects[oi].name, other_names_[other], "");
      events_.back().t = double(last_touch_[k] + 1) * opt_.dt;
    }
  }
}

void Simulation::measure_squeeze() {
  for (auto& q : block_pairs_) {
    if (q.kind != Pair::kMovable) continue;
    q.settled = 0;
    const Object& o = objects_[size_t(q.object_b)];
    if (o.removed || o.carried || !aabb_overlap(q.a, q.b)) continue;
    dContactGeom c[kMaxMeshContacts];
    const int n = dCollide(q.a, q.b, q.max_contacts, c, sizeof(dContactGeom));
    for (int i = 0; i < n; ++i) q.settled = std::max(q.settled, c[i].depth / kMm);
  }
}

void Simulation::after_step() {
  for (auto& pp : parts_) {
    Part& p = *pp;
    if (!p.moved) continue;
    p.T_set.p.x = std::nan("");  // the step moved it by its velocity: set it back whatever was set
    set_part_pose(p, p.T);
    dBodySetLinearVel(p.body, 0, 0, 0);
    dBodySetAngularVel(p.body, 0, 0, 0);
  }
  for (size_t i = 0; i < objects_.size(); ++i) {
    Object& o = objects_[i];
    if (!o.movable || o.removed) continue;
    if (o.carried) {
      dBodySetPosition(o.body, o.T_carry.p.x * kMm, o.T_carry.p.y * kMm, o.T_carry.p.z * kMm);
      dMatrix3 R;
      to_ode(o.T_carry.R, R);
      dBodySetRotation(o.body, R);
      dBodySetLinearVel(o.body, 0, 0, 0);
      dBodySetAngularVel(o.body, 0, 0, 0);
      continue;
    }
    if (!dBodyIsEnabled(o.body)) continue;
    const dReal* p = dBodyGetPosition(o.body);
    const dReal* v = dBodyGetLinearVel(o.body);
    const dReal* w = dBodyGetAngularVel(o.body);
    const dReal* q = dBodyGetQuaternion(o.body);
    bool finite = true;
    for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(p[k]) && std::isfinite(v[k]) && std::isfinite(w[k]);
    for (int k = 0; k < 4; ++k) finite = finite && std::isfinite(q[k]);
    const bool inside = finite && p[0] >= scene_.world_min.x * kMm && p[0] <= scene_.world_max.x * kMm &&
                        p[1] >= scene_.world_min.y * kMm && p[1] <= scene_.world_max.y * kMm &&
                        p[2] >= scene_.world_min.z * kMm && p[2] <= scene_.world_max.z * kMm;
    if (inside) {
      std::copy(p, p + 3, o.last_good);
      continue;
    }
    o.removed = true;
    dBodySetPosition(o.body, o.last_good[0], o.last_good[1], o.last_good[2]);
    if (!finite) {
      dMatrix3 R;
      to_ode(identity3<double>(), R);
      dBodySetRotation(o.body, R);
    }
    dBodySetLinearVel(o.body, 0, 0, 0);
    dBodySetAngularVel(o.body, 0, 0, 0);
    dBodyDisable(o.body);
    dGeomDisable(o.geom);
    SimEvent e;
    e.kind = SimEvent::Kind::kObjectRemoved;
    e.t = time() + opt_.dt, e.line = current_line_, e.a = scene_.objects[i].name;
    e.has_point = true;
    e.point_mm = make_vec3(o.last_good[0] / kMm, o.last_good[1] / kMm, o.last_good[2] / kMm);
    e.detail = finite ? "left the world box: taken out of the simulation, frozen where it was last inside"
                      : "its state stopped being finite: taken out of the simulation, frozen where it was last finite";
    events_.push_back(e);
  }
  measure_squeeze();
}

void Simulation::step_path(int n, int every, std::vector<double>& path) {
  every = std::max(1, every);
  for (int i = 1; i <= n; ++i) {
    step();
    if (i % every == 0 || i == n) {
      const Vec3<double>& p = frames_.T_base_tool.p;
      path.insert(path.end(), {p.x, p.y, p.z});
    }
  }
}

void Simulation::step() {
  const double dt = opt_.dt;
  const uint64_t until = (steps_ + 1) * ticks_per_step_;
  const double t_end = double(steps_ + 1) * dt;
  while (pending_next_ < pending_.size() && pending_[pending_next_].t <= t_end + 1e-12) events_.push_back(pending_[pending_next_++]);
  for (auto& p : parts_) {
    p->T_prev = p->T;
    p->moved = false;
  }
  for (auto& o : objects_) o.T_carry_prev = o.T_carry;
  arm_moved_ = false;
  const double t_start = time();
  if (motors_) {
    motor_events(until);
    if (has_servos_) servo_follow(dt);
  } else {
    joint_follow(t_end);
  }
  gripper_follow(t_end);
  if (arm_moved_) {
    for (auto& pp : parts_) {
      Part& p = *pp;
      if (!p.moved) continue;
      // A stepper's link moves in steps; the contact sees the mean speed since the last one
      // (a step every 3 ms is 1/3 of the step's displacement per ms, not all of it).
      const double span = std::clamp(t_end - p.t_last_move, dt, 0.05);
      p.t_last_move = t_start;
      const Vec3<double> v = (kMm / span) * (p.T.p - p.T_prev.p);
      const Vec3<double> w = (1 / span) * rotation_vector(p.T.R, p.T_prev.R);
      dBodySetLinearVel(p.body, v.x, v.y, v.z);
      dBodySetAngularVel(p.body, w.x, w.y, w.z);
      dBodyEnable(p.body);  // idle parts are auto-disabled, so objects resting on them can sleep
    }
    for (auto& o : objects_) {
      if (!o.carried) continue;
      const Vec3<double> v = (kMm / dt) * (o.T_carry.p - o.T_carry_prev.p);
      const Vec3<double> w = (1 / dt) * rotation_vector(o.T_carry.R, o.T_carry_prev.R);
      dBodySetLinearVel(o.body, v.x, v.y, v.z);
      dBodySetAngularVel(o.body, w.x, w.y, w.z);
    }
  }
  collide_objects();
  apply_drag();
  if (opt_.quick_step)
    dWorldQuickStep(world_, dt);
  else
    dWorldStep(world_, dt);
  dJointGroupEmpty(contacts_);
  after_step();
  ++steps_;
}

// ---- a mouse drag ----

void Simulation::drag_object(int i, const Vec3<double>& target_mm) {
  if (i < 0 || i >= int(objects_.size())) throw std::invalid_argument("no object " + std::to_string(i) + " in the scene");
  const Object& o = objects_[size_t(i)];
  const std::string& name = scene_.objects[size_t(i)].name;
  if (!o.movable) throw std::invalid_argument("'" + name + "' is static: it cannot be dragged");
  if (o.removed) throw std::invalid_argument("'" + name + "' has left the world");
  if (!std::isfinite(target_mm.x) || !std::isfinite(target_mm.y) || !std::isfinite(target_mm.z))
    throw std::invalid_argument("a drag target must be finite");
  if (drag_object_ >= 0 && drag_object_ != i) release_drag();
  drag_object_ = i;
  drag_target_[0] = target_mm.x * kMm, drag_target_[1] = target_mm.y * kMm, drag_target_[2] = target_mm.z * kMm;
  dBodySetAngularDamping(o.body, 0.2);
  dBodyEnable(o.body);
}

void Simulation::release_drag() {
  if (drag_object_ < 0) return;
  Object& o = objects_[size_t(drag_object_)];
  dBodySetAngularDamping(o.body, 0);
  dBodyEnable(o.body);
  drag_object_ = -1;
}

// The spring of a drag: a = w^2 (target - p) - 2 w v - g, w = 2 pi 4 Hz (critically damped,
// the same for every mass), the acceleration capped at 30 m/s^2 so that a far target pulls
// the object along instead of throwing it through what lies between.
void Simulation::apply_drag() {
  if (drag_object_ < 0) return;
  Object& o = objects_[size_t(drag_object_)];
  if (o.removed || o.carried) return;
  const double w = 2 * M_PI * 4, a_max = 30;
  const dReal* p = dBodyGetPosition(o.body);
  const dReal* v = dBodyGetLinearVel(o.body);
  const double g[3] = {scene_.gravity.x, scene_.gravity.y, scene_.gravity.z};
  double a[3], size = 0;
  for (int k = 0; k < 3; ++k) {
    a[k] = w * w * (drag_target_[k] - p[k]) - 2 * w * v[k];
    size += a[k] * a[k];
  }
  size = std::sqrt(size);
  const double scale = size > a_max ? a_max / size : 1;
  dMass m;
  dBodyGetMass(o.body, &m);
  dBodyEnable(o.body);
  dBodyAddForce(o.body, m.mass * (a[0] * scale - g[0]), m.mass * (a[1] * scale - g[1]), m.mass * (a[2] * scale - g[2]));
}

bool Simulation::busy() const {
  if (motors_) return firmware_->pending() || !firmware_->at_rest();
  return action_ < actions_.size();
}

std::vector<SimContact> Simulation::contacts() const {
  std::vector<SimContact> out;
  for (size_t k = 0; k < touching_.size(); ++k) {
    if (!touching_[k]) continue;
    const size_t oi = k / size_t(n_others_), other = k % size_t(n_others_);
    const dContactGeom& c = touch_point_[k];
    out.push_back({scene_.objects[oi].name, other_names_[other], make_vec3(c.pos[0] / kMm, c.pos[1] / kMm, c.pos[2] / kMm)});
  }
  return out;
}

nlohmann::json event_json(const SimEvent& e) {
  nlohmann::json j = {{"t", e.t}, {"kind", event_kind_name(e.kind)}, {"line", e.line}, {"a", e.a}, {"b", e.b}};
  if (e.has_point) j["point_mm"] = {e.point_mm.x, e.point_mm.y, e.point_mm.z};
  if (e.depth_mm > 0) j["depth_mm"] = e.depth_mm;
  if (!e.detail.empty()) j["detail"] = e.detail;
  return j;
}

void Simulation::run_until(double t) {
  while (time() < t - 1e-12) step();
}

// ---- what the outside sees ----

Transform<double> Simulation::object_pose(int i) const {
  const Object& o = objects_[size_t(i)];
  const dReal* p = o.body ? dBodyGetPosition(o.body) : dGeomGetPosition(o.geom);
  const dReal* R = o.body ? dBodyGetRotation(o.body) : dGeomGetRotation(o.geom);
  return make_transform(from_ode(R), make_vec3(p[0] / kMm, p[1] / kMm, p[2] / kMm));
}

bool Simulation::object_removed(int i) const { return objects_[size_t(i)].removed; }
bool Simulation::object_carried(int i) const { return objects_[size_t(i)].carried; }
dBodyID Simulation::object_body(int i) const { return objects_[size_t(i)].body; }
dGeomID Simulation::object_geom(int i) const { return objects_[size_t(i)].geom; }

std::vector<int32_t> Simulation::lost_steps() const {
  std::vector<int32_t> out(offset_, offset_ + n_motors_);
  // A servo rests anywhere within half its dead band of its pulse (servo_follow): its own loop's
  // tolerance, not a step lost. Only what holds it back beyond that is off its command.
  for (int i = 0; i < n_motors_; ++i)
    if (servo_[i]) {
      const int32_t v = out[size_t(i)], band = servo_band_[i];
      out[size_t(i)] = v > band ? v - band : v < -band ? v + band : 0;
    }
  return out;
}
std::vector<int32_t> Simulation::counted_steps() const { return std::vector<int32_t>(counted_, counted_ + n_motors_); }

std::vector<ArmPartInfo> Simulation::arm_parts() const {
  std::vector<ArmPartInfo> out;
  for (const auto& p : parts_) out.push_back({p->name, p->frame, p->body, p->T});
  return out;
}

}  // namespace articula::host
