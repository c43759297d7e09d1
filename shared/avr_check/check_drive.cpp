#include <articula/drive.h>
#include "check_common.h"
using namespace articula;
void check_drive() {
  // The firmware's STEP/DIR timing: a chip's datasheet figures, and a mode's check.
  const StepDirChip& c = kStepDirChip[uint8_t(g_in) % kStepDirChips];
  g_out = long(c.step_high_ns) + long(microsteps_allowed(c.microsteps_mask, uint16_t(g_out)));
}
