// host/physics/sim.h - the arm and its scene as rigid bodies in the Open Dynamics Engine: a
// world (world.h) of one arm at the origin, the simulation `articula sim ROBOT`, Python's Sim
// and the studio's live physics use. The model, and what each part does: world.h.
#ifndef ARTICULA_PHYSICS_SIM_H
#define ARTICULA_PHYSICS_SIM_H

#include <cstdint>
#include <string>
#include <vector>

#include "arm_body.h"
#include "arm_driver.h"
#include "program.h"
#include "robot.h"
#include "scene.h"
#include "world.h"

namespace articula::host {

class Simulation {
 public:
  // The scene's bodies and the arm at its power-up pose (the motors' zero steps, or the home
  // pose of a robot without motors). Throws std::invalid_argument for what cannot be
  // simulated (more than 8 motors, a mesh file that cannot be read: mesh.h).
  Simulation(const Robot& robot, const Scene& scene, const SimOptions& options = {});

  // The program the arm runs, from now: each line sent to the firmware once the arm is at
  // rest after the one before (as the harness and the studio's runner send). The firmware
  // powered up with the options' settings at construction and goes on from where it is; a
  // robot without motors: the kinematic model from where it is (replacing what it queued).
  // Commands refused become kRejected events.
  void load_program(const Program& program) { driver().load_program(program, world_.now_tick()); }

  // One protocol line (docs/protocol.md) to the firmware now, or as soon as the reply before
  // is off the wire (commands one after the other stream as GRBL's simple sender streams:
  // the firmware plans them into the moves ahead); its reply, the firmware's (run.h's
  // kinematic model for a robot without motors, which queues it after what it is doing). A
  // rejected line changes nothing (a kRejected event).
  Status command(const std::string& line) { return driver().command(line, world_.now_tick()); }
  // Whether the arm is still busy with queued actions.
  bool busy() const { return driver().busy(); }

  // A mouse drag (World::drag_object).
  void drag_object(int i, const Vec3<double>& target_mm) { world_.drag_object(i, target_mm); }
  void release_drag() { world_.release_drag(); }
  int dragged_object() const { return world_.dragged_object(); }
  void set_belt(int i, double mm_s) { world_.set_belt(i, mm_s); }  // (World::set_belt)
  Scene scene_as_placed() const { return world_.scene_as_placed(); }  // (World::scene_as_placed)

  // What touches what now (movable objects only; the arm's refused steps are events).
  std::vector<SimContact> contacts() const { return world_.contacts(); }

  void step() { world_.step(); }
  // Steps until time() >= t.
  void run_until(double t) { world_.run_until(t); }
  // `n` world steps; after every `every`-th of them and after the last, the tool point (x, y,
  // z mm) appended to `path`: the path the tool took, for a pen's ink drawn from the physics
  // however rarely the world is looked at (the studio's live physics, Python's Sim.step_path).
  void step_path(int n, int every, std::vector<double>& path);
  double time() const { return world_.time(); }
  uint64_t steps_taken() const { return world_.steps_taken(); }
  double program_end() const { return driver().program_end(); }
  // The program's line being carried out (1-based; 0 before the first action).
  int current_line() const { return body().current_line(); }
  double end_time() const { return program_end() + options().extra_time; }
  bool done() const { return time() >= end_time() - 1e-12 && !busy(); }

  const std::vector<SimEvent>& events() const { return world_.events(); }

  // The arm as it physically is (after skipped steps): joint variables in model units.
  const std::vector<double>& joints() const { return body().joints(); }
  const HostFrames& frames() const { return body().frames(); }
  double gripper_opening_mm() const { return body().gripper_opening_mm(); }
  // Steps each motor has lost so far (physical - counted; a servo's, beyond half its dead band:
  // what holds it back, not where its own loop lets it rest), and the controller's counts.
  std::vector<int32_t> lost_steps() const { return body().lost_steps(); }
  std::vector<int32_t> counted_steps() const { return body().counted_steps(); }

  int num_objects() const { return world_.num_objects(); }
  const SceneObject& object(int i) const { return world_.object(i); }
  Transform<double> object_pose(int i) const { return world_.object_pose(i); }  // mm
  bool object_removed(int i) const { return world_.object_removed(i); }
  bool object_carried(int i) const { return world_.object_carried(i); }
  dBodyID object_body(int i) const { return world_.object_body(i); }  // null for a static object
  dGeomID object_geom(int i) const { return world_.object_geom(i); }

  std::vector<ArmPartInfo> arm_parts() const { return body().arm_parts(); }
  dWorldID world() const { return world_.world(); }
  const Robot& robot() const { return body().robot(); }
  const SimOptions& options() const { return world_.options(); }

 private:
  ArmBody& body() { return world_.body(0); }
  const ArmBody& body() const { return world_.body(0); }
  ArmDriver& driver() { return world_.driver(0); }
  const ArmDriver& driver() const { return world_.driver(0); }

  World world_;
};

}  // namespace articula::host

#endif  // ARTICULA_PHYSICS_SIM_H
