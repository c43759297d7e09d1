// host/physics/cell_sim.cpp - see cell_sim.h.
#include "cell_sim.h"

#include <algorithm>

namespace articula::host {

namespace {

std::vector<ArmPlacement> placements(const Cell& cell) {
  std::vector<ArmPlacement> out;
  for (const CellArm& a : cell.arms) out.push_back({a.robot, a.name, a.T_world_base()});
  return out;
}

}  // namespace

CellSimulation::CellSimulation(const Cell& cell, const SimOptions& options)
    : cell_(cell), world_(placements(cell), cell.scene, options) {
  for (size_t i = 0; i < cell_.arms.size(); ++i)
    if (!cell_.arms[i].program.statements.empty()) world_.driver(int(i)).load_program(cell_.arms[i].program, 0);
}

double CellSimulation::program_end() const {
  double end = 0;
  for (int i = 0; i < world_.num_arms(); ++i) end = std::max(end, world_.driver(i).program_end());
  return end;
}

nlohmann::json cell_arms_json(const CellSimulation& sim) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < sim.num_arms(); ++i) {
    const ArmBody& b = sim.arm(i);
    const CellArm& a = sim.cell().arms[size_t(i)];
    const Robot& r = b.robot();
    std::vector<double> q;
    for (int j = 0; j < r.model.num_joints; ++j) q.push_back(joint_from_model(r, j, b.joints()[size_t(j)]));
    const Transform<double> T = a.T_world_base() * b.frames().T_base_tool;
    out.push_back({{"name", b.name()},
                   {"robot", r.name},
                   {"base", {{"xyz", {a.xyz.x, a.xyz.y, a.xyz.z}}, {"yaw", a.yaw_deg}, {"footprint_mm", a.footprint_mm}}},
                   {"program", a.program_ref},
                   {"program_end_s", sim.driver(i).program_end()},
                   {"line", b.current_line()},
                   {"joints", q},
                   {"tool_mm", {T.p.x, T.p.y, T.p.z}},
                   {"gripper_mm", b.gripper_opening_mm()},
                   {"counted_steps", b.counted_steps()},
                   {"lost_steps", b.lost_steps()}});
  }
  return out;
}

nlohmann::json cell_state_json(const CellSimulation& sim) {
  const World& w = sim.world();
  nlohmann::json objects = nlohmann::json::array();
  for (int i = 0; i < w.num_objects(); ++i) {
    const Transform<double> T = w.object_pose(i);
    const int carrier = w.object_carrier(i);
    objects.push_back({{"name", w.object(i).name},
                       {"xyz_mm", {T.p.x, T.p.y, T.p.z}},
                       {"carried_by", carrier >= 0 ? nlohmann::json(w.body(carrier).name()) : nlohmann::json(nullptr)},
                       {"removed", w.object_removed(i)}});
  }
  return {{"t", sim.time()}, {"arms", cell_arms_json(sim)}, {"objects", objects}};
}

}  // namespace articula::host
