// firmware/src/queue.cpp - the motion queue's ring.
#include "queue.h"

#include "hal.h"

namespace queue {

namespace {
// The queue's state (queue.h), in the firmware's (state.h).
inline Ram& q() { return ram(); }

// The ring's place k after `i` (both below kSize): a compare, not a division (kSize is no
// power of two; the AVR has no divide instruction, and pop() runs in the step interrupt).
inline uint8_t ring(uint8_t i, uint8_t k) {
  const uint8_t j = uint8_t(i + k);
  return j >= kSize ? uint8_t(j - kSize) : j;
}
}  // namespace

void clear() {
  const uint8_t s = hal::interrupts_off();
  q().head = 0;
  q().count = 0;
  hal::interrupts_restore(s);
}

uint8_t count() { return q().count; }

void push(const Action& a) {
  const uint8_t s = hal::interrupts_off();
  q().ring[ring(q().head, q().count)] = a;
  q().count = uint8_t(q().count + 1);
  hal::interrupts_restore(s);
}

const Action& front() { return q().ring[q().head]; }

void replan() {
  uint8_t s = hal::interrupts_off();
  const uint8_t head = q().head, n = q().count;
  hal::interrupts_restore(s);
  articula::plan_entries([head](uint8_t k) -> const articula::PlanBlock& { return q().ring[ring(head, k)].plan; },
                                [head](uint8_t k, uint16_t e) {
                                  const uint8_t t = hal::interrupts_off();
                                  q().ring[ring(head, k)].plan.entry = e;
                                  hal::interrupts_restore(t);
                                },
                                n);
}

void pop() {
  q().head = ring(q().head, 1);
  q().count = uint8_t(q().count - 1);
}

}  // namespace queue
