// bench/bench_common.h - robots and random poses shared by the benchmarks.
#ifndef ARTICULA_BENCH_COMMON_H
#define ARTICULA_BENCH_COMMON_H

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "robot.h"
#include "robot_file.h"

namespace articula::bench {

inline host::Robot load(const std::string& name) {
  return host::load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/" + name + ".json");
}

// The Panda exactly as published (7 rows, a4 = -82.5 mm), built in code: the robot file
// needs two extra fixed rows for the negative a (robots/panda.json), this needs none.
inline host::HostModel panda_published() {
  const host::Robot file = load("panda");
  host::HostModel m{};
  const double a[7] = {0, 0, 0, 82.5, -82.5, 0, 88};
  const double d[7] = {333, 0, 316, 0, 384, 0, 0};
  const double alpha[7] = {0, -90, 90, 90, -90, 90, 90};
  m.num_rows = 7;
  m.num_joints = 7;
  m.num_linked = 0;
  for (int i = 0; i < 7; ++i) {
    m.rows[i] = DhRow<double>{a[i], deg_to_rad(alpha[i]), d[i], 0.0};
    m.joints[i].row = uint8_t(i);
    m.joints[i].param = kParamTheta;
    m.joints[i].lo = file.model.joints[i].lo;
    m.joints[i].hi = file.model.joints[i].hi;
  }
  m.T_last_tool = make_transform(identity3<double>(), make_vec3(0.0, 0.0, 107.0));
  return m;
}

// n joint vectors uniform within the model's joint limits, from a fixed seed.
inline std::vector<std::vector<double>> random_poses(const host::HostModel& m, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> out;
  for (int i = 0; i < count; ++i) {
    std::vector<double> q(size_t(m.num_joints));
    for (int j = 0; j < m.num_joints; ++j)
      q[size_t(j)] = std::uniform_real_distribution<double>(m.joints[j].lo, m.joints[j].hi)(rng);
    out.push_back(q);
  }
  return out;
}

// The p-quantile (0..1) of sorted values, interpolated.
inline double percentile_sorted(const std::vector<double>& v, double p) {
  if (v.empty()) return 0;
  const double pos = p * double(v.size() - 1);
  const size_t i = size_t(pos);
  const double f = pos - double(i);
  return i + 1 < v.size() ? v[i] * (1 - f) + v[i + 1] * f : v[i];
}

}  // namespace articula::bench

#endif  // ARTICULA_BENCH_COMMON_H
