// firmware/src/queue.h - the motion queue: actions accepted (answered ok) and not yet
// started, in a ring. The main loop pushes, the step interrupt takes from the front; both
// sides touch the indices with interrupts off.
#ifndef ARTICULA_FIRMWARE_QUEUE_H
#define ARTICULA_FIRMWARE_QUEUE_H

#include <stdint.h>

#include <articula/planner.h>

#include "robot.h"
#include "ram.h"

namespace queue {

// What the status report's Q counts down from (articula/planner.h: as many as the RAM
// allows). The planner looks this far ahead; docs/protocol.md says how long a move must be
// for a speed to hold.
static const uint8_t kSize = articula::kQueueSize;

enum Kind : uint8_t {
  kMove,     // every motor to target[] (absolute steps), along a line, one StepProfile
  kGripper,  // a servo pulse width, then a pause for the servo to get there
  kHome,     // seek the switches of `mask`, then move to target[] (the switch motors'
             // targets are the steps their switch stands for)
  kDwell,    // a pause of grip.settle_ticks (D), nothing else
  kOutput,   // header pin `mask` to level grip.percent (O), in no time
  kWaitIn,   // until header pin `mask` reads grip.percent, for at most grip.settle_ticks
             // milliseconds (W); past that, the queue is dropped (stepper::take_fault)
};

struct Gripper {
  uint16_t pulse_us;      // servo pulse, microseconds
  uint8_t percent;        // aperture for status reports, whole percent
  uint32_t settle_ticks;  // pause after it, step-timer ticks
};

// 8 + 4 * joints bytes on the Nano (20 for three motors).
struct Action {
  uint8_t kind;
  uint8_t mask;  // kHome: motors with a switch
  union {
    int32_t target[robot::kJoints];
    Gripper grip;
  };
  articula::PlanBlock plan;  // a kMove's steps and levels; steps 0 for the others
};

// The ring (state.h holds it; only queue.cpp touches it).
struct Ram {
  Action ring[kSize];
  uint8_t head;            // the front
  volatile uint8_t count;  // changed by both sides
};
ARTICULA_FIRMWARE_RAM(Ram, ram)


void clear();
uint8_t count();
inline bool empty() { return count() == 0; }
inline bool full() { return count() == kSize; }
inline uint8_t free_slots() { return uint8_t(kSize - count()); }

// The main loop: adds at the back (the caller checked !full()).
void push(const Action& a);

// The step interrupt (or the main loop with interrupts off): the front action, then pop().
const Action& front();
void pop();

// The planner's reverse pass (articula/planner.h) over the queued actions. The step
// interrupt may take the front meanwhile: the pass works on the ring as it was, and each
// entry is stored with interrupts off.
void replan();

}  // namespace queue

#endif  // ARTICULA_FIRMWARE_QUEUE_H
