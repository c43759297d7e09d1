// host/physics/sim_view.cpp - the simulation as JSON, for the bindings.
#include "sim_view.h"

#include "robot_view.h"

namespace articula::host {

nlohmann::json sim_state_json(const Simulation& s) {
  using json = nlohmann::json;
  const Robot& r = s.robot();
  json q = json::array(), parts = json::array(), objects = json::array(), contacts = json::array();
  for (int j = 0; j < r.model.num_joints; ++j) q.push_back(joint_from_model(r, j, s.joints()[size_t(j)]));
  for (const auto& p : s.arm_parts()) parts.push_back({{"name", p.name}, {"frame", p.frame}, {"pose", transform_json(p.T)}});
  for (int i = 0; i < s.num_objects(); ++i)
    objects.push_back({{"name", s.object(i).name},
                       {"pose", transform_json(s.object_pose(i))},
                       {"movable", s.object(i).movable},
                       {"carried", s.object_carried(i)},
                       {"removed", s.object_removed(i)}});
  for (const auto& c : s.contacts())
    contacts.push_back({{"a", c.a}, {"b", c.b}, {"point_mm", {c.point_mm.x, c.point_mm.y, c.point_mm.z}}});
  return {{"t", s.time()},
          {"joints", q},
          {"frames", frames_json(r, s.frames())},
          {"tool", transform_json(s.frames().T_base_tool)},
          {"gripper_mm", s.gripper_opening_mm()},
          {"counted_steps", s.counted_steps()},
          {"lost_steps", s.lost_steps()},
          {"busy", s.busy()},
          {"line", s.current_line()},
          {"parts", parts},
          {"objects", objects},
          {"contacts", contacts}};
}

nlohmann::json scene_objects_json(const Scene& scene) {
  static const char* kTypes[] = {"box", "cylinder", "sphere"};
  nlohmann::json out = nlohmann::json::array();
  for (const auto& o : scene.objects)
    out.push_back({{"name", o.name},
                   {"type", kTypes[int(o.type)]},
                   {"size", {o.size[0], o.size[1], o.size[2]}},
                   {"movable", o.movable},
                   {"mass_kg", o.movable ? o.mass_kg() : 0.0},
                   {"friction", o.friction},
                   {"belt", o.belt}});
  return out;
}

}  // namespace articula::host
