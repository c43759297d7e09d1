// firmware/src/queue.cpp - the motion queue's ring.
#include "queue.h"

#include "hal.h"

namespace queue {

namespace {
Action g_ring[kSize];
uint8_t g_head;            // the front
volatile uint8_t g_count;  // changed by both sides
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
  g_ring[(g_head + g_count) % kSize] = a;
  g_count = uint8_t(g_count + 1);
  hal::interrupts_restore(s);
}

const Action& front() { return g_ring[g_head]; }

void replan() {
  uint8_t s = hal::interrupts_off();
  const uint8_t head = g_head, n = g_count;
  hal::interrupts_restore(s);
  articula::plan_entries([head](uint8_t k) -> const articula::PlanBlock& { return g_ring[(head + k) % kSize].plan; },
                                [head](uint8_t k, uint16_t e) {
                                  const uint8_t t = hal::interrupts_off();
                                  g_ring[(head + k) % kSize].plan.entry = e;
                                  hal::interrupts_restore(t);
                                },
                                n);
}

void pop() {
  g_head = uint8_t((g_head + 1) % kSize);
  g_count = uint8_t(g_count - 1);
}

}  // namespace queue
