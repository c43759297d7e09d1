#include <articula/line.h>
#include <articula/motion.h>
#include "check_common.h"
using namespace articula;
// The firmware's straight line: a MK2-like arm, a line cut through the closed form, and a
// segment's cruise.
static YppArm<float> s_arm;
static MotorSpec s_motors[3];

void check_line() {
  s_arm.base_height = 72;
  s_arm.upper = 135;
  s_arm.fore = 147;
  s_arm.tool_forward = g_in;
  s_arm.parallelogram = true;
  for (uint8_t i = 0; i < 3; ++i) {
    s_arm.lo[i] = -3;
    s_arm.hi[i] = 3;
    s_motors[i].min = -180000;
    s_motors[i].max = 180000;
  }
  const YppLineSolver solver = {&s_arm, s_motors};
  LineCutter<float, kJoints> cut;
  const Millideg at[3] = {0, 45000, 0};
  float from[3];
  const float to[3] = {200.0f, g_in, 100.0f};
  solver.tool(from, at);
  cut.start(from, to, at, 3, 0.1f);
  Millideg end[3];
  long n = 0;
  while (!cut.done() && cut.next(solver, end) == kOk) n += end[0] + segment_cruise4(uint32_t(end[1]), segment_ticks4(cut.segment_length(), g_in, kStepTickHz));
  g_out = n;
}
