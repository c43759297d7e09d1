// host/physics/arm_body.cpp - see arm_body.h; docs/physics.md explains the choices.
#include "arm_body.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "geometry.h"
#include "mesh.h"
#include "world_detail.h"

namespace articula::host {

using namespace detail;

struct ArmBody::Pair {
  enum Kind { kGround, kStatic, kSelf, kOtherArm, kMovable, kCarriedGround, kCarriedStatic } kind;
  dGeomID a = nullptr, b = nullptr;
  int max_contacts = kMaxContacts;  // kMaxMeshContacts when a or b is a mesh
  int part_a = -1;    // arm part (or -1: the carried object object_a)
  int object_a = -1;
  int part_b = -1;    // kSelf, kOtherArm (a part of arm_b)
  int arm_b = -1;     // kOtherArm
  int object_b = -1;  // kStatic, kMovable, kCarriedStatic
  int group = -1;     // what b belongs to, for the broad phase: 0 an object object_b, 1 the arm arm_b; -1 always checked
  double accepted = 0;  // depth at the last accepted pose, mm
  double settled = 0;   // kMovable: depth after the last world step, mm
};

// A mesh file's triangles as ODE reads them (it keeps pointers to these arrays, so they live
// as long as the geoms: ArmBody::meshes_ is destroyed after the geoms).
struct ArmBody::MeshData {
  std::string path;
  std::vector<dReal> vertices;  // x y z, m
  std::vector<dTriIndex> indices;
  dTriMeshDataID data = nullptr;
  ~MeshData() {
    if (data) dGeomTriMeshDataDestroy(data);
  }
};

namespace {

// An axis-aligned box around geoms (ODE's AABBs), m.
struct Box {
  dReal b[6] = {1e30, -1e30, 1e30, -1e30, 1e30, -1e30};
  void add(dGeomID g) {
    dReal x[6];
    dGeomGetAABB(g, x);
    for (int k = 0; k < 6; k += 2) b[k] = std::min(b[k], x[k]), b[k + 1] = std::max(b[k + 1], x[k + 1]);
  }
  bool overlaps(const dReal* y) const {
    return b[0] <= y[1] && y[0] <= b[1] && b[2] <= y[3] && y[2] <= b[3] && b[4] <= y[5] && y[4] <= b[5];
  }
  bool overlaps(const Box& o) const { return overlaps(o.b); }
  bool overlaps(dGeomID g) const {
    dReal y[6];
    dGeomGetAABB(g, y);
    return overlaps(y);
  }
};

// The farthest a shape's points lie from its frame's origin, mm.
double shape_extent(const Shape& s, const std::vector<dReal>* mesh_vertices) {
  double r = 0;
  switch (s.type) {
    case Shape::Type::kBox: r = 0.5 * std::sqrt(s.size[0] * s.size[0] + s.size[1] * s.size[1] + s.size[2] * s.size[2]); break;
    case Shape::Type::kCylinder: r = std::hypot(s.size[0], s.size[1] / 2); break;
    case Shape::Type::kCapsule: r = s.size[0] + s.size[1] / 2; break;
    case Shape::Type::kSphere: r = s.size[0]; break;
    case Shape::Type::kMesh:
      for (size_t k = 0; mesh_vertices && k + 2 < mesh_vertices->size(); k += 3)
        r = std::max(r, std::sqrt((*mesh_vertices)[k] * (*mesh_vertices)[k] + (*mesh_vertices)[k + 1] * (*mesh_vertices)[k + 1] +
                                  (*mesh_vertices)[k + 2] * (*mesh_vertices)[k + 2]) / kMm);
      break;
  }
  const Vec3<double>& c = s.T_frame_shape.p;
  return std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z) + r;
}

// The largest magnitude a DH parameter can take: a joint variable's limits, a linked one's
// offset and gains over the joints' limits, an adjustable length's range, else its value.
double param_bound(const Robot& robot, int row, int param, double value) {
  const HostModel& m = robot.model;
  double out = std::fabs(value);
  for (int j = 0; j < m.num_joints; ++j)
    if (m.joints[j].row == row && m.joints[j].param == param)
      out = std::max(std::fabs(m.joints[j].lo), std::fabs(m.joints[j].hi));
  for (int l = 0; l < m.num_linked; ++l) {
    const auto& p = m.linked[l];
    if (p.row != row || p.param != param) continue;
    double b = std::fabs(p.offset);
    for (int j = 0; j < m.num_joints; ++j)
      b += std::fabs(p.gain[j]) * std::max(std::fabs(m.joints[j].lo), std::fabs(m.joints[j].hi));
    out = std::max(out, b);
  }
  if (param == -1 && size_t(row) < robot.length_ranges.size() && robot.length_ranges[size_t(row)].adjustable)
    out = std::max(out, std::max(std::fabs(robot.length_ranges[size_t(row)].min), std::fabs(robot.length_ranges[size_t(row)].max)));
  return out;
}

// A bound on the reach (ArmBody::reach_mm): each frame's origin within the sum of the offsets
// before it, each shape within its extent of its frame's origin, the fingers of the tool's.
double reach_bound(const Robot& robot, const std::vector<LinkGeometry>& links,
                   const std::function<const std::vector<dReal>*(const Shape&)>& mesh_of) {
  const HostModel& m = robot.model;
  std::vector<double> origin(size_t(m.num_rows) + 1, 0.0);
  for (int i = 0; i < m.num_rows; ++i)
    origin[size_t(i) + 1] = origin[size_t(i)] + param_bound(robot, i, -1, m.rows[i].a) + param_bound(robot, i, kParamD, m.rows[i].d);
  const Vec3<double>& t = m.T_last_tool.p;
  const double tool = origin.back() + std::sqrt(t.x * t.x + t.y * t.y + t.z * t.z);
  double reach = tool;
  for (const LinkGeometry& l : links)
    for (const Shape& s : l.shapes) reach = std::max(reach, origin[size_t(std::max(0, l.frame))] + shape_extent(s, mesh_of(s)));
  if (robot.gripper.present) {
    const Gripper& g = robot.gripper;
    reach = std::max(reach, tool + std::sqrt(g.finger_length_mm * g.finger_length_mm / 4 +
                                             std::pow(g.max_opening_mm / 2 + g.finger_thickness_mm, 2) +
                                             g.finger_height_mm * g.finger_height_mm / 4));
  }
  return reach;
}

}  // namespace

ArmBody::ArmBody(World& world, int index, const ArmPlacement& placement)
    : world_(world), index_(index), robot_(placement.robot), name_(placement.name),
      T_world_base_(placement.T_world_base), opt_(world.options()) {
  const Transform<double> I = Transform<double>::identity();
  placed_ = std::memcmp(&T_world_base_, &I, sizeof I) != 0;
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

  reach_mm_ = reach_bound(robot_, arm_geometry(robot_), [this](const Shape& sh) -> const std::vector<dReal>* {
    const std::string path = mesh_path(robot_, sh);
    for (const auto& m : meshes_)
      if (m->path == path) return &m->vertices;
    return nullptr;
  });
  q_.assign(size_t(n_joints_), 0.0);
  if (motors_) {
    joints_from_steps(q_.data(), robot_.actuation, counted_);
  } else {
    for (int j = 0; j < n_joints_ && size_t(j) < robot_.home.size(); ++j) q_[size_t(j)] = robot_.home[size_t(j)];
  }
  q_try_ = q_cmd_want_ = q_;
  opening_mm_ = robot_.gripper.present ? robot_.gripper.max_opening_mm : 0;
  grip_from_ = grip_to_ = opening_mm_;  // open until a program or a command says otherwise
}

ArmBody::~ArmBody() {
  for (auto& p : parts_)
    for (dGeomID g : p->geoms) dGeomDestroy(g);
}

double ArmBody::time() const { return world_.time(); }


std::string ArmBody::label(const std::string& part) const { return name_.empty() ? part : name_ + ": " + part; }

// ---- building ----

void ArmBody::build_parts() {
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
      p->mu = kArmFriction;
      p->body = dBodyCreate(world_.world_);
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
      p->body = dBodyCreate(world_.world_);
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

void ArmBody::build_pairs() {
  const auto& objects = world_.objects_;
  for (size_t pi = 0; pi < parts_.size(); ++pi) {
    const Part& p = *parts_[pi];
    if (p.frame == 0) continue;  // the base never moves: nothing to refuse
    for (dGeomID g : p.geoms) {
      if (world_.ground_) {
        Pair q{Pair::kGround};
        q.a = g, q.b = world_.ground_, q.part_a = int(pi);
        block_pairs_.push_back(q);
      }
      for (size_t oi = 0; oi < objects.size(); ++oi) {
        Pair q{objects[oi].movable ? Pair::kMovable : Pair::kStatic};
        q.a = g, q.b = objects[oi].geom, q.part_a = int(pi), q.object_b = int(oi), q.group = 0;
        block_pairs_.push_back(q);
      }
      // Every part of every other arm within reach: each arm checks its own steps against where
      // the others are.
      for (int ai = 0; ai < world_.num_arms(); ++ai) {
        if (ai == index_ || !within_reach(world_.body(ai))) continue;
        const auto& other = world_.body(ai).parts();
        for (size_t pj = 0; pj < other.size(); ++pj)
          for (dGeomID h : other[pj]->geoms) {
            Pair q{Pair::kOtherArm};
            q.a = g, q.b = h, q.part_a = int(pi), q.arm_b = ai, q.part_b = int(pj), q.group = 1;
            block_pairs_.push_back(q);
          }
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
        e.arm = name_;
        e.a = parts_[i]->name, e.b = parts_[j]->name;
        e.detail = "overlap where the arm starts: their collisions are not checked";
        world_.events_.push_back(e);
      } else {
        block_pairs_.insert(block_pairs_.end(), these.begin(), these.end());
      }
    }
  }
  // A carried object becomes part of the arm: it may not go into the ground or a static object.
  for (size_t oi = 0; oi < objects.size(); ++oi) {
    if (!objects[oi].movable) continue;
    if (world_.ground_) {
      Pair q{Pair::kCarriedGround};
      q.a = objects[oi].geom, q.b = world_.ground_, q.object_a = int(oi);
      block_pairs_.push_back(q);
    }
    for (size_t si = 0; si < objects.size(); ++si) {
      if (objects[si].movable) continue;
      Pair q{Pair::kCarriedStatic};
      q.a = objects[oi].geom, q.b = objects[si].geom, q.object_a = int(oi), q.object_b = int(si);
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
      e.arm = name_;
      e.a = parts_[size_t(q.part_a)]->name, e.b = parts_[size_t(q.part_b)]->name;
      e.detail = "mesh against mesh: ODE gives no true depth for it, so such parts are stopped at their first touch "
                 "(and the depth the event gives is not the overlap)";
      world_.events_.push_back(e);
    }
  }
  block_depth_.assign(block_pairs_.size(), 0.0);
  // The broad phase pays where there is more than a few things to pass over.
  near_object_.assign(objects.size(), 1);
  near_arm_.assign(size_t(world_.num_arms()), 1);
  broad_ = world_.num_arms() > 1;
}

bool ArmBody::within_reach(const ArmBody& other) const {
  const Vec3<double> d = other.T_world_base_.p - T_world_base_.p;
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) <= reach_mm_ + other.reach_mm_ + 1;
}

void ArmBody::start() {
  place_arm(q_.data(), opening_mm_);
  accept_pose();
  for (auto& p : parts_) p->T_prev = p->T;
}

// ---- the arm's pose ----

Transform<double> ArmBody::in_world(const Transform<double>& T_base) const {
  return placed_ ? T_world_base_ * T_base : T_base;
}

void ArmBody::set_part_pose(Part& p, const Transform<double>& T) {
  if (std::memcmp(&T, &p.T_set, sizeof T) == 0) return;  // ODE re-normalises a rotation it is given: skip
  p.T_set = T;
  set_body_pose(p.body, T);
}

void ArmBody::place_arm(const double* q, double opening_mm) {
  HostFrames f;
  forward_kinematics(f, robot_.model, q);
  for (auto& pp : parts_) {
    Part& p = *pp;
    const Transform<double> T = p.frame >= 0 ? f.T_base_frame[p.frame]
                                             : finger_pose(robot_.gripper, f.T_base_tool, opening_mm, p.side);
    set_part_pose(p, in_world(T));
  }
  for (auto& o : world_.objects_) {
    if (o.carrier != index_) continue;
    set_body_pose(o.body, in_world(f.T_base_tool * o.T_tool_obj));
  }
  frames_try_ = f;
}

// The candidate pose (placed) against every block pair: false and an event (once per
// action) when a step would push the arm into something.
bool ArmBody::check_pose(int line) {
  const auto& objects = world_.objects_;
  const Scene& scene = world_.scene_;
  const double tol = opt_.touch_tolerance_mm;
  int worst = -1;
  dContactGeom worst_c{};
  // The broad phase: the box around every part of the arm that moves (and what it carries);
  // an object or another arm wholly outside it cannot touch any of them. (The same pairs in the
  // same order as without it: only pairs that could not overlap are passed over.)
  if (broad_) {
    Box arm_box;
    for (const auto& p : parts_)
      if (p->frame != 0)
        for (dGeomID g : p->geoms) arm_box.add(g);
    for (const auto& o : objects)
      if (o.carrier == index_) arm_box.add(o.geom);
    for (size_t oi = 0; oi < objects.size(); ++oi) near_object_[oi] = arm_box.overlaps(objects[oi].geom);
    for (int ai = 0; ai < world_.num_arms(); ++ai) {
      near_arm_[size_t(ai)] = false;
      if (ai == index_) continue;
      Box other;
      for (const auto& p : world_.body(ai).parts())
        for (dGeomID g : p->geoms) other.add(g);
      near_arm_[size_t(ai)] = arm_box.overlaps(other);
    }
  }
  for (size_t k = 0; k < block_pairs_.size(); ++k) {
    Pair& q = block_pairs_[k];
    block_depth_[k] = 0;
    if (broad_ && ((q.group == 0 && !near_object_[size_t(q.object_b)]) || (q.group == 1 && !near_arm_[size_t(q.arm_b)])))
      continue;
    if (q.object_a >= 0 && objects[size_t(q.object_a)].carrier != index_) continue;
    if (q.kind == Pair::kMovable) {
      const World::Object& o = objects[size_t(q.object_b)];
      if (o.removed || o.carried()) continue;
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
    const std::string a =
        q.part_a >= 0 ? parts_[size_t(q.part_a)]->name : scene.objects[size_t(q.object_a)].name + " (carried)";
    std::string b;
    SimEvent::Kind kind = SimEvent::Kind::kCollision;
    switch (q.kind) {
      case Pair::kGround:
      case Pair::kCarriedGround: b = "ground"; break;
      case Pair::kStatic:
      case Pair::kCarriedStatic: b = scene.objects[size_t(q.object_b)].name; break;
      case Pair::kSelf: b = parts_[size_t(q.part_b)]->name, kind = SimEvent::Kind::kSelfCollision; break;
      case Pair::kOtherArm: {
        const ArmBody& other = world_.body(q.arm_b);
        b = other.label(other.parts()[size_t(q.part_b)]->name);
        break;
      }
      case Pair::kMovable: b = scene.objects[size_t(q.object_b)].name, kind = SimEvent::Kind::kSqueeze; break;
    }
    current_line_ = line;
    event(kind, a, b,
          "the next step would go " + fmt_mm(block_depth_[size_t(worst)]) + " mm deep: the arm holds at contact" +
              (motors_ ? ", the motors skip the steps" : ""),
          &worst_c);
    world_.events_.back().depth_mm = block_depth_[size_t(worst)];
  }
  return false;
}

void ArmBody::accept_pose() {
  for (size_t k = 0; k < block_pairs_.size(); ++k) block_pairs_[k].accepted = block_depth_[k];
  frames_ = frames_try_;
  for (auto& pp : parts_) {
    Part& p = *pp;
    const Transform<double> T = in_world(p.frame >= 0 ? frames_.T_base_frame[p.frame]
                                                      : finger_pose(robot_.gripper, frames_.T_base_tool, opening_mm_, p.side));
    if (!p.moved) {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) p.moved = p.moved || T.R.m[i][j] != p.T.R.m[i][j];
      p.moved = p.moved || T.p.x != p.T.p.x || T.p.y != p.T.p.y || T.p.z != p.T.p.z;
    }
    p.T = T;
    arm_moved_ = arm_moved_ || p.moved;
  }
  for (auto& o : world_.objects_)
    if (o.carrier == index_) o.T_carry = in_world(frames_.T_base_tool * o.T_tool_obj);
}

// Back to the accepted pose, without the kinematics.
void ArmBody::restore_arm() {
  for (auto& p : parts_) set_part_pose(*p, p->T);
  for (auto& o : world_.objects_)
    if (o.carrier == index_) set_body_pose(o.body, o.T_carry);
  frames_try_ = frames_;
}

// Places the arm at (q, opening) and keeps it there unless a step would push it into something.
bool ArmBody::try_joints(const double* q, double opening_mm) {
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

// ---- what the controller does ----

void ArmBody::action_begins(uint64_t tick, int line, bool firmware) {
  if (firmware) firmware_action_ends(tick);
  firmware_action_ = firmware;
  blocked_reported_ = false;
  current_line_ = line;
  event_tick_ = tick;
  std::fill(std::begin(lost_in_action_), std::end(lost_in_action_), 0);
}

void ArmBody::grip(double to_mm, double t0, double t1) {
  grip_blocked_reported_ = false;
  grip_from_ = target_opening(t0);
  grip_to_ = to_mm;
  grip_t0_ = t0;
  grip_t1_ = t1;
}

// The stall model (stall.h) samples the move at the firmware's step times from the counted
// steps, with whatever the gripper carries as the payload; a motor that needs more than its
// pull-out torque gives a `stall` event at the start of the move, saying when in the move it
// happens.
void ArmBody::stall_check(const std::vector<int32_t>& delta, const MotionSettings& motion) {
  if (!stall_) return;
  std::vector<double> start_deg(static_cast<size_t>(n_motors_));
  for (int i = 0; i < n_motors_; ++i)
    start_deg[size_t(i)] = steps_to_degrees<double>(robot_.actuation.motors[i], counted_[i]);
  ControllerSettings settings = opt_.settings;
  settings.value[ControllerSettings::kMaxRate] = motion.max_rate;
  settings.value[ControllerSettings::kAccel] = motion.accel;
  double payload_kg = 0;
  for (size_t i = 0; i < world_.objects_.size(); ++i)
    if (world_.objects_[i].carrier == index_) payload_kg += world_.scene_.objects[i].mass_kg();
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
void ArmBody::firmware_action_ends(uint64_t tick) {
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
  e.arm = name_;
  e.line = current_line_;
  e.detail = "skipped " + lost +
             ": the controller does not know (open loop), so the arm stays that far off its counted "
             "position until it is homed against endstops (H) or re-zeroed (Z)";
  world_.events_.push_back(e);
}

void ArmBody::recount(const std::vector<int32_t>& counted) {
  for (int i = 0; i < n_motors_ && i < int(counted.size()); ++i) {
    offset_[i] += counted_[i] - counted[size_t(i)];
    counted_[i] = counted[size_t(i)];
  }
}

// ---- motion within a world step ----

bool ArmBody::try_steps(const int32_t* steps) {
  joints_from_steps(q_try_.data(), robot_.actuation, steps);
  return try_joints(q_try_.data(), opening_mm_);
}

void ArmBody::apply_steps(uint8_t mask, uint8_t negative) {
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

// Each servo whose command (its pulse's ticks) lies beyond half its dead band of where it
// stands turns towards it at its top speed, and stops as soon as it is within the band; a
// blocked one stays.
void ArmBody::servo_follow(double dt) {
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
uint8_t ArmBody::try_motor_by_motor(const int32_t* from, const int32_t* move, uint8_t mask) {
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

void ArmBody::follow_joints(const std::vector<double>& q_cmd, double dt) {
  bool moves = false;
  for (int j = 0; j < n_joints_; ++j) {
    const bool angle = joint_is_angle(robot_, j);
    const double max = 2 * dt * (angle ? deg_to_rad(opt_.joints.speed_deg) : opt_.joints.speed_mm);
    const double d = std::clamp(q_cmd[size_t(j)] - q_[size_t(j)], -max, max);
    q_try_[size_t(j)] = q_[size_t(j)] + d;
    moves = moves || d != 0;
  }
  if (!moves) return;
  const uint64_t steps = world_.steps_taken();
  if (steps < retry_after_step_) return;
  std::vector<double>& cand = q_try_;
  if (try_joints(cand.data(), opening_mm_)) return;
  // Blocked: joint by joint, those that can go on do; then wait 10 ms before trying again.
  retry_after_step_ = steps + std::max<uint64_t>(1, uint64_t(std::llround(0.01 / opt_.dt)));
  std::vector<double>& want = q_cmd_want_;
  want = cand;
  for (int j = 0; j < n_joints_; ++j) {
    if (want[size_t(j)] == q_[size_t(j)]) continue;
    cand = q_;
    cand[size_t(j)] = want[size_t(j)];
    try_joints(cand.data(), opening_mm_);
  }
}

double ArmBody::target_opening(double t) const {
  if (t >= grip_t1_ || grip_t1_ <= grip_t0_) return grip_to_;
  if (t <= grip_t0_) return grip_from_;
  return grip_from_ + (grip_to_ - grip_from_) * (t - grip_t0_) / (grip_t1_ - grip_t0_);
}

void ArmBody::gripper_follow(double t_end) {
  if (!robot_.gripper.present) return;
  auto& objects = world_.objects_;
  double cand = target_opening(t_end);
  bool carrying = false;
  for (const auto& o : objects) carrying = carrying || o.carrier == index_;
  if (grip_stalled_) {
    if (cand > grip_stall_mm_ + 1e-9) {
      grip_stalled_ = false;
      for (size_t i = 0; i < objects.size(); ++i) {
        World::Object& o = objects[i];
        if (o.carrier != index_) continue;
        o.carrier = -1;
        dBodySetDynamic(o.body);
        dBodyEnable(o.body);
        const Transform<double> T = world_.object_pose(int(i));
        SimEvent e;
        e.kind = SimEvent::Kind::kRelease;
        e.t = t_end, e.arm = name_, e.line = current_line_, e.a = "gripper", e.b = world_.scene_.objects[i].name;
        e.has_point = true, e.point_mm = T.p;
        e.detail = "the gripper opens: the object is free";
        world_.events_.push_back(e);
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
    if (!grip_blocked_reported_)  // once per gripper command (an opening held back tries again every step)
      event(SimEvent::Kind::kGripperBlocked, "gripper", "",
            "the fingers stop at " + fmt_mm(opening_mm_) + " mm: something they cannot " +
                (closing ? "grasp is in the way" : "open past is in the way"));
    grip_blocked_reported_ = true;
    return;
  }
  if (closing && !carrying) grasp_check();
}

// Both fingers touch a movable object while closing: it is grasped. An object another arm
// carries is taken from it (a handover: that arm's gripper holds on to nothing).
void ArmBody::grasp_check() {
  auto& objects = world_.objects_;
  for (size_t i = 0; i < objects.size(); ++i) {
    World::Object& o = objects[i];
    if (!o.movable || o.removed || o.carrier == index_) continue;
    bool touch[2] = {false, false};
    for (int f = 0; f < 2; ++f) {
      for (dGeomID g : parts_[size_t(finger_[f])]->geoms) {
        dContactGeom c[kMaxContacts];
        if (aabb_overlap(g, o.geom) && dCollide(g, o.geom, kMaxContacts, c, sizeof(dContactGeom)) > 0) touch[f] = true;
      }
    }
    if (!(touch[0] && touch[1])) continue;
    const int from = o.carrier;
    const Transform<double> T = world_.object_pose(int(i));
    o.carrier = index_;
    dBodySetLinearVel(o.body, 0, 0, 0);
    dBodySetAngularVel(o.body, 0, 0, 0);
    dBodySetKinematic(o.body);
    o.T_tool_obj = inverse(in_world(frames_.T_base_tool)) * T;
    o.T_carry = o.T_carry_prev = T;
    grip_stalled_ = true;
    grip_stall_mm_ = opening_mm_;
    SimEvent e;
    e.kind = SimEvent::Kind::kGrasp;
    e.t = time() + opt_.dt, e.arm = name_, e.line = current_line_, e.a = "gripper", e.b = world_.scene_.objects[i].name;
    e.has_point = true, e.point_mm = T.p;
    e.detail = "both fingers touch it while closing: the servo stalls at " + fmt_mm(opening_mm_) +
               " mm and the object moves with the tool";
    if (from >= 0) e.detail += " (taken from " + world_.body(from).name() + ", which holds nothing now)";
    world_.events_.push_back(e);
    return;
  }
}

// ---- the world step ----

void ArmBody::event(SimEvent::Kind k, const std::string& a, const std::string& b, const std::string& detail,
                    const dContactGeom* c) {
  SimEvent e;
  e.kind = k;
  e.t = motors_ ? double(event_tick_) / kStepTickHz : time() + opt_.dt;
  e.arm = name_;
  e.line = current_line_;
  e.a = a, e.b = b, e.detail = detail;
  if (c) {
    e.has_point = true;
    e.point_mm = make_vec3(c->pos[0] / kMm, c->pos[1] / kMm, c->pos[2] / kMm);
  }
  world_.events_.push_back(e);
}

void ArmBody::add_event(SimEvent e) {
  e.arm = name_;
  world_.events_.push_back(std::move(e));
}

void ArmBody::begin_step() {
  for (auto& p : parts_) {
    p->T_prev = p->T;
    p->moved = false;
  }
  arm_moved_ = false;
}

void ArmBody::set_velocities(double t_start, double t_end, double dt) {
  if (!arm_moved_) return;
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
  for (auto& o : world_.objects_) {
    if (o.carrier != index_) continue;
    const Vec3<double> v = (kMm / dt) * (o.T_carry.p - o.T_carry_prev.p);
    const Vec3<double> w = (1 / dt) * rotation_vector(o.T_carry.R, o.T_carry_prev.R);
    dBodySetLinearVel(o.body, v.x, v.y, v.z);
    dBodySetAngularVel(o.body, w.x, w.y, w.z);
  }
}

void ArmBody::end_step() {
  for (auto& pp : parts_) {
    Part& p = *pp;
    if (!p.moved) continue;
    p.T_set.p.x = std::nan("");  // the step moved it by its velocity: set it back whatever was set
    set_part_pose(p, p.T);
    dBodySetLinearVel(p.body, 0, 0, 0);
    dBodySetAngularVel(p.body, 0, 0, 0);
  }
}

void ArmBody::measure_squeeze() {
  for (auto& q : block_pairs_) {
    if (q.kind != Pair::kMovable) continue;
    q.settled = 0;
    const World::Object& o = world_.objects_[size_t(q.object_b)];
    if (o.removed || o.carried() || !aabb_overlap(q.a, q.b)) continue;
    dContactGeom c[kMaxMeshContacts];
    const int n = dCollide(q.a, q.b, q.max_contacts, c, sizeof(dContactGeom));
    for (int i = 0; i < n; ++i) q.settled = std::max(q.settled, c[i].depth / kMm);
  }
}

// ---- what the outside sees ----

std::vector<int32_t> ArmBody::lost_steps() const {
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

std::vector<int32_t> ArmBody::counted_steps() const { return std::vector<int32_t>(counted_, counted_ + n_motors_); }

std::vector<ArmPartInfo> ArmBody::arm_parts() const {
  std::vector<ArmPartInfo> out;
  for (const auto& p : parts_) out.push_back({p->name, p->frame, p->body, p->T});
  return out;
}

}  // namespace articula::host
