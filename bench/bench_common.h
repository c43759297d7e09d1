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
