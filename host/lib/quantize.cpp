#include "quantize.h"

#include <articula/protocol.h>

#include <stdexcept>

namespace articula::host {

std::vector<QuantizeRecord> quantize_lines(const Robot& robot, const std::vector<std::string>& lines) {
  if (!robot.has_motors) throw std::invalid_argument(robot.name + " has no motors in " + robot.source + ": nothing to quantize");
  const int n = robot.actuation.num_motors;
  MotorState<kMaxJoints> state;
  reset(state, robot.actuation);
  std::vector<QuantizeRecord> out;
  out.reserve(lines.size());
  for (const std::string& text : lines) {
    QuantizeRecord r;
    r.text = text;
    Command cmd;
    r.reply = text.size() > 255 ? kLineTooLong : parse_line(cmd, text.data(), uint8_t(text.size()), uint8_t(n));
    if (r.reply == kOk && cmd.type == kCmdRotate) {
      r.motor = cmd.arg[0];
      r.reply = move_relative(state, robot.actuation, uint8_t(r.motor), cmd.arg[1]);
    }
    r.simulated = r.reply != kOk || cmd.type == kCmdNone || cmd.type == kCmdRotate || cmd.type == kCmdGripper;
    // Ideal: the exact commanded angles; quantized: the steps.
    const size_t count = size_t(n);
    std::vector<double> u(count), q_ideal(count), q_real(count);
    for (int k = 0; k < n; ++k) u[size_t(k)] = deg_to_rad(state.commanded[k] / 1000.0);
    joints_from_actuators(q_ideal.data(), robot.actuation, u.data());
    joints_from_steps(q_real.data(), robot.actuation, state.steps);
    r.tool_ideal = tool_position(robot.model, q_ideal.data());
    r.tool_quantized = tool_position(robot.model, q_real.data());
    r.tool_error_mm = norm(r.tool_quantized - r.tool_ideal);
    r.all_steps.assign(state.steps, state.steps + n);
    if (r.moved()) {
      r.commanded_deg = state.commanded[r.motor] / 1000.0;
      r.steps = state.steps[r.motor];
      r.reached_deg = steps_to_degrees<double>(robot.actuation.motors[r.motor], state.steps[r.motor]);
    } else {
      r.motor = -1;
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace articula::host
