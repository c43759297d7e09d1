// host/physics/world.cpp - see world.h; docs/physics.md explains the choices.
#include "world.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "arm_body.h"
#include "arm_driver.h"
#include "world_detail.h"

namespace articula::host {

namespace detail {

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

std::string fmt_mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

void set_body_pose(dBodyID body, const Transform<double>& T) {
  dBodySetPosition(body, T.p.x * kMm, T.p.y * kMm, T.p.z * kMm);
  dMatrix3 R;
  to_ode(T.R, R);
  dBodySetRotation(body, R);
}

}  // namespace detail

using namespace detail;

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
    case SimEvent::Kind::kDeadlock: return "deadlock";
    case SimEvent::Kind::kDevice: return "device";
  }
  return "?";
}

nlohmann::json event_json(const SimEvent& e) {
  nlohmann::json j = {{"t", e.t}, {"kind", event_kind_name(e.kind)}};
  if (!e.arm.empty()) j["arm"] = e.arm;
  j["line"] = e.line;
  j["a"] = e.a;
  j["b"] = e.b;
  if (e.has_point) j["point_mm"] = {e.point_mm.x, e.point_mm.y, e.point_mm.z};
  if (e.depth_mm > 0) j["depth_mm"] = e.depth_mm;
  if (!e.detail.empty()) j["detail"] = e.detail;
  return j;
}

World::World(const std::vector<ArmPlacement>& arms, const Scene& scene, const SimOptions& options)
    : scene_(scene), opt_(options) {
  init_ode();
  if (!(opt_.dt > 0 && opt_.dt <= 0.01)) throw std::invalid_argument("the world step must be in (0, 10] ms");
  if (arms.empty()) throw std::invalid_argument("a world needs an arm");
  ticks_per_step_ = uint64_t(std::llround(opt_.dt * kStepTickHz));
  if (ticks_per_step_ == 0) ticks_per_step_ = 1;
  // Every arm's files first (a mesh that cannot be read throws before ODE's world exists).
  for (size_t i = 0; i < arms.size(); ++i) bodies_.push_back(std::make_unique<ArmBody>(*this, int(i), arms[i]));

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

  for (auto& b : bodies_) b->build_parts();
  build_scene();
  for (auto& b : bodies_) b->build_pairs();
  for (auto& b : bodies_) b->start();
  for (auto& b : bodies_) drivers_.push_back(std::make_unique<ArmDriver>(*b, opt_));
}

World::~World() {
  drivers_.clear();
  dJointGroupDestroy(contacts_);
  bodies_.clear();  // (their geoms)
  for (auto& o : objects_) dGeomDestroy(o.geom);
  if (ground_) dGeomDestroy(ground_);
  if (world_) dWorldDestroy(world_);
}

int World::arm_index(const std::string& name) const {
  for (size_t i = 0; i < bodies_.size(); ++i)
    if (bodies_[i]->name() == name) return int(i);
  return -1;
}

// ---- building ----

void World::build_scene() {
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
    const Mat3<double> R = so.rotation();
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
      if (so.belt != 0) {
        o.belt = true;
        o.belt_m_s = so.belt * kMm;
        for (int r = 0; r < 3; ++r) o.belt_dir[r] = R.m[r][0], o.belt_up[r] = R.m[r][2];
      }
    }
    objects_.push_back(o);
  }
  // Contact bookkeeping: others = ground, every object, every arm's parts.
  other_names_.push_back("ground");
  other_arm_.push_back(-1);
  for (const auto& so : scene_.objects) {
    other_names_.push_back(so.name);
    other_arm_.push_back(-1);
  }
  for (const auto& b : bodies_)
    for (const auto& p : b->parts()) {
      other_names_.push_back(b->label(p->name));
      other_arm_.push_back(b->index());
    }
  n_others_ = int(other_names_.size());
  touching_.assign(objects_.size() * size_t(n_others_), 0);
  touched_now_ = touching_;
  touch_point_.assign(touching_.size(), dContactGeom{});
  last_touch_.assign(touching_.size(), 0);
}

// ---- the world step ----

int World::event_arm(int other) const {
  if (other >= 0 && other_arm_[size_t(other)] >= 0) return other_arm_[size_t(other)];
  return bodies_.size() == 1 ? 0 : -1;
}

void World::event(SimEvent::Kind k, int arm, const std::string& a, const std::string& b, const std::string& detail,
                  const dContactGeom* c) {
  SimEvent e;
  e.kind = k;
  e.t = time() + opt_.dt;
  if (arm >= 0) {
    e.arm = bodies_[size_t(arm)]->name();
    e.line = bodies_[size_t(arm)]->current_line();
  }
  e.a = a, e.b = b, e.detail = detail;
  if (c) {
    e.has_point = true;
    e.point_mm = make_vec3(c->pos[0] / kMm, c->pos[1] / kMm, c->pos[2] / kMm);
  }
  events_.push_back(e);
}

void World::set_belt(int i, double mm_s) {
  if (i < 0 || size_t(i) >= objects_.size())
    throw std::invalid_argument("no object " + std::to_string(i) + ": the scene has " + std::to_string(objects_.size()));
  if (!objects_[size_t(i)].belt)
    throw std::invalid_argument("\"" + scene_.objects[size_t(i)].name + "\" is not a belt (a static box with a \"belt\" speed)");
  if (!std::isfinite(mm_s) || std::fabs(mm_s) > 1000)
    throw std::invalid_argument("a belt runs at most 1000 mm/s either way");
  objects_[size_t(i)].belt_m_s = mm_s * kMm;
}

std::string World::beam_blocker(const Vec3<double>& from_mm, const Vec3<double>& to_mm) const {
  const Vec3<double> d = to_mm - from_mm;
  const double len = norm(d);
  if (!(len > 0)) return "";
  dGeomID ray = dCreateRay(nullptr, len * kMm);
  dGeomRaySet(ray, from_mm.x * kMm, from_mm.y * kMm, from_mm.z * kMm, d.x / len, d.y / len, d.z / len);
  std::string by;
  for (size_t i = 0; i < objects_.size() && by.empty(); ++i) {
    if (objects_[i].removed || !objects_[i].geom) continue;
    dContactGeom c;
    if (dCollide(ray, objects_[i].geom, 1, &c, sizeof c) > 0) by = scene_.objects[i].name;
  }
  dGeomDestroy(ray);
  return by;
}

std::string World::box_presser(const Vec3<double>& centre_mm, const Vec3<double>& size_mm) const {
  dGeomID box = dCreateBox(nullptr, size_mm.x * kMm, size_mm.y * kMm, size_mm.z * kMm);
  dGeomSetPosition(box, centre_mm.x * kMm, centre_mm.y * kMm, centre_mm.z * kMm);
  auto inside = [&](dGeomID g) {
    dContactGeom c;
    return g && dGeomIsEnabled(g) && dCollide(box, g, 1, &c, sizeof c) > 0;
  };
  std::string by;
  for (size_t i = 0; i < objects_.size() && by.empty(); ++i)
    if (objects_[i].movable && !objects_[i].removed && inside(objects_[i].geom)) by = scene_.objects[i].name;
  for (const auto& b : bodies_)
    for (const auto& part : b->parts())
      for (dGeomID g : part->geoms)
        if (by.empty() && inside(g)) by = (bodies_.size() > 1 ? b->name() + ": " : std::string()) + part->name;
  dGeomDestroy(box);
  return by;
}

void World::stow_object(int i) {
  if (i < 0 || size_t(i) >= objects_.size() || !objects_[size_t(i)].movable)
    throw std::invalid_argument("object " + std::to_string(i) + " is not a movable object");
  Object& o = objects_[size_t(i)];
  if (drag_object_ == i) release_drag();
  o.removed = true;
  o.carrier = -1;
  dBodySetLinearVel(o.body, 0, 0, 0);
  dBodySetAngularVel(o.body, 0, 0, 0);
  dBodyDisable(o.body);
  dGeomDisable(o.geom);
}

bool World::put_out(int i, const Vec3<double>& xyz_mm) {
  if (i < 0 || size_t(i) >= objects_.size() || !objects_[size_t(i)].movable)
    throw std::invalid_argument("object " + std::to_string(i) + " is not a movable object");
  Object& o = objects_[size_t(i)];
  const SceneObject& so = scene_.objects[size_t(i)];
  const Transform<double> T = make_transform(
      so.rotation(), xyz_mm);
  set_body_pose(o.body, T);  // (its geom follows: tried there before it joins the world)
  dGeomEnable(o.geom);
  auto overlaps = [&](dGeomID other) {
    dContactGeom c;
    return other && other != o.geom && dGeomIsEnabled(other) && dCollide(o.geom, other, 1, &c, sizeof c) > 0 &&
           c.depth > 1e-4;  // (touching is fine: 0.1 mm)
  };
  bool taken = false;
  for (size_t j = 0; j < objects_.size() && !taken; ++j) taken = !objects_[j].removed && overlaps(objects_[j].geom);
  for (const auto& b : bodies_)
    for (const auto& part : b->parts())
      for (dGeomID g : part->geoms) taken = taken || overlaps(g);
  if (taken) {
    dGeomDisable(o.geom);
    return false;
  }
  o.removed = false;
  dBodySetLinearVel(o.body, 0, 0, 0);
  dBodySetAngularVel(o.body, 0, 0, 0);
  dBodyEnable(o.body);
  o.last_good[0] = xyz_mm.x * kMm, o.last_good[1] = xyz_mm.y * kMm, o.last_good[2] = xyz_mm.z * kMm;
  return true;
}

void World::add_contact(dGeomID a, dGeomID b, double mu, int touch_index, bool joints, const Object* belt) {
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
  const bool carries = belt && belt->belt_m_s != 0;  // a running belt wakes what lies on it
  if (ba && !dBodyIsEnabled(ba) && !carries) {
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
    // On a belt's top face (the contact's normal along its up: ODE's normal points into the
    // first geom, the object lying on it) the surface moves: ODE's contact motion along the
    // belt's x. Its sides and ends are still.
    if (carries &&
        (cg[i].normal[0] * belt->belt_up[0] + cg[i].normal[1] * belt->belt_up[1] + cg[i].normal[2] * belt->belt_up[2]) > 0.9) {
      c.surface.mode |= dContactFDir1 | dContactMotion1;
      for (int r = 0; r < 3; ++r) c.fdir1[r] = belt->belt_dir[r];
      c.surface.motion1 = belt->belt_m_s;
    }
    dJointID j = dJointCreateContact(world_, contacts_, &c);
    dJointAttach(j, ba, bb);
  }
}

void World::collide_objects() {
  std::fill(touched_now_.begin(), touched_now_.end(), uint8_t(2));
  const int n_obj = int(objects_.size());
  for (int oi = 0; oi < n_obj; ++oi) {
    Object& o = objects_[size_t(oi)];
    if (!o.movable || o.removed) continue;
    const int base = oi * n_others_;
    if (o.carried()) {  // held: its contacts are the arm's; only whether it touches the world
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
        if (dBodyIsEnabled(o.body) || (p.belt && p.belt_m_s != 0))
          add_contact(o.geom, p.geom, mu, base + 1 + oj, true, p.belt ? &p : nullptr);
      } else if (p.carried()) {
        if (dBodyIsEnabled(o.body) || bodies_[size_t(p.carrier)]->moved()) add_contact(o.geom, p.geom, mu, base + 1 + oj);
      } else if (oj > oi) {
        if (dBodyIsEnabled(o.body) || dBodyIsEnabled(p.body)) add_contact(o.geom, p.geom, mu, base + 1 + oj);
      }
    }
    int other = 1 + n_obj;
    for (const auto& b : bodies_)
      for (const auto& pp : b->parts()) {
        const ArmBody::Part& p = *pp;
        const int index = base + other++;
        if (!dBodyIsEnabled(o.body) && !p.moved) continue;
        for (dGeomID g : p.geoms) add_contact(o.geom, g, std::sqrt(o.mu * p.mu), index);
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
        event(SimEvent::Kind::kContactStarted, event_arm(int(other)), scene_.objects[oi].name, other_names_[other], "",
              &touch_point_[k]);
      }
    } else if (now == 0 && touching_[k] && steps_ - last_touch_[k] >= debounce) {
      touching_[k] = 0;
      event(SimEvent::Kind::kContactEnded, event_arm(int(other)), scene_.objects[oi].name, other_names_[other], "");
      events_.back().t = double(last_touch_[k] + 1) * opt_.dt;
    }
  }
}

void World::after_step() {
  for (auto& b : bodies_) b->end_step();
  for (size_t i = 0; i < objects_.size(); ++i) {
    Object& o = objects_[i];
    if (!o.movable || o.removed) continue;
    if (o.carried()) {
      set_body_pose(o.body, o.T_carry);
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
    e.t = time() + opt_.dt;
    if (bodies_.size() == 1) e.line = bodies_[0]->current_line();
    e.a = scene_.objects[i].name;
    e.has_point = true;
    e.point_mm = make_vec3(o.last_good[0] / kMm, o.last_good[1] / kMm, o.last_good[2] / kMm);
    e.detail = finite ? "left the world box: taken out of the simulation, frozen where it was last inside"
                      : "its state stopped being finite: taken out of the simulation, frozen where it was last finite";
    events_.push_back(e);
  }
  for (auto& b : bodies_) b->measure_squeeze();
}

void World::step() {
  const double dt = opt_.dt;
  const uint64_t until = (steps_ + 1) * ticks_per_step_;
  const double t_end = double(steps_ + 1) * dt;
  for (auto& d : drivers_) d->take_rejections(t_end, events_);
  for (auto& b : bodies_) b->begin_step();
  for (auto& o : objects_) o.T_carry_prev = o.T_carry;
  const double t_start = time();
  for (size_t i = 0; i < bodies_.size(); ++i) {
    drivers_[i]->advance(until, t_end, dt);
    bodies_[i]->gripper_follow(t_end);
  }
  for (auto& b : bodies_) b->set_velocities(t_start, t_end, dt);
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

void World::run_until(double t) {
  while (time() < t - 1e-12) step();
}

bool World::busy() const {
  for (const auto& d : drivers_)
    if (d->busy()) return true;
  return false;
}

// ---- a mouse drag ----

void World::drag_object(int i, const Vec3<double>& target_mm) {
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

void World::release_drag() {
  if (drag_object_ < 0) return;
  placed_[drag_object_] = object_pose(drag_object_);
  Object& o = objects_[size_t(drag_object_)];
  dBodySetAngularDamping(o.body, 0);
  dBodyEnable(o.body);
  drag_object_ = -1;
}

Scene World::scene_as_placed() const {
  Scene out = scene_;
  for (const auto& [i, pose] : placed_) {
    SceneObject& o = out.objects[size_t(i)];
    o.xyz = pose.p;
    const Vec3<double> rpy = matrix_to_rpy(pose.R);
    o.rpy_deg = make_vec3(rpy.x * 180 / M_PI, rpy.y * 180 / M_PI, rpy.z * 180 / M_PI);
  }
  return out;
}

// The spring of a drag: a = w^2 (target - p) - 2 w v - g, w = 2 pi 4 Hz (critically damped,
// the same for every mass), the acceleration capped at 30 m/s^2 so that a far target pulls
// the object along instead of throwing it through what lies between.
void World::apply_drag() {
  if (drag_object_ < 0) return;
  Object& o = objects_[size_t(drag_object_)];
  if (o.removed || o.carried()) return;
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

// ---- what the outside sees ----

std::vector<SimContact> World::contacts() const {
  std::vector<SimContact> out;
  for (size_t k = 0; k < touching_.size(); ++k) {
    if (!touching_[k]) continue;
    const size_t oi = k / size_t(n_others_), other = k % size_t(n_others_);
    const dContactGeom& c = touch_point_[k];
    out.push_back({scene_.objects[oi].name, other_names_[other], make_vec3(c.pos[0] / kMm, c.pos[1] / kMm, c.pos[2] / kMm)});
  }
  return out;
}

Transform<double> World::object_pose(int i) const {
  const Object& o = objects_[size_t(i)];
  const dReal* p = o.body ? dBodyGetPosition(o.body) : dGeomGetPosition(o.geom);
  const dReal* R = o.body ? dBodyGetRotation(o.body) : dGeomGetRotation(o.geom);
  return make_transform(from_ode(R), make_vec3(p[0] / kMm, p[1] / kMm, p[2] / kMm));
}

bool World::object_removed(int i) const { return objects_[size_t(i)].removed; }
bool World::object_carried(int i) const { return objects_[size_t(i)].carried(); }
int World::object_carrier(int i) const { return objects_[size_t(i)].carrier; }
dBodyID World::object_body(int i) const { return objects_[size_t(i)].body; }
dGeomID World::object_geom(int i) const { return objects_[size_t(i)].geom; }

}  // namespace articula::host
