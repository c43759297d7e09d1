#include <articula/planner.h>
#include "check_common.h"
using namespace articula;
// The firmware's planner: a junction of two three-motor moves (64-bit arithmetic), and the
// reverse pass over a small queue.
static PlanBlock s_blocks[4];

void check_planner() {
  int32_t a[3] = {int32_t(g_out), 1, -2}, b[3] = {int32_t(g_in), 3, 0};
  const uint16_t level = junction_level<3>(a, uint32_t(g_out), b, uint32_t(g_in), 3, uint32_t(g_out));
  for (uint8_t k = 0; k < 4; ++k) {
    s_blocks[k].steps = uint16_t(g_in + k);
    s_blocks[k].max_entry = level;
  }
  const uint16_t first = plan_entries([](uint8_t k) -> const PlanBlock& { return s_blocks[k]; },
                                      [](uint8_t k, uint16_t e) { s_blocks[k].entry = e; }, 4);
  g_out = long(level) + first;
}
