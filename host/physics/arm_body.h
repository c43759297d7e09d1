// host/physics/arm_body.h - one arm in the world (world.h): its links and fingers as kinematic
// bodies, where its motors stand (counted by its controller, and physically: a refused step is
// a step lost), the checks that refuse a step into something, and its gripper's grasp.
// What moves it is its driver (arm_driver.h); the world steps them all on one clock.
#ifndef ARTICULA_PHYSICS_ARM_BODY_H
#define ARTICULA_PHYSICS_ARM_BODY_H

#include <ode/ode.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "firmware_session.h"
#include "stall.h"
#include "world.h"

namespace articula::host {

class ArmBody {
 public:
  // Reads the robot's mesh files (throws std::invalid_argument naming the one that cannot be
  // read) and makes its parts in the world, at the power-up pose.
  ArmBody(World& world, int index, const ArmPlacement& placement);
  ~ArmBody();
  ArmBody(const ArmBody&) = delete;
  ArmBody& operator=(const ArmBody&) = delete;

  const Robot& robot() const { return robot_; }
  const std::string& name() const { return name_; }
  int index() const { return index_; }
  const Transform<double>& T_world_base() const { return T_world_base_; }
  bool has_motors() const { return motors_; }
  // How far from its base frame's origin any part of the arm can ever be, mm (a bound, over
  // every joint value within its limits): two arms farther apart than their reaches' sum never
  // meet, and the world checks no step of one against the other.
  double reach_mm() const { return reach_mm_; }
  bool within_reach(const ArmBody& other) const;
  int num_motors() const { return n_motors_; }

  // The arm as it physically is (after skipped steps): joint variables in model units, its DH
  // frames in its base frame, the gripper's opening.
  const std::vector<double>& joints() const { return q_; }
  const HostFrames& frames() const { return frames_; }
  double gripper_opening_mm() const { return opening_mm_; }
  // Steps each motor has lost so far (physical - counted; a servo's, beyond half its dead band:
  // what holds it back, not where its own loop lets it rest), and the controller's counts.
  std::vector<int32_t> lost_steps() const;
  std::vector<int32_t> counted_steps() const;
  std::vector<ArmPartInfo> arm_parts() const;
  // The program's line being carried out (1-based; 0 before the first action).
  int current_line() const { return current_line_; }
  // A part's name as the world's events give it: its own ("link 2") in a world of one arm,
  // with the arm's in a world of several ("right: link 2").
  std::string label(const std::string& part) const;

  // ---- what the driver does to it (arm_driver.cpp) ----
  // One step event of the firmware: the counts always change; the arm follows unless blocked,
  // motor by motor.
  void apply_steps(uint8_t mask, uint8_t negative);
  // A servo arm's servos over one world step (see servo_rate_).
  void servo_follow(double dt);
  // Robots without motors: ideal position servos toward q_cmd over dt; after a block they
  // catch up at twice the speed.
  void follow_joints(const std::vector<double>& q_cmd, double dt);
  // The firmware's step counts now `counted` (Z, homing, each action's start): the arm stays
  // where it is, so what it is off its counts changes by as much.
  void recount(const std::vector<int32_t>& counted);
  // An action of the controller's begins at `tick` on program line `line` (firmware: the one
  // before, if any, ends there) / the firmware's action ends (the steps lost in it: an event).
  void action_begins(uint64_t tick, int line, bool firmware);
  void firmware_action_ends(uint64_t tick);
  // The gripper holds where it is until commanded otherwise.
  void hold_grip() {
    grip_from_ = grip_to_ = opening_mm_;
    grip_blocked_reported_ = false;
  }
  // The gripper is commanded from wherever it is at t0 to `to_mm` by t1 (s).
  void grip(double to_mm, double t0, double t1);
  // Will the motors keep up with this move? (stall.h; an event when not)
  void stall_check(const std::vector<int32_t>& delta, const MotionSettings& motion);
  void set_event_tick(uint64_t tick) { event_tick_ = tick; }
  void set_line(int line) { current_line_ = line; }
  // An event of this arm's: dated at the firmware's tick (event_tick) or at the end of the world
  // step, on its line (event), or as given (add_event).
  void event(SimEvent::Kind k, const std::string& a, const std::string& b, const std::string& detail,
             const dContactGeom* c = nullptr);
  void add_event(SimEvent e);

  // ---- the world step (world.cpp) ----
  void begin_step();
  void gripper_follow(double t_end);
  // The moved parts' (and carried objects') velocities for the contacts of this world step.
  void set_velocities(double t_start, double t_end, double dt);
  void end_step();  // back at the accepted pose after ODE moved the kinematic bodies
  void measure_squeeze();
  bool moved() const { return arm_moved_; }
  // Made by the world in this order: the parts (once its ODE world exists), then, once every
  // arm's parts and the objects exist, the pairs a step is checked on, then the start pose.
  void build_parts();
  void build_pairs();
  void start();

  struct Part {
    std::string name;
    int frame = -1;  // DH frame; -1 a finger
    int side = 0;    // finger: -1 right, +1 left (along the tool's y)
    int chain = 0;   // position along the arm: parts one apart are adjacent
    double mu = 0;
    dBodyID body = nullptr;
    std::vector<dGeomID> geoms;
    Transform<double> T = Transform<double>::identity();       // accepted pose in the world, mm
    Transform<double> T_prev = Transform<double>::identity();  // at the start of the world step
    bool moved = false;
    Transform<double> T_set{};  // the pose last given to ODE
    double t_last_move = 0;  // when it last moved (s): a step's displacement is spread over the time since
  };
  const std::vector<std::unique_ptr<Part>>& parts() const { return parts_; }

 private:
  struct Pair;
  struct MeshData;

  void place_arm(const double* q, double opening_mm);
  void set_part_pose(Part& p, const Transform<double>& T_world);
  Transform<double> in_world(const Transform<double>& T_base) const;
  bool check_pose(int line);  // false: blocked (event written once per action)
  void accept_pose();
  void restore_arm();
  bool try_joints(const double* q_candidate, double opening_mm);
  bool try_steps(const int32_t* steps);
  uint8_t try_motor_by_motor(const int32_t* from, const int32_t* move, uint8_t mask);
  double target_opening(double t) const;
  void grasp_check();
  double time() const;

  World& world_;
  int index_ = 0;
  Robot robot_;
  std::string name_;
  Transform<double> T_world_base_ = Transform<double>::identity();
  bool placed_ = false;  // the base stands anywhere but at the world's origin
  double reach_mm_ = 0;
  SimOptions opt_;
  bool motors_ = false;
  int n_motors_ = 0, n_joints_ = 0;

  std::vector<std::unique_ptr<MeshData>> meshes_;  // mesh shapes' triangles, kept while their geoms live
  std::vector<std::unique_ptr<Part>> parts_;  // arm parts: links by frame, then the fingers
  int finger_[2] = {-1, -1};
  std::vector<Pair> block_pairs_;  // arm part vs ground/static/self/other arm/movable (squeeze), for step checks
  std::vector<double> block_depth_;  // scratch: the candidate's depth per block pair
  bool broad_ = false;  // check_pose's broad phase: which objects and other arms the moving arm's box reaches
  std::vector<uint8_t> near_object_, near_arm_;

  // Motor state: counted steps (what the firmware believes), physical = counted + offset.
  int32_t counted_[8]{}, offset_[8]{}, lost_in_action_[8]{};
  // Hobby servos (a servo arm's motors): a step is a tick of the pulse the servo is given (its
  // command); the servo's own position loop turns it towards the command at its top speed
  // (ticks/s) and stops within half its dead band (ticks). servo_carry_: a tick's fraction.
  bool servo_[8]{};
  bool has_servos_ = false;
  double servo_rate_[8]{}, servo_carry_[8]{};
  int32_t servo_band_[8]{};
  bool firmware_action_ = false;  // an action of the firmware's runs (its line: current_line_)
  uint64_t event_tick_ = 0;
  // The gripper's commanded opening: from, to, over [t0, t1] (s).
  double grip_from_ = 0, grip_to_ = 0, grip_t0_ = 0, grip_t1_ = 0;

  // Joint state (model units): physical q, its DH frames (base frame), and the gripper.
  std::vector<double> q_, q_try_, q_cmd_want_;
  HostFrames frames_{}, frames_try_{};
  double opening_mm_ = 0;
  bool grip_stalled_ = false;
  bool grip_blocked_reported_ = false;  // this gripper command's kGripperBlocked is out
  double grip_stall_mm_ = 0;
  bool arm_moved_ = false;  // a kinematic body moved during this world step
  bool blocked_reported_ = false;
  uint64_t retry_after_step_ = 0;  // robots without motors: a blocked arm retries joint by joint every 10 ms
  int current_line_ = 0;

  // The stall model (robots with motors and pull-out curves; else null).
  std::unique_ptr<StallModel> stall_;

 public:
  bool has_servos() const { return has_servos_; }
};

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_ARM_BODY_H
