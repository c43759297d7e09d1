// host/physics/world.h - one world of rigid bodies in the Open Dynamics Engine: the scene's
// objects and any number of arms on the table, on one virtual clock.
//
// The model (docs/physics.md says why):
//   - each arm's links are kinematic bodies: steppers hold position, so each link's pose *is*
//     the DH frame of the motors' step counts at that instant (placed where the arm's base
//     stands on the table), set every world step, with the velocity of that motion so contacts
//     push objects as the link would;
//   - each arm's step counts are its own firmware's: firmware/src runs on its own virtual Nano
//     (firmware_session.h, a sitl::Machine each) and every step its coils make moves the links
//     at its tick; a robot without motors follows its joint targets as ideal position servos at
//     a fixed joint speed (arm_driver.h);
//   - a step that would push a link into the ground, a static object, a non-adjacent link of
//     its own, another arm, or squeeze a movable object, is refused: the motor skips it (an
//     open-loop stepper loses it, the controller does not know) and an event says which parts,
//     where, when (arm_body.h);
//   - movable objects are dynamic bodies (gravity, contacts, friction); two fingers at each
//     tool frame follow that arm's gripper commands; when both touch the same object while
//     closing it is grasped (carried rigidly with the tool) until the gripper opens again, or
//     until another arm's fingers close on it: a handover.
// The parts: World (this file: ODE, the objects, contacts, drag, the clock), ArmBody (an arm's
// parts, pose checks and steps), ArmDriver (what moves it: its firmware or the kinematic
// model). Simulation (sim.h) is a world of one arm; Cell (cell_sim.h) one of a cell file's arms.
// Inside: SI units (m, kg, s, rad). Everything read or reported: mm and degrees.
#ifndef ARTICULA_PHYSICS_WORLD_H
#define ARTICULA_PHYSICS_WORLD_H

#include <nlohmann/json.hpp>
#include <ode/ode.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "predict.h"
#include "robot.h"
#include "run.h"
#include "scene.h"
#include "timeline.h"

namespace articula::host {

struct SimOptions {
  double dt = 0.001;                  // world step, s
  double extra_time = 1.0;            // simulated after the program's last action, s
  double touch_tolerance_mm = 1.0;    // how deep the arm may touch a static thing before a step is refused
  double squeeze_mm = 3.0;            // a movable object pressed deeper than this stops the arm
  JointTiming joints;                 // robots without motors: joint speeds, a gripper action's time
  bool quick_step = false;            // dWorldQuickStep (iterative) instead of dWorldStep
  bool stall_check = true;            // check every move against the motors' pull-out curves (stall.h)
  ControllerSettings settings;        // the controller's settings at power-up
};

struct SimEvent {
  enum class Kind {
    kContactStarted,   // a movable object starts touching something
    kContactEnded,
    kCollision,        // a step would push the arm into the ground, a static object or another arm: refused
    kSelfCollision,    // ... into a non-adjacent part of itself
    kSqueeze,          // ... or press a movable object into something: refused
    kStepsLost,        // at the end of an action: steps the motors skipped (open loop: not known to the firmware)
    kBlocked,          // robots without motors: an action ended short of its target
    kGrasp,
    kRelease,
    kGripperBlocked,   // the fingers stop closing on something they cannot grasp
    kRejected,         // the controller refused a command (nothing moved)
    kObjectRemoved,    // a body left the world box or its state stopped being finite
    kNote,             // information (self-collision pairs left out, ...)
    kStall,            // a move needs more torque of a motor than its pull-out curve gives: it would skip (stall.h)
    kDeadlock,         // a cell's arms each wait for a signal that none will give (cell_sim.h): told in `detail`
    kDevice,           // a cell's device changed (cell_file.h): a belt starts or stops, a beam is broken
                       // (`b`: by what) or clear again; `a` the device, `detail` in words
  };
  Kind kind = Kind::kNote;
  double t = 0;         // s
  std::string arm;      // the arm whose action it is, in a world of several ("" in a world of one)
  int line = 0;         // that arm's program line of the action running (0: none)
  std::string a, b;     // the parts: "link 2", "finger left", an object's name, "ground"; another
                        // arm's part with its arm's name: "right: link 3"
  bool has_point = false;
  Vec3<double> point_mm{0, 0, 0};
  double depth_mm = 0;  // penetration the refused step would have made
  Status reply = kOk;   // kRejected: the controller's answer
  std::string detail;
};
const char* event_kind_name(SimEvent::Kind k);
// An event as `articula sim --events` writes it: t, kind, (arm,) line, a, b, point_mm, depth_mm, detail.
nlohmann::json event_json(const SimEvent& e);

// One kinematic part of an arm (a link, a finger) as the tests and the CLI see it.
struct ArmPartInfo {
  std::string name;
  int frame = -1;  // DH frame the part rides on; -1 a finger
  dBodyID body = nullptr;
  Transform<double> T = Transform<double>::identity();  // its accepted pose in the world, mm
};

// Two things touching now (a movable object and the ground, another object or an arm part),
// with the (debounced) start of their contact's bookkeeping: what the studio highlights.
struct SimContact {
  std::string a, b;  // the movable object, and what it touches
  Vec3<double> point_mm{0, 0, 0};
};

// An arm in a world: its robot, its name (shown with its events and parts when the world has
// several; "" for a world of one) and where its base stands: the base frame's pose on the
// table (mm), so the world frame is the table's.
struct ArmPlacement {
  Robot robot;
  std::string name;
  Transform<double> T_world_base = Transform<double>::identity();
};

class ArmBody;
class ArmDriver;

class World {
 public:
  // The scene's bodies and every arm at its power-up pose (the motors' zero steps, or the home
  // pose of a robot without motors), each with its controller ready for commands. Throws
  // std::invalid_argument for what cannot be simulated (no arm, more than 8 motors, a mesh file
  // that cannot be read: mesh.h).
  World(const std::vector<ArmPlacement>& arms, const Scene& scene, const SimOptions& options = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int num_arms() const { return int(bodies_.size()); }
  ArmBody& body(int arm) { return *bodies_[size_t(arm)]; }
  const ArmBody& body(int arm) const { return *bodies_[size_t(arm)]; }
  ArmDriver& driver(int arm) { return *drivers_[size_t(arm)]; }
  const ArmDriver& driver(int arm) const { return *drivers_[size_t(arm)]; }
  // The arm of that name (-1: none).
  int arm_index(const std::string& name) const;

  void step();
  // Steps until time() >= t.
  void run_until(double t);
  double time() const { return double(steps_) * opt_.dt; }
  uint64_t steps_taken() const { return steps_; }
  uint64_t now_tick() const { return steps_ * ticks_per_step_; }
  // Whether any arm is still busy with queued actions.
  bool busy() const;

  const std::vector<SimEvent>& events() const { return events_; }
  void add_event(const SimEvent& e) { events_.push_back(e); }
  // What touches what now (movable objects only; the arms' refused steps are events).
  std::vector<SimContact> contacts() const;

  // A mouse drag: movable object i is pulled toward target_mm by a critically damped spring
  // (the same pull per kg for every object, gravity held, its spin damped), a body among
  // bodies, not teleported: what it hits stops it. Until release_drag(). Throws
  // std::invalid_argument for a static, removed or unknown object.
  void drag_object(int i, const Vec3<double>& target_mm);
  void release_drag();
  int dragged_object() const { return drag_object_; }
  // A belt's speed (mm/s; 0 stops it): object i must be a belt of the scene (SceneObject::belt).
  // Throws std::invalid_argument otherwise.
  void set_belt(int i, double mm_s);
  // The first of the scene's objects (not removed) that the segment from..to (mm, on the table)
  // passes through, by name ("" none): a light barrier's beam.
  std::string beam_blocker(const Vec3<double>& from_mm, const Vec3<double>& to_mm) const;
  // The first thing inside the box of `size_mm` at `centre_mm` (upright, on the table): a movable
  // object (not removed; a static one is the switch's mount) or an arm's part ("link 2", "right: finger left" in a world of several), by
  // name ("" none): a touch or limit switch's actuator.
  std::string box_presser(const Vec3<double>& centre_mm, const Vec3<double>& size_mm) const;
  // A feeder's magazine (cell_file.h): movable object i taken out of the world, as if it had left
  // it (object_removed() is true; no event), until put_out() puts it at xyz_mm (its centre, turned
  // as the scene turns it, at rest) if nothing (an object, an arm's part) stands there; false if
  // something does. Throws std::invalid_argument for a static or unknown object.
  void stow_object(int i);
  bool put_out(int i, const Vec3<double>& xyz_mm);
  // The scene with every object a drag let go of standing where it was let go, turned as it
  // was: where a student put it by hand, for the next run to start from (the studio's Run).
  Scene scene_as_placed() const;

  int num_objects() const { return int(scene_.objects.size()); }
  const SceneObject& object(int i) const { return scene_.objects[size_t(i)]; }
  Transform<double> object_pose(int i) const;  // mm
  bool object_removed(int i) const;
  bool object_carried(int i) const;
  int object_carrier(int i) const;  // the arm that carries it (-1: none)
  dBodyID object_body(int i) const;  // null for a static object
  dGeomID object_geom(int i) const;

  dWorldID world() const { return world_; }
  const Scene& scene() const { return scene_; }
  const SimOptions& options() const { return opt_; }

 private:
  friend class ArmBody;
  struct Object {
    dBodyID body = nullptr;  // null: static
    dGeomID geom = nullptr;
    bool movable = false, removed = false;
    int carrier = -1;  // the arm that carries it (-1: none)
    double mu = 0.8;
    bool belt = false;       // a conveyor belt (static): its top face moves
    double belt_m_s = 0;     // its speed now, along belt_dir
    double belt_dir[3] = {1, 0, 0}, belt_up[3] = {0, 0, 1};  // its x and its top face's normal, world
    Transform<double> T_tool_obj = Transform<double>::identity();  // carried: pose in its carrier's tool frame, mm
    Transform<double> T_carry = Transform<double>::identity();     // carried: accepted pose, mm
    Transform<double> T_carry_prev = Transform<double>::identity();
    double last_good[3] = {0, 0, 0};
    bool carried() const { return carrier >= 0; }
  };

  void build_scene();
  void collide_objects();
  void add_contact(dGeomID a, dGeomID b, double mu, int touch_index, bool joints = true, const Object* belt = nullptr);
  void after_step();
  void apply_drag();
  // An event of the world's own (contacts, objects leaving): dated at the end of the world step,
  // on the line of the arm it involves (in a world of one, that arm's).
  void event(SimEvent::Kind k, int arm, const std::string& a, const std::string& b, const std::string& detail,
             const dContactGeom* c = nullptr);
  int event_arm(int other) const;  // the arm a contact with `other` involves (-1: none)

  Scene scene_;
  SimOptions opt_;
  uint64_t ticks_per_step_ = 2000;

  dWorldID world_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  dGeomID ground_ = nullptr;
  std::vector<Object> objects_;

  std::vector<std::unique_ptr<ArmBody>> bodies_;
  std::vector<std::unique_ptr<ArmDriver>> drivers_;

  // A mouse drag: the object (-1 none) and where it is pulled, m.
  int drag_object_ = -1;
  double drag_target_[3] = {0, 0, 0};
  std::map<int, Transform<double>> placed_;  // each object a drag let go of: where (mm)

  std::vector<SimEvent> events_;
  uint64_t steps_ = 0;

  // Contact bookkeeping: touching state per (movable object, other thing); the others are the
  // ground, every object, then every arm's parts, arm by arm (other_arm_: which, -1 none).
  int n_others_ = 0;
  std::vector<uint8_t> touching_, touched_now_;
  std::vector<dContactGeom> touch_point_;
  std::vector<uint64_t> last_touch_;  // world step of the last touch: an end is reported 50 ms later
  std::vector<std::string> other_names_;
  std::vector<int> other_arm_;
};

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_WORLD_H
