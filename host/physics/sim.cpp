// host/physics/sim.cpp - see sim.h.
#include "sim.h"

namespace articula::host {

Simulation::Simulation(const Robot& robot, const Scene& scene, const SimOptions& options)
    : world_({ArmPlacement{robot, "", Transform<double>::identity()}}, scene, options) {}

void Simulation::step_path(int n, int every, std::vector<double>& path) {
  every = std::max(1, every);
  for (int i = 1; i <= n; ++i) {
    step();
    if (i % every == 0 || i == n) {
      const Vec3<double>& p = frames().T_base_tool.p;
      path.insert(path.end(), {p.x, p.y, p.z});
    }
  }
}

}  // namespace articula::host
