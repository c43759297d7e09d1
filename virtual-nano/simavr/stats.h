// virtual-nano/simavr/stats.h - count, min, max and mean of a measured quantity.
#ifndef ARTICULA_HIL_VNANO_STATS_H
#define ARTICULA_HIL_VNANO_STATS_H

#include <cstdint>

#include <nlohmann/json.hpp>

namespace vnano {

struct Stat {
  uint64_t count = 0;
  double sum = 0, min = 0, max = 0;

  void add(double v) {
    if (count == 0 || v < min) min = v;
    if (count == 0 || v > max) max = v;
    sum += v;
    ++count;
  }
  double mean() const { return count ? sum / double(count) : 0.0; }

  // {"count": n, "min": .., "max": .., "mean": ..}; min/max/mean are null when count is 0.
  nlohmann::json json() const {
    nlohmann::json j;
    j["count"] = count;
    if (count) {
      j["min"] = round3(min);
      j["max"] = round3(max);
      j["mean"] = round3(mean());
    } else {
      j["min"] = j["max"] = j["mean"] = nullptr;
    }
    return j;
  }

  static double round3(double v) { return double(int64_t(v * 1000.0 + (v < 0 ? -0.5 : 0.5))) / 1000.0; }
};

}  // namespace vnano

#endif  // ARTICULA_HIL_VNANO_STATS_H
