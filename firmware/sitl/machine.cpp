// firmware/sitl/machine.cpp - the Nano's main loop and interrupts on the virtual clock.
#include "machine.h"

#include <articula/config.h>
#include <articula/protocol.h>

#include <algorithm>
#include <cstring>
#include <deque>

#include "firmware.h"
#include "hal.h"
#include "queue.h"
#include "robot.h"
#include "stepper.h"

namespace sitl {

// The machine this thread runs: the first one until a Use says otherwise (threads that never
// say share it: a program that needs one firmware needs no machine object).
namespace {
Machine g_first;
ARTICULA_FIRMWARE_THREAD Machine* g_machine = &g_first;
}  // namespace
ARTICULA_FIRMWARE_THREAD Hardware* g_hw = &g_first.hw;

}  // namespace sitl

// The firmware's parts (firmware/src/ram.h): the first machine's until a Use says otherwise.
#define ARTICULA_FIRMWARE_POINTER(type, member, object) ARTICULA_FIRMWARE_THREAD type* object = &sitl::g_first.firmware.member;
ARTICULA_FIRMWARE_PARTS(ARTICULA_FIRMWARE_POINTER)
#undef ARTICULA_FIRMWARE_POINTER

namespace sitl {

Machine::Use::Use(Machine& m) : was_(g_machine) { take(&m); }
Machine::Use::~Use() { take(was_); }
void Machine::Use::take(Machine* m) {
  g_machine = m;
  g_hw = &m->hw;
#define ARTICULA_FIRMWARE_TAKE(type, member, object) object = &m->firmware.member;
  ARTICULA_FIRMWARE_PARTS(ARTICULA_FIRMWARE_TAKE)
#undef ARTICULA_FIRMWARE_TAKE
}

Machine& current() { return *g_machine; }

namespace {
inline Machine::Loop& lp() { return g_machine->loop; }

// run_lines()' '!'s; kPending: not at rest yet.
const uint64_t kPending = ~uint64_t(0);

bool is_reply(const std::string& s) { return s == "ok" || s.rfind("error:", 0) == 0; }
void collect();

void bang_arrives() {
  if (!lp().track_stops) return;
  collect();
  lp().stop_events.push_back(StopEvent{sitl::hw().now, kPending, lp().replies, 0, 0, robot::State()});
}

// The first step of the run, once the coil log has one.
void find_first_step() {
  const std::vector<CoilWrite>& log = sitl::hw().coil_log;
  for (; !lp().first_known && lp().coil_from < log.size(); ++lp().coil_from)
    if (log[lp().coil_from].step != 0) {
      lp().first_known = true;
      lp().first_step = log[lp().coil_from].tick;
    }
}

// firmware::poll(). An action it began that takes no time (a Home with nothing to do, a
// gripper action without a settle pause), with nothing queued after it, leaves the step timer
// unstarted: the action log gets its end here, as a timer stop.
void poll() {
  Hardware& hw = sitl::hw();
  const bool stopping = stepper::stop_requested();
  const size_t actions = hw.actions.size(), queued = hw.queued.size();
  firmware::poll();
  if (!hw.timer_running && !hw.actions.empty() && hw.actions.back().kind != kTimerStopped)
    log_action(kTimerStopped);
  // A stop is done when the main loop has emptied the queue at rest (controller.cpp
  // service_stop), in the pass that may go on to read the next line.
  if (stopping && !stepper::stop_requested())
    for (size_t i = lp().stop_events.size(); i > 0 && lp().stop_events[i - 1].rest == kPending; --i) {
      lp().stop_events[i - 1].rest = hw.now;
      lp().stop_events[i - 1].actions = actions;
      lp().stop_events[i - 1].queued = queued;
      // (Where the arm rests, as the firmware counts it: the pass may have gone on to plan
      // the next line's move already.)
      robot::State& at = lp().stop_events[i - 1].planned;
      stepper::read_positions(at.steps);
      for (uint8_t m = 0; m < robot::kJoints; ++m)
        at.commanded[m] = m < robot::count() ? articula::steps_to_millideg(robot::motor(m), at.steps[m]) : 0;
    }
}

// The step deadline due now: the staged coils, the firmware's step, the next deadline.
void fire_deadline() {
  Hardware& hw = sitl::hw();
  hw.now = hw.deadline;
  const uint32_t next = sitl::step_deadline();
  if (next == 0) {
    hw.timer_running = false;
    log_action(kTimerStopped);
    lp().stopped_at = hw.now;
  } else {
    hw.deadline += next;
  }
}

// The byte due now at the receive interrupt.
void deliver_byte() {
  sitl::hw().now = lp().line.front().tick;
  const char c = lp().line.front().c;
  lp().line.pop_front();
  if (c == '!') bang_arrives();
  sitl::receive(c);
}

void collect() {
  const std::string& tx = sitl::hw().tx;
  for (; lp().tx_seen < tx.size(); ++lp().tx_seen) {
    const char c = tx[lp().tx_seen];
    if (c == '\n') {
      lp().replies += is_reply(lp().partial);
      lp().lines.push_back(lp().partial);
      lp().partial.clear();
    } else {
      lp().partial.push_back(c);
    }
  }
}

}  // namespace

void boot(bool blank_eeprom, const std::string& during_setup, const uint8_t* config,
          const articula::ConfiguredArm<kMotors>* arm) {
  sitl::reset(blank_eeprom);
  if (config != nullptr) {
    // The arm as `articula configure ROBOT` would have left it in EEPROM.
    if (blank_eeprom || sitl::hw().eeprom[robot::kEepromAddress] != robot::kEepromVersion) robot::store(config);
  }
  lp() = Machine::Loop();
  current().firmware = firmware::State();  // the RAM as at a reset: all zero, as the Nano's C start-up leaves it
  hal::init();  // as main.cpp
  for (char c : during_setup) sitl::receive(c);
  firmware::setup();
  if (arm != nullptr) {
    robot::use(*arm, 0);
    firmware::configured();
  }
  for (int i = 0; i < robot::kJoints; ++i) sitl::hw().microsteps[i] = robot::actuation().motors[i].microsteps;
  sitl::hw().unipolar = robot::config().drive == articula::kDriveUln2003;  // the rig's motors, as the arm's
  hal::start();
}

void send(const std::string& bytes) {
  for (char c : bytes) sitl::receive(c);
}

uint64_t send_at(uint64_t tick, const std::string& bytes) {
  uint64_t t = tick < sitl::hw().now ? sitl::hw().now : tick;
  if (t < lp().line_free) t = lp().line_free;
  for (char c : bytes) {
    t += kByteTicks;
    lp().line.push_back(Machine::Arrival{t, c});
  }
  lp().line_free = t;
  return t;
}

size_t on_the_line() { return lp().line.size(); }

void tick() {
  Hardware& hw = sitl::hw();
  poll();
  const uint64_t end = hw.now + kPollTicks;
  for (;;) {
    // The next event: a step deadline or a byte's arrival (a deadline first at the same tick:
    // the step timer's interrupt has the higher priority on the ATmega328P).
    const bool step = hw.timer_running && hw.deadline <= end;
    const bool byte = !lp().line.empty() && lp().line.front().tick <= end;
    if (!step && !byte) break;
    if (step && (!byte || hw.deadline <= lp().line.front().tick))
      fire_deadline();
    else
      deliver_byte();
  }
  hw.now = end;
  collect();
}

namespace {
const uint64_t kMilliTicks = kSecond / 1000;

// poll() as the Nano's loop runs it after an interrupt: again while it makes progress (reads
// a byte, writes one), as hal::idle() does not sleep while a received byte waits.
void poll_until_idle() {
  Hardware& hw = sitl::hw();
  for (int pass = 0; pass < 64; ++pass) {
    const size_t rx = hw.rx.size(), tx = hw.tx.size();
    const bool running = hw.timer_running;
    poll();
    if (hw.rx.size() == rx && hw.tx.size() == tx && hw.timer_running == running) break;
  }
}
}  // namespace

uint64_t next_event() {
  const Hardware& hw = sitl::hw();
  // The millisecond tick wakes the Nano's loop for what it times by millis(): the coils'
  // release $2 ms after the arm came to rest. While the arm moves, a pass at it finds nothing
  // new (a byte, a step, the stop's end wake the loop themselves, and the loop reads the clock
  // only at rest): it is left out then, a third of the machine's time.
  uint64_t t = ~uint64_t(0);
  if (!hw.timer_running || at_rest()) t = (hw.now / kMilliTicks + 1) * kMilliTicks;
  if (hw.timer_running && hw.deadline < t) t = hw.deadline;
  if (!lp().line.empty() && lp().line.front().tick < t) t = lp().line.front().tick;
  if (lp().first_known && !lp().stops.empty() && lp().first_step + lp().stops.front() < t) t = lp().first_step + lp().stops.front();
  return t < hw.now ? hw.now : t;
}

uint64_t first_step() { return lp().first_known ? lp().first_step : 0; }
const std::vector<uint64_t>& stops_sent() { return lp().stops_sent; }
const std::vector<StopEvent>& stop_events() { return lp().stop_events; }

namespace {
// The next event delivered (the clock at it), then the main loop's passes.
void step_event() {
  Hardware& hw = sitl::hw();
  const uint64_t t = next_event();
  // At a tie: the step timer's interrupt first (it has the higher priority), then a line's
  // byte, then a timed '!'.
  if (hw.timer_running && hw.deadline == t) {
    fire_deadline();
  } else if (!lp().line.empty() && lp().line.front().tick == t) {
    deliver_byte();
  } else if (lp().first_known && !lp().stops.empty() && lp().first_step + lp().stops.front() == t) {
    hw.now = t;
    lp().stops.pop_front();
    lp().stops_sent.push_back(t);
    bang_arrives();
    sitl::receive('!');
  } else {
    hw.now = t;  // the millisecond tick
  }
  if (!lp().first_known) find_first_step();
  poll_until_idle();
}
}  // namespace

void run_to(uint64_t until) {
  Hardware& hw = sitl::hw();
  if (until < hw.now) until = hw.now;  // the clock never goes back
  poll_until_idle();
  while (next_event() <= until) step_event();
  hw.now = until;
  collect();
}

uint64_t stopped_at() { return lp().stopped_at; }

std::vector<Exchange> run_lines(const std::vector<std::string>& lines, SenderKind kind,
                                const std::vector<uint64_t>& stops, uint64_t max_ticks) {
  size_t i = 0;
  return run_lines(
      [&](std::string& line) {
        if (i == lines.size()) return false;
        line = lines[i++];
        return true;
      },
      kind, stops, max_ticks);
}

std::vector<Exchange> run_lines(const std::function<bool(std::string& line)>& next, SenderKind kind,
                                const std::vector<uint64_t>& stops, uint64_t max_ticks) {
  Hardware& hw = sitl::hw();
  std::vector<Exchange> out;
  lp().stops.assign(stops.begin(), stops.end());
  std::sort(lp().stops.begin(), lp().stops.end());
  lp().stops_sent.clear();
  lp().stop_events.clear();
  lp().track_stops = true;
  lp().coil_from = hw.coil_log.size();
  lp().first_known = false;
  lp().first_step = 0;
  const uint64_t end = hw.now + max_ticks;
  uint64_t wire = hw.now;  // when the sender may start the next line (the last reply is off the wire)
  bool first = true;
  poll_until_idle();
  collect();
  lp().lines.clear();
  lp().replies = 0;
  std::string line;
  while (true) {
    // When it goes: the first at once; then as the sender waits.
    if (!first && kind == kAtRest) {
      poll_until_idle();  // (a '!' at rest is dealt with at once)
      while (!at_rest() && hw.now < end) step_event();
    }
    if (!next(line)) break;
    Exchange x;
    x.line = line;
    const bool bang = line == "!";
    if (first || kind == kAtRest) {
      x.in = hw.now;
    } else {
      x.in = 0;  // set below
    }
    if (first || kind == kAtRest) {
      run_to(x.in);
      if (bang) bang_arrives();
      send(bang ? "!" : line + "\n");
    } else {  // (a '!' too: its byte on the wire after the last reply)
      x.in = send_at(wire, bang ? "!" : line + "\n");
    }
    first = false;
    if (bang) {
      run_to(x.in);
      x.answered = x.in;
      wire = x.in;
      out.push_back(x);
      continue;
    }
    // Its reply: the first reply line the firmware writes from here (reports go by).
    poll_until_idle();
    while (x.reply.empty() && hw.now < end) {
      if (lp().tx_seen != hw.tx.size()) {  // (only new output can hold it)
        collect();
        for (size_t i = 0; i < lp().lines.size(); ++i)
          if (is_reply(lp().lines[i])) {
            x.reply = lp().lines[i];
            lp().lines.erase(lp().lines.begin(), lp().lines.begin() + long(i) + 1);
            break;
          }
      }
      if (x.reply.empty()) step_event();
    }
    if (x.reply.empty()) {
      out.push_back(x);
      break;
    }
    x.answered = hw.now;
    wire = x.answered + (x.reply.size() + 1) * kByteTicks;
    out.push_back(x);
  }
  // At rest, and every timed '!' sent (one after the arm stopped still stops nothing).
  while ((!at_rest() || (lp().first_known && !lp().stops.empty())) && hw.now < end) step_event();
  collect();
  lp().stops.clear();
  lp().track_stops = false;
  return out;
}

bool run_until(const std::function<bool()>& done, uint64_t max_ticks) {
  const uint64_t end = sitl::hw().now + max_ticks;
  while (sitl::hw().now < end) {
    tick();
    if (done()) return true;
  }
  return false;
}

std::vector<std::string> take_lines() {
  collect();
  std::vector<std::string> out;
  out.swap(lp().lines);
  return out;
}

std::string take_report() {
  collect();
  for (size_t i = 0; i < lp().lines.size(); ++i) {
    if (!lp().lines[i].empty() && lp().lines[i][0] == '<') {
      const std::string l = lp().lines[i];
      lp().lines.erase(lp().lines.begin() + long(i));
      return l;
    }
  }
  return "";
}

std::string command(const std::string& line, uint64_t max_ticks) {
  lp().reports.clear();
  send(line + "\n");
  std::string reply;
  run_until(
      [&] {
        collect();
        while (!lp().lines.empty() && reply.empty()) {
          const std::string l = lp().lines.front();
          lp().lines.erase(lp().lines.begin());
          if (is_reply(l))
            reply = l;
          else
            lp().reports.push_back(l);
        }
        return !reply.empty();
      },
      max_ticks);
  return reply;
}

const std::vector<std::string>& reports() { return lp().reports; }

bool at_rest() {
  return !stepper::busy() && queue::empty() && !stepper::stop_requested() && !sitl::hw().timer_running;
}

bool run_until_at_rest(uint64_t max_ticks) {
  // Two passes at rest in a row: the queue may still hold actions a pass has not started.
  int quiet = 0;
  return run_until(
      [&] {
        quiet = at_rest() ? quiet + 1 : 0;
        return quiet >= 2;
      },
      max_ticks);
}

articula::MotionSettings motion_settings() { return stepper::motion_settings(); }

std::vector<Step> steps_of(int motor, uint64_t from_tick) {
  std::vector<Step> out;
  for (const sitl::CoilWrite& w : sitl::hw().coil_log)
    if (w.motor == motor && w.step != 0 && w.tick >= from_tick) out.push_back(Step{w.tick, w.step});
  return out;
}

std::string hal_errors() {
  std::string s;
  for (const std::string& e : sitl::hw().errors) s += e + "\n";
  return s;
}

}  // namespace sitl
