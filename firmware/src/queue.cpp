// firmware/src/queue.cpp - the motion queue's ring.
#include "queue.h"

#include "hal.h"

namespace queue {

namespace {
Action g_ring[kSize];
uint8_t g_head;            // the front
volatile uint8_t g_count;  // changed by both sides

// The ring's place k after `i` (both below kSize): a compare, not a division (kSize is no
// power of two; the AVR has no divide instruction, and pop() runs in the step interrupt).
inline uint8_t ring(uint8_t i, uint8_t k) {
  const uint8_t j = uint8_t(i + k);
  return j >= kSize ? uint8_t(j - kSize) : j;
}
}  // namespace

void clear() {
  const uint8_t s = hal::interrupts_off();
  g_head = 0;
  g_count = 0;
  hal::interrupts_restore(s);
}

uint8_t count() { return g_count; }

void push(const Action& a) {
  const uint8_t s = hal::interrupts_off();
  g_ring[ring(g_head, g_count)] = a;
  g_count = uint8_t(g_count + 1);
  hal::interrupts_restore(s);
}

const Action& front() { return g_ring[g_head]; }

void replan() {
  uint8_t s = hal::interrupts_off();
  const uint8_t head = g_head, n = g_count;
  hal::interrupts_restore(s);
  articula::plan_entries([head](uint8_t k) -> const articula::PlanBlock& { return g_ring[ring(head, k)].plan; },
                                [head](uint8_t k, uint16_t e) {
                                  const uint8_t t = hal::interrupts_off();
                                  g_ring[ring(head, k)].plan.entry = e;
                                  hal::interrupts_restore(t);
                                },
                                n);
}

void pop() {
  g_head = ring(g_head, 1);
  g_count = uint8_t(g_count - 1);
}

}  // namespace queue
