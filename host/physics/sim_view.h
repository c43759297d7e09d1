// host/physics/sim_view.h - the simulation for the bindings (python/src, wasm/src): the world
// now and the scene's objects as JSON, deg or mm and 4x4 poses (16 numbers, row-major, mm),
// one home so the Python package and the web engine describe a simulation alike.
#ifndef ARTICULA_HOST_SIM_VIEW_H
#define ARTICULA_HOST_SIM_VIEW_H

#include <nlohmann/json.hpp>

#include "scene.h"
#include "sim.h"

namespace articula::host {

// t, joints (deg or mm, as the steps put them), frames (base, rows, tool), tool, gripper_mm,
// counted_steps and lost_steps per motor, busy, parts (arm links and fingers: name, frame,
// pose), objects (name, pose, movable, carried, removed), contacts ({a, b, point_mm}).
nlohmann::json sim_state_json(const Simulation& sim);

// The scene's objects: name, type (box, cylinder, sphere), size (mm), movable, mass_kg, friction,
// belt (mm/s; 0: not a belt).
nlohmann::json scene_objects_json(const Scene& scene);

}  // namespace articula::host

#endif  // ARTICULA_HOST_SIM_VIEW_H
