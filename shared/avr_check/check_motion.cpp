#include <articula/motion.h>
#include "check_common.h"
using namespace articula;
// The firmware's sizes: 2 MHz ticks, three motors; every function of motion.h. In small
// functions of their own: a frame above 63 bytes makes every access to a local longer.
// The settings come from EEPROM at run time: nothing here may fold them into constants.
static MotionSettings s_settings = {kStepTickHz, 1000UL, 4000UL};

__attribute__((noinline)) static long check_profile() {
  StepProfile p;
  p.start(uint32_t(g_out), s_settings);
  long out = long(p.next_interval());
  p.stop();
  return out + long(p.stop_steps() + p.steps_left()) + p.done();
}

// The firmware's split: constants once per settings change, a cheap start per move.
__attribute__((noinline)) static long check_constants() {
  ProfileConstants k;
  const MotionError e = profile_constants(k, s_settings);
  StepProfile p;
  p.start(uint32_t(g_out), k);
  return long(p.next_interval()) + e;
}

__attribute__((noinline)) static long check_line_stepper() {
  int32_t delta[kJoints];
  for (int i = 0; i < kJoints; ++i) delta[i] = int32_t(g_out);
  LineStepper<kJoints> line;
  line.start(delta, kJoints);
  long out = line.negative;
  while (!line.done()) out += line.next();
  return out;
}

void check_motion() {
  s_settings.max_rate = uint32_t(g_out);
  uint64_t times[2] = {0, 0};
  const long host = long(profile_duration_ticks(uint32_t(g_out), s_settings)) +
                    long(profile_step_times(times, 2, 10, s_settings)) + long(times[1]);
  g_out = host + check_profile() + check_constants() + check_line_stepper() + motion_error_text(validate(s_settings))[0] +
          cruise_level_cap(s_settings, uint32_t(g_out), uint32_t(g_out) + 1);
}
