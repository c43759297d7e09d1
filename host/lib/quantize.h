// host/lib/quantize.h - protocol lines through the firmware's codec and step arithmetic, one
// motor at a time: what whole steps make of each `L` move (`articula quantize`,
// `robot.quantize` in Python). Only L moves anything; the other commands are parsed and
// checked as the firmware does and reported as not simulated (predict.h runs them all).
#ifndef ARTICULA_HOST_QUANTIZE_H
#define ARTICULA_HOST_QUANTIZE_H

#include <articula/status.h>

#include <cstdint>
#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

struct QuantizeRecord {
  std::string text;        // the line as given
  Status reply = kOk;      // the controller's answer; a rejected line moves nothing
  bool simulated = true;   // false: a valid line quantize has no model for (M, P, G, H, Z, I, $)
  int motor = -1;          // the motor an accepted L moved; -1 none
  double commanded_deg = 0;  // that motor's exact commanded angle after the line
  int32_t steps = 0;         //   its step count
  double reached_deg = 0;    //   and the angle the steps give
  std::vector<int32_t> all_steps;          // every motor's step count after the line
  Vec3<double> tool_ideal{0, 0, 0};        // tool position of the exact commanded angles, mm
  Vec3<double> tool_quantized{0, 0, 0};    // tool position of the steps, mm
  double tool_error_mm = 0;                // |tool_quantized - tool_ideal|

  bool moved() const { return reply == kOk && motor >= 0; }
};

// Runs the lines one after the other from every motor at step 0. Throws
// std::invalid_argument for a robot without motors.
std::vector<QuantizeRecord> quantize_lines(const Robot& robot, const std::vector<std::string>& lines);

}  // namespace articula::host

#endif  // ARTICULA_HOST_QUANTIZE_H
