// firmware/sitl/machine.h - the Nano running the firmware on a virtual clock (software in the
// loop, as ArduPilot's SITL runs its flight code): firmware/src's own controller, compiled for
// the host against hal_sitl.cpp, driven by the main loop and interrupts the Nano has.
//
// The main loop is firmware::poll(), one pass every kPollTicks of virtual time; between two
// passes every event is delivered in its time order and the clock jumps to it:
//   - the step timer's deadlines: the staged coils are written, then firmware::on_step_timer();
//   - bytes from the host on the serial line: each arrives at the receive interrupt (sitl::
//     receive) once its frame is in, 10 bits at the Nano's real 117,647 baud (kByteTicks), one
//     frame after another: '?' is answered by a status report at the next line boundary of the
//     output, '!' goes to firmware::on_realtime, every other byte to serial_read().
// Everything the firmware does is in sitl::hw(): its output, every coil write and servo pulse
// stamped with its tick, the EEPROM.
//
// A Machine is one Nano: the firmware's state (firmware/src/state.h), its hardware and this
// loop's. The calls below run the machine this thread uses now: a Machine::Use makes one the
// thread's for its scope, and a thread that never says uses a first one of the program's. So
// several machines run in one thread by turns, or each in a thread of its own.
//
//   sitl::Machine a, b;
//   { sitl::Machine::Use use(a); sitl::boot(); sitl::command("M 10 0 0"); }
//   { sitl::Machine::Use use(b); sitl::boot(); ... }
#ifndef ARTICULA_FIRMWARE_SITL_MACHINE_H
#define ARTICULA_FIRMWARE_SITL_MACHINE_H

#include <articula/config.h>
#include <articula/motion.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "../src/state.h"  // (by its path, as hal_sitl.h includes robot.h)

namespace sitl {

static const uint64_t kPollTicks = 1000;  // a main-loop pass every 0.5 ms
static const uint64_t kSecond = articula::kStepTickHz;  // ticks

// The serial line: USART0 with U2X and UBRR 16 (hal_avr.cpp) takes 8 x 17 CPU cycles a bit,
// 17 ticks of the 2 MHz step timer: 117,647 baud for the 115,200 asked. A frame (8N1) is
// 10 bits.
static const uint64_t kBitTicks = 17;
static const uint64_t kByteTicks = 10 * kBitTicks;

// Power-up: the hardware reset (the EEPROM blank, or kept as it is), then as main.cpp:
// hal::init(), firmware::setup(), hal::start(). `during_setup`: bytes that arrive after the
// receiver is on and before the firmware is set up. `config`: a robot configuration image
// (articula::kConfigImageSize bytes, as `articula configure --header` makes) put in the
// EEPROM first when it holds none (or is blank): the arm as configured for that robot.
// `arm`: instead, an arm put in use after setup as `$199=` puts one (robot::use,
// firmware::configured()): for an arm with more motors than the image carries, which this
// build (kMotors) drives.
void boot(bool blank_eeprom = true, const std::string& during_setup = "", const uint8_t* config = nullptr,
          const articula::ConfiguredArm<kMotors>* arm = nullptr);

// Bytes from the host at the receive interrupt, at the current time (all at once).
void send(const std::string& bytes);
// Bytes the host starts sending at `tick` (not before the current time): each reaches the
// receive interrupt when its frame is in, after those sent before it. Returns the tick the
// last one arrives.
uint64_t send_at(uint64_t tick, const std::string& bytes);
// Bytes sent and not yet arrived.
size_t on_the_line();

// One main-loop pass: poll(), then the clock advances kPollTicks, firing every step-timer
// deadline and delivering every byte due on the way.
void tick();
// Ticks until done() (checked after each pass) or max_ticks have passed; false on timeout.
bool run_until(const std::function<bool()>& done, uint64_t max_ticks);

// Complete lines the firmware has written since the last call (without their LF).
std::vector<std::string> take_lines();
// The first of them that is a status report ("<...>"), taken out of them; "" if none.
std::string take_report();

// Sends `line` and an LF, runs until a reply (ok / error:N) comes; returns it ("" on
// timeout). Report lines before it go to reports().
std::string command(const std::string& line, uint64_t max_ticks = 120 * kSecond);
const std::vector<std::string>& reports();

// The Nano's own loop instead of tick()'s fixed passes, in no time of its own: poll() after
// every interrupt (a step deadline, a byte's arrival, the millisecond tick), again while it
// reads or writes, as hal::idle() lets it run on while a received byte waits. Events up to
// and including `until`; the clock is then at `until`.
void run_to(uint64_t until);
// The next event after now: a step deadline, a byte's arrival or the millisecond tick.
uint64_t next_event();
// When the step timer last stopped (its last deadline): the arm came to rest there.
uint64_t stopped_at();

// How the host sends a program's lines (the prediction's SenderModel, articula predict
// --sender): each line once the arm is at rest after the reply to the one before (kAtRest;
// the whole line in at that tick), or as soon as that reply is off the wire (kStreamed: the
// reply's bytes, then the line's, at the line's rate). The first line is in at once. A line
// "!" is the realtime byte alone, sent as a line would be, and has no reply.
enum SenderKind { kAtRest, kStreamed };
struct Exchange {
  std::string line;
  uint64_t in = 0;        // its last byte at the receive interrupt
  uint64_t answered = 0;  // its reply written (in for a '!')
  std::string reply;      // "ok", "error:N"; "" for a '!' or none (the run ended first)
};
// Runs the lines from the current time (the machine booted), each as `kind` sends it, then
// until the arm is at rest; every line gets its reply within `max_ticks` or the run ends.
// `stops`: a '!' at each of these ticks after the arm's first step, whatever the lines are
// doing (a student pressing STOP; articula predict --stop-at), at the receive interrupt at once
// (after a step deadline or a line's byte at the same tick).
std::vector<Exchange> run_lines(const std::vector<std::string>& lines, SenderKind kind,
                                const std::vector<uint64_t>& stops = std::vector<uint64_t>(),
                                uint64_t max_ticks = 3600 * kSecond);
// The same, each line asked of `next` when it is to be sent (the one before answered, or the
// arm at rest after it), so it may depend on what the firmware did so far; false: no more.
std::vector<Exchange> run_lines(const std::function<bool(std::string& line)>& next, SenderKind kind,
                                const std::vector<uint64_t>& stops = std::vector<uint64_t>(),
                                uint64_t max_ticks = 3600 * kSecond);
// Every '!' of the last run_lines() (its own and the timed ones), when it reached the receive
// interrupt and when the arm was at rest after it (nothing moving, nothing queued, the stop
// done: the tick of its last step, or of the '!' itself when nothing moved).
// `replies`: the replies (ok, error:N) the run had written when it came; `actions`: the
// action log's size when it was done (hw.actions from there on began after it, even at the
// same tick, in the main loop's pass that went on to the next line).
// `queued`: hw.queued's size then (the actions queued before it that never began, it
// emptied from the queue); `planned`: the steps the arm rests at, as the firmware counts them,
// and their angles (the plan the firmware takes up again: controller.cpp rederive_planned).
struct StopEvent {
  uint64_t bang;
  uint64_t rest;
  size_t replies;
  size_t actions;
  size_t queued;
  robot::State planned;
};
const std::vector<StopEvent>& stop_events();
// The first step the motors made in the last run_lines() (0 if none), and the ticks its
// timed '!'s came at.
uint64_t first_step();
const std::vector<uint64_t>& stops_sent();

// Nothing moving, nothing queued, no stop under way.
bool at_rest();
bool run_until_at_rest(uint64_t max_ticks = 600 * kSecond);

// The motion settings the firmware's StepProfile uses now.
articula::MotionSettings motion_settings();

// Step events of one motor from the coil log (decoded by hal_sitl.cpp): times and signs.
struct Step {
  uint64_t tick;
  int8_t dir;
};
std::vector<Step> steps_of(int motor, uint64_t from_tick = 0);

// Every error the HAL saw (illegal coil patterns, jumps, unbalanced interrupts).
std::string hal_errors();

// One Nano on the virtual clock: the firmware's state, its hardware, and what this loop keeps
// (the host's line, the output read so far, run_lines()' bookkeeping).
class Machine {
 public:
  Machine() = default;
  Machine(const Machine&) = delete;
  Machine& operator=(const Machine&) = delete;

  // The machine this thread's calls run for the Use's scope (the one before it again after).
  class Use {
   public:
    explicit Use(Machine& m);
    ~Use();
    Use(const Use&) = delete;
    Use& operator=(const Use&) = delete;

   private:
    static void take(Machine* m);
    Machine* was_;
  };

  struct Arrival {  // a byte on the serial line from the host, and the tick it arrives
    uint64_t tick;
    char c;
  };
  struct Loop {
    std::string partial;  // output not yet ended by an LF
    std::vector<std::string> lines;
    std::vector<std::string> reports;
    size_t tx_seen = 0;
    size_t replies = 0;  // reply lines collect() has seen
    std::deque<Arrival> line;  // the serial line from the host, in order
    uint64_t line_free = 0;    // when the last frame sent is in
    uint64_t stopped_at = 0;   // the step timer's last deadline before it stopped
    // Timed '!'s (run_lines): ticks after the first step, pending until it is known.
    std::deque<uint64_t> stops;
    size_t coil_from = 0;  // the coil log's first write of the run
    bool first_known = false;
    uint64_t first_step = 0;
    std::vector<uint64_t> stops_sent;
    std::vector<StopEvent> stop_events;
    bool track_stops = false;  // inside run_lines()
  };

  firmware::State firmware{};  // (value-initialised: all zero, as the Nano's RAM at reset)
  Hardware hw;
  Loop loop;
};

// The machine this thread runs now.
Machine& current();

}  // namespace sitl

#endif  // ARTICULA_FIRMWARE_SITL_MACHINE_H
