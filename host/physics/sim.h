// host/physics/sim.h - the arm and its scene as rigid bodies in the Open Dynamics Engine.
//
// The model (docs/physics.md says why):
//   - links are kinematic bodies: steppers hold position, so each link's pose *is* the DH
//     frame of the motors' step counts at that instant, set every world step, with the
//     velocity of that motion so contacts push objects as the link would;
//   - the step counts are the firmware's own: firmware/src runs on its virtual clock
//     (firmware_session.h) and every step its coils make moves the links at its tick; a
//     robot without motors follows its joint targets as ideal position servos at a fixed
//     joint speed;
//   - a step that would push a link into the ground, a static object or a non-adjacent link,
//     or squeeze a movable object, is refused: the motor skips it (an open-loop stepper
//     loses it, the controller does not know) and an event says which parts, where, when;
//   - movable objects are dynamic bodies (gravity, contacts, friction); two fingers at the
//     tool frame follow the gripper commands; when both touch the same object while closing
//     it is grasped (carried rigidly with the tool) until the gripper opens again.
// Inside: SI units (m, kg, s, rad). Everything read or reported: mm and degrees.
#ifndef ARTICULA_PHYSICS_SIM_H
#define ARTICULA_PHYSICS_SIM_H

#include <nlohmann/json.hpp>
#include <ode/ode.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "firmware_session.h"
#include "predict.h"
#include "program.h"
#include "robot.h"
#include "run.h"
#include "scene.h"
#include "stall.h"
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
    kCollision,        // a step would push the arm into the ground or a static object: refused
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
  };
  Kind kind = Kind::kNote;
  double t = 0;         // s
  int line = 0;         // program line of the action running (0: none)
  std::string a, b;     // the parts: "link 2", "finger left", an object's name, "ground"
  bool has_point = false;
  Vec3<double> point_mm{0, 0, 0};
  double depth_mm = 0;  // penetration the refused step would have made
  Status reply = kOk;   // kRejected: the controller's answer
  std::string detail;
};
const char* event_kind_name(SimEvent::Kind k);
// An event as `articula sim --events` writes it: t, kind, line, a, b, point_mm, depth_mm, detail.
nlohmann::json event_json(const SimEvent& e);

// One kinematic part of the arm (a link, a finger) as the tests and the CLI see it.
struct ArmPartInfo {
  std::string name;
  int frame = -1;  // DH frame the part rides on; -1 a finger
  dBodyID body = nullptr;
  Transform<double> T = Transform<double>::identity();  // its accepted pose, mm
};

// Two things touching now (a movable object and the ground, another object or an arm part),
// with the (debounced) start of their contact's bookkeeping: what the studio highlights.
struct SimContact {
  std::string a, b;  // the movable object, and what it touches
  Vec3<double> point_mm{0, 0, 0};
};

class Simulation {
 public:
  // The scene's bodies and the arm at its power-up pose (the motors' zero steps, or the
  // home pose of a robot without motors). Throws std::invalid_argument for what cannot be
  // simulated (more than 8 motors, a mesh file that cannot be read: mesh.h).
  Simulation(const Robot& robot, const Scene& scene, const SimOptions& options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // The program the arm runs, from now: each line sent to the firmware once the arm is at
  // rest after the one before (as the harness and the studio's runner send). The firmware
  // powered up with the options' settings at construction and goes on from where it is; a
  // robot without motors: the kinematic model from where it is (replacing what it queued).
  // Commands refused become kRejected events.
  void load_program(const Program& program);

  // One protocol line (docs/protocol.md) to the firmware now, or as soon as the reply before
  // is off the wire (commands one after the other stream as GRBL's simple sender streams:
  // the firmware plans them into the moves ahead); its reply, the firmware's (run.h's
  // kinematic model for a robot without motors, which queues it after what it is doing). A
  // rejected line changes nothing (a kRejected event).
  Status command(const std::string& line);
  // Whether the arm is still busy with queued actions.
  bool busy() const;

  // A mouse drag: movable object i is pulled toward target_mm by a critically damped spring
  // (the same pull per kg for every object, gravity held, its spin damped), a body among
  // bodies, not teleported: what it hits stops it. Until release_drag(). Throws
  // std::invalid_argument for a static, removed or unknown object.
  void drag_object(int i, const Vec3<double>& target_mm);
  void release_drag();
  int dragged_object() const { return drag_object_; }

  // What touches what now (movable objects only; the arm's refused steps are events).
  std::vector<SimContact> contacts() const;

  void step();
  // Steps until time() >= t.
  void run_until(double t);
  // `n` world steps; after every `every`-th of them and after the last, the tool point (x, y,
  // z mm) appended to `path`: the path the tool took, for a pen's ink drawn from the physics
  // however rarely the world is looked at (the studio's live physics, Python's Sim.step_path).
  void step_path(int n, int every, std::vector<double>& path);
  double time() const { return double(steps_) * opt_.dt; }
  uint64_t steps_taken() const { return steps_; }
  double program_end() const { return program_end_s_; }
  // The program's line being carried out (1-based; 0 before the first action).
  int current_line() const { return current_line_; }
  double end_time() const { return program_end_s_ + opt_.extra_time; }
  bool done() const { return time() >= end_time() - 1e-12 && !busy(); }

  const std::vector<SimEvent>& events() const { return events_; }

  // The arm as it physically is (after skipped steps): joint variables in model units.
  const std::vector<double>& joints() const { return q_; }
  const HostFrames& frames() const { return frames_; }
  double gripper_opening_mm() const { return opening_mm_; }
  // Steps each motor has lost so far (physical - counted; a servo's, beyond half its dead band:
  // what holds it back, not where its own loop lets it rest), and the controller's counts.
  std::vector<int32_t> lost_steps() const;
  std::vector<int32_t> counted_steps() const;

  int num_objects() const { return int(scene_.objects.size()); }
  const SceneObject& object(int i) const { return scene_.objects[size_t(i)]; }
  Transform<double> object_pose(int i) const;  // mm
  bool object_removed(int i) const;
  bool object_carried(int i) const;
  dBodyID object_body(int i) const;  // null for a static object
  dGeomID object_geom(int i) const;

  std::vector<ArmPartInfo> arm_parts() const;
  dWorldID world() const { return world_; }
  const Robot& robot() const { return robot_; }
  const SimOptions& options() const { return opt_; }

 private:
  struct Part;
  struct Object;
  struct Pair;
  struct Action;
  struct MeshData;

  void build_arm();
  void build_scene();
  void build_pairs();
  void place_arm(const double* q, double opening_mm);
  void set_part_pose(Part& p, const Transform<double>& T_mm);
  bool check_pose(int line);  // false: blocked (event written once per action)
  void accept_pose();
  bool try_joints(const double* q_candidate, double opening_mm);
  void motor_events(uint64_t until_tick);
  void firmware_action_ends(uint64_t tick);
  void recount(const std::vector<int32_t>& counted);
  void apply_steps(uint8_t mask, uint8_t negative);
  void servo_follow(double dt);
  uint8_t try_motor_by_motor(const int32_t* from, const int32_t* move, uint8_t mask);
  bool try_steps(const int32_t* steps);
  void follow_joints(const std::vector<double>& q_cmd, double dt);
  void joint_follow(double t_end);
  void gripper_follow(double t_end);
  void begin_action(size_t index);
  void end_action();
  void update_carried();
  void collide_objects();
  void after_step();
  void measure_squeeze();
  void add_contact(dGeomID a, dGeomID b, double mu, int touch_index, bool joints = true);
  void event(SimEvent::Kind k, const std::string& a, const std::string& b, const std::string& detail,
             const dContactGeom* c = nullptr);
  double target_opening(double t) const;
  void grasp_check();
  void stall_check(const std::vector<int32_t>& delta, const MotionSettings& motion);
  void reset_controller();
  void enqueue(const Statement& st, uint64_t now_tick);
  Status send(const Statement& st, uint64_t now_tick, FirmwareSession::Sender sender);
  SimEvent rejection(uint64_t tick, int line, const std::string& text, Status s, const std::string& note);
  void rejected(uint64_t tick, int line, const std::string& text, Status s, const std::string& note);
  void apply_drag();

  Robot robot_;
  Scene scene_;
  SimOptions opt_;
  bool motors_ = false;
  int n_motors_ = 0, n_joints_ = 0;

  dWorldID world_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  dGeomID ground_ = nullptr;

  std::vector<std::unique_ptr<MeshData>> meshes_;  // mesh shapes' triangles, kept while their geoms live
  std::vector<std::unique_ptr<Part>> parts_;  // arm parts: links by frame, then the fingers
  int finger_[2] = {-1, -1};
  std::vector<Object> objects_;
  std::vector<Pair> block_pairs_;  // arm part vs ground/static/self/movable (squeeze), for step checks
  std::vector<double> block_depth_;  // scratch: the candidate's depth per block pair

  // What turns commands into motion (one of the two): the firmware itself on its virtual
  // clock (a robot with motors; its lines from a program's statements: lines_, on a copy of
  // the robot that RoboSim's l may change), or the kinematic model and what it has queued so
  // far: where the queue ends, the joints and gripper it leaves.
  std::unique_ptr<FirmwareSession> firmware_;
  Robot lines_robot_;
  std::unique_ptr<StatementLines> lines_;
  std::unique_ptr<KinematicModel> kinematic_;
  uint64_t queue_end_tick_ = 0;
  std::vector<double> queued_q_;
  int queued_percent_ = -1;

  // A mouse drag: the object (-1 none) and where it is pulled, m.
  int drag_object_ = -1;
  double drag_target_[3] = {0, 0, 0};

  // The program.
  std::vector<Action> actions_;
  size_t action_ = 0;  // the action running or next
  bool action_running_ = false;
  double program_end_s_ = 0;
  uint64_t ticks_per_step_ = 2000;

  // Motor state: counted steps (what the firmware believes), physical = counted + offset.
  int32_t counted_[8]{}, offset_[8]{}, lost_in_action_[8]{};
  // Hobby servos (a servo arm's motors): a step is a tick of the pulse the servo is given (its
  // command); the servo's own position loop turns it towards the command at its top speed
  // (ticks/s) and stops within half its dead band (ticks). servo_carry_: a tick's fraction.
  bool servo_[8]{};
  bool has_servos_ = false;  // any servo_[i]: servo_follow() runs each world step
  double servo_rate_[8]{}, servo_carry_[8]{};
  int32_t servo_band_[8]{};
  bool firmware_action_ = false;  // an action of the firmware's runs (its line: current_line_)
  uint64_t event_tick_ = 0;
  // The gripper's commanded opening: from, to, over [t0, t1] (s).
  double grip_from_ = 0, grip_to_ = 0, grip_t0_ = 0, grip_t1_ = 0;

  // Joint state (model units): physical q, its DH frames, and the gripper.
  std::vector<double> q_, q_try_, q_cmd_, q_cmd_want_;
  HostFrames frames_{}, frames_try_{};
  double opening_mm_ = 0, opening_from_mm_ = 0;
  bool grip_closing_ = false, grip_stalled_ = false;
  double grip_stall_mm_ = 0;
  bool arm_moved_ = false;  // a kinematic body moved during this world step
  bool blocked_reported_ = false;
  uint64_t retry_after_step_ = 0;  // robots without motors: a blocked arm retries joint by joint every 10 ms
  void restore_arm();
  int current_line_ = 0;

  // The stall model (robots with motors and pull-out curves; else null).
  std::unique_ptr<StallModel> stall_;

  std::vector<SimEvent> events_;
  std::vector<SimEvent> pending_;  // rejected commands, shown when the clock reaches them
  size_t pending_next_ = 0;
  uint64_t steps_ = 0;

  // Contact bookkeeping: touching state per (movable object, other thing).
  int n_others_ = 0;
  std::vector<uint8_t> touching_, touched_now_;
  std::vector<dContactGeom> touch_point_;
  std::vector<uint64_t> last_touch_;  // world step of the last touch: an end is reported 50 ms later
  std::vector<std::string> other_names_;
};

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_SIM_H
