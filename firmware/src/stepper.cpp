// firmware/src/stepper.cpp - the step interrupt: moves, gripper pauses, homing.
#include "stepper.h"

#include "coils.h"
#include "hal.h"
#include "queue.h"
#include "settings.h"

using namespace articula;

namespace stepper {

namespace {
const uint8_t kJ = robot::kJoints;

enum Mode : uint8_t { kIdle, kMove, kPause, kWait, kSeek };

// An input's wait looks at its pin once a millisecond.
const uint32_t kWaitTicks = hal::kTickHz / 1000;

// The step interrupt's state (stepper.h), in the firmware's (state.h).
inline Ram& st() { return ram(); }

// Stops the interrupt's work: nothing runs until the main loop kicks again.
uint32_t halt() {
  st().profile = StepProfile();  // at rest: the next move starts from rest
  st().mode = kIdle;
  st().homing = 0;
  st().running = 0;
  return 0;
}

// The positions of the step staged for this deadline, now on the coils.
void book_staged() {
  const uint8_t mask = st().next_mask;
  if (mask == 0) return;
  st().next_mask = 0;
  uint8_t bit = 1;
  for (uint8_t i = 0; i < kJ; ++i, bit = uint8_t(bit << 1)) {
    if ((mask & bit) == 0) continue;
    if (st().next_negative & bit)
      --st().pos[i];
    else
      ++st().pos[i];
  }
}

// Works out the move's next step (the motors LineStepper says) and stages its coils.
void stage_move_step() {
  const uint8_t mask = st().line.next();
  const uint8_t negative = st().line.negative;
  st().next_mask = mask;
  st().next_negative = negative;
  uint8_t bit = 1;
  for (uint8_t i = 0; i < kJ; ++i, bit = uint8_t(bit << 1))
    if (mask & bit) coils::stage_step(i, (negative & bit) != 0);
}

// The level the move about to start may end at: the plan's entry of the move queued behind
// it (the front, once the move itself is popped), 0 when an action that is not a move or
// nothing is next.
uint32_t planned_exit() {
  if (queue::empty()) return 0;
  const queue::Action& next = queue::front();
  return next.kind == queue::kMove ? next.plan.entry : 0;
}

// Starts a move to absolute steps, ending at level `exit` (a stop: cut to rest at once), at
// its own cruise (PlanBlock::cruise4: a straight line's segment; 0: $0's); 0 when there is
// nothing to step. After a move that ended moving it goes on from that speed (a blended
// junction).
uint32_t begin_move(const int32_t* target, uint32_t exit, uint16_t cruise4 = 0, bool stopping = false) {
  int32_t delta[kJ];
  for (uint8_t i = 0; i < kJ; ++i) delta[i] = target[i] - st().pos[i];
  st().line.start(delta, kJ);
  if (st().line.dominant == 0) return 0;
  if (!coils::on()) coils::energise();
  const uint32_t cruise = max_of(uint32_t(cruise4) * 4, st().constants.cruise);
  if (st().profile.level() > 0)
    st().profile.follow(st().line.dominant, exit, cruise);
  else
    st().profile.start(st().line.dominant, st().constants, exit, cruise);
  if (stopping) st().profile.stop();
  st().mode = kMove;
  const uint32_t t = st().profile.next_interval();
  stage_move_step();
  return t;
}

// The next switch motor to seek, or the final move of a Home action.
uint32_t next_seek() {
  for (uint8_t i = 0; i < kJ; ++i) {
    if (st().seek_mask & (1u << i)) {
      st().seek_motor = i;
      st().seek_left = st().seek_range[i];
      st().mode = kSeek;
      return st().homing_ticks;
    }
  }
  return begin_move(st().home_target, 0);
}

// An input's wait: over when its pin reads the level (the next action starts), a fault when
// its time is out; else it looks again in a millisecond.
uint32_t wait_tick() {
  if (hal::io_read(st().wait_pin) == (st().wait_level != 0)) return 0;
  if (st().wait_left == 0) {
    st().fault = kInputTimedOut;
    return 0;
  }
  --st().wait_left;
  st().mode = kWait;
  return kWaitTicks;
}

// Starts an action already taken off the queue (so the front is the one after it).
uint32_t begin(const queue::Action& a) {
  switch (a.kind) {
    case queue::kMove:
      return begin_move(a.target, planned_exit(), a.plan.cruise4);
    case queue::kGripper:
      hal::set_servo_pulse(a.grip.pulse_us);
      st().gripper = a.grip.percent;
      // fall through - the servo's settle time is a pause, as D's is
    case queue::kDwell:
      if (a.grip.settle_ticks == 0) return 0;
      st().mode = kPause;
      return a.grip.settle_ticks;
    case queue::kOutput:
      hal::io_write(a.mask, a.grip.percent != 0);
      return 0;
    case queue::kWaitIn:
      st().wait_pin = a.mask;
      st().wait_level = a.grip.percent;
      st().wait_left = a.grip.settle_ticks;
      return wait_tick();
    case queue::kHome: {
      st().homing = 1;
      for (uint8_t i = 0; i < kJ; ++i) st().home_target[i] = a.target[i];
      st().seek_mask = a.mask;
      if (a.mask != 0 && !coils::on()) coils::energise();
      const uint32_t t = next_seek();
      if (t == 0) st().homing = 0;
      return t;
    }
  }
  return 0;
}

// Starts queued actions until one takes time; stops the timer (0) when none is left or a
// stop or fault says to start nothing more.
uint32_t next_action() {
  st().mode = kIdle;
  st().homing = 0;
  while (!st().stop && !st().fault && !queue::empty()) {
    // Popped first, so the front is the action after it; the slot is not overwritten while
    // this interrupt runs (only the main loop pushes), so no copy on the stack.
    const queue::Action& a = queue::front();
    queue::pop();
    hal::action_began(a.kind);
    const uint32_t t = begin(a);
    if (t != 0) return t;
  }
  return halt();
}

// '!' with the move ended and the arm still moving (a short move at speed): the stop goes on
// along the path, into the next queued move, until the arm is at rest.
uint32_t continue_stop() {
  while (st().profile.level() != 0 && !st().homing && !queue::empty() && queue::front().kind == queue::kMove) {
    const queue::Action& a = queue::front();  // (as in next_action)
    queue::pop();
    hal::action_began(a.kind);
    const uint32_t t = begin_move(a.target, 0, a.plan.cruise4, true);
    if (t != 0) return t;
  }
  return halt();
}

uint32_t seek_tick() {
  const uint8_t m = st().seek_motor;
  if (st().stop) {
    st().fault = kHomingFailed;
    return halt();
  }
  if (hal::endstop(m)) {
    st().pos[m] = st().home_target[m];  // the step of the motor's minimum angle
    st().seek_mask = uint8_t(st().seek_mask & ~(1u << m));
    const uint32_t t = next_seek();
    if (t != 0) return t;
    return next_action();
  }
  if (st().seek_left == 0) {
    st().fault = kHomingFailed;
    return halt();
  }
  --st().seek_left;
  // Towards the minimum angle: fewer steps unless the motor turns the other way.
  const bool negative = robot::motor(m).direction > 0;
  coils::step(m, negative);
  st().pos[m] += negative ? -1 : 1;
  return st().homing_ticks;
}

// The step of this deadline is on the coils already (staged by the previous call, written
// by the HAL before this one) and booked: what remains is the next one.
uint32_t move_tick() {
  if (st().stop) st().profile.stop();
  if (st().profile.done()) return st().stop ? continue_stop() : next_action();
  const uint32_t t = st().profile.next_interval();
  stage_move_step();
  return t;
}
}  // namespace

void setup() {
  hal::stop_step_timer();
  st().next_mask = st().next_negative = 0;
  st().stop = st().fault = 0;
  halt();  // (a setup again, as the SITL's power cycle, may come in the middle of a move)
  st().gripper = 0;
  for (uint8_t i = 0; i < kJ; ++i) {
    st().pos[i] = 0;
    const MotorSpec& m = robot::motor(i);
    // (max_steps - min_steps: the whole steps at the two limits, without limit_steps' divisions)
    const int32_t ends = quantize_within_limits(m, m.max) - quantize_within_limits(m, m.min);
    st().seek_range[i] = 2 * uint32_t(ends < 0 ? -ends : ends) + 16;
  }
  update_constants();
}

const ProfileConstants& constants() { return st().constants; }

void update_constants() {
  st().motion.tick_hz = hal::kTickHz;
  st().motion.max_rate = settings::value()[settings::kMaxRate];
  st().motion.accel = settings::value()[settings::kAccel];
  // A servo arm's servos cap both ($138, $139: the robot file's speed and accel in ticks).
  const articula::ConfiguredArm<robot::kJoints>& c = robot::config();
  if (c.rate_cap != 0 && c.rate_cap < st().motion.max_rate) st().motion.max_rate = c.rate_cap;
  if (c.accel_cap != 0 && c.accel_cap < st().motion.accel) st().motion.accel = c.accel_cap;
  profile_constants(st().constants, st().motion);  // valid for every value the settings allow
  const uint32_t rate = settings::value()[settings::kHomingRate];
  st().homing_ticks = (hal::kTickHz + rate / 2) / rate;
}

const MotionSettings& motion_settings() { return st().motion; }

void kick() {
  if (st().running || st().stop || st().fault || queue::empty()) return;
  // Nothing runs, so the step timer is stopped and the step interrupt touches none of this
  // state: the action is set up with interrupts enabled (a move's set-up takes ~50 us, which
  // the servo's pulse edges and the serial interrupts do not wait for). Running from here
  // on, for the status report. A '!' meanwhile is seen by next_action() or at the first
  // deadline.
  st().running = 1;
  const uint32_t t = next_action();
  if (t != 0) hal::start_step_timer(t);  // its own short critical section
}

bool busy() { return st().running != 0; }

void raise_exit() {
  const uint8_t s = hal::interrupts_off();
  if (st().mode == kMove && !st().homing && !st().stop) st().profile.raise_exit(planned_exit());
  hal::interrupts_restore(s);
}
bool homing() { return st().homing != 0; }

void read_positions(int32_t* steps) {
  const uint8_t s = hal::interrupts_off();
  for (uint8_t i = 0; i < kJ; ++i) steps[i] = st().pos[i];
  hal::interrupts_restore(s);
}

void set_positions(const int32_t* steps) {
  const uint8_t s = hal::interrupts_off();
  for (uint8_t i = 0; i < kJ; ++i) st().pos[i] = steps[i];
  hal::interrupts_restore(s);
}

void request_stop() { st().stop = 1; }
bool stop_requested() { return st().stop != 0; }
void clear_stop() { st().stop = 0; }

void cut_pause() {
  const uint8_t s = hal::interrupts_off();
  if (st().mode == kPause || st().mode == kWait) {
    hal::stop_step_timer();
    halt();
  }
  hal::interrupts_restore(s);
}

uint8_t take_fault() {
  const uint8_t f = st().fault;
  st().fault = kNoFault;
  return f;
}

uint8_t gripper_percent() { return st().gripper; }

uint32_t on_timer() {
  book_staged();
  switch (st().mode) {
    case kMove:
      return move_tick();
    case kSeek:
      return seek_tick();
    case kPause:
      return next_action();
    case kWait: {
      const uint32_t t = wait_tick();
      return t != 0 ? t : next_action();
    }
    default:
      return halt();
  }
}

}  // namespace stepper
