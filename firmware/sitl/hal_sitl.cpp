// firmware/sitl/hal_sitl.cpp - hal.h on the host, on the virtual clock (hal_sitl.h).
#include "hal_sitl.h"

#include <cstdlib>
#include <cstring>

#include <articula/protocol.h>

#include "firmware.h"
#include "hal.h"
#include "queue.h"
#include "settings.h"
#include "stepper.h"

namespace sitl {

namespace {
// The Nano's report buffer: the most motors it drives.
const uint16_t kReportSize = articula::status_report_size(robot::kJoints);

void build_report_if_due();

// The transmitter (an instant one): the report's bytes when report.h says they go, at a line
// boundary; a '?' that came while it went out is built once its LF has gone.
void flush_report() {
  sitl::Hardware& hw = sitl::hw();
  report::Schedule& r = hw.report_schedule;
  while (!hw.report.empty() && r.report_next(hw.tx_line_start, true)) {
    const char c = hw.report.front();
    hw.report.erase(0, 1);
    hw.tx += c;
    if (r.on_report_byte(c == '\n')) build_report_if_due();
  }
}

// The Nano's build_report_if_due() and build_report(), by report.h's rules.
void build_report_if_due() {
  sitl::Hardware& hw = sitl::hw();
  report::Schedule& r = hw.report_schedule;
  if (!r.due(hw.started, hw.in_step_timer)) return;
  do {
    r.begin_build();
    char buf[kReportSize];
    const uint8_t n = firmware::status_line(buf, uint8_t(sizeof buf));
    r.end_build();
    ++hw.reports_built;
    if (n == 0 || n > sizeof buf || buf[n - 1] != '\n') {
      hw.errors.push_back("status_line wrote no report line");
      return;
    }
    hw.report.assign(buf, n);
    flush_report();
  } while (r.build_again());
}

// An interrupt may come here: the firmware is in a HAL call with interrupts enabled.
__attribute__((noinline)) void call_interrupt_point() {
  const std::function<void()> f = hw().interrupt_point;  // it may replace itself
  f();
}

inline void interrupt_point() {
  sitl::Hardware& hw = sitl::hw();
  if (!hw.interrupt_point || hw.interrupts_off_depth != 0 || hw.in_step_timer || hw.report_schedule.building) return;
  call_interrupt_point();
}
}  // namespace

void receive(char c) {
  sitl::Hardware& hw = sitl::hw();
  const articula::RealtimeCommand r = articula::realtime_command(c);
  if (r == articula::kRealtimeStatus) {
    // A report waiting for a line boundary, or being built, answers this one too.
    hw.report_schedule.on_request(!hw.report.empty());
    build_report_if_due();
  } else if (r == articula::kRealtimeStop) {
    if (hw.started)
      firmware::on_realtime(c);
    else
      hw.stop_early = true;
  } else {
    hw.rx.push_back(c);
  }
}

namespace {
// A STEP/DIR driver's inputs but STEP, as the coil log writes them.
uint8_t driver_inputs(uint8_t motor) {
  sitl::Hardware& hw = sitl::hw();
  return uint8_t((hw.drivers_enabled ? kEnabled : 0) | (hw.dir[motor] ? kDirHigh : 0));
}

// A STEP pulse of `motor` now, as its driver takes it.
void step_pulse(uint8_t motor, bool staged) {
  sitl::Hardware& hw = sitl::hw();
  CoilWrite w{hw.now, motor, uint8_t(kStepPulse | driver_inputs(motor)), 0, staged, hw.interrupts_off_depth != 0};
  if (!hw.drivers_enabled)
    hw.errors.push_back("motor " + std::to_string(motor) + ": a STEP pulse while the drivers are disabled");
  else
    w.step = hw.dir[motor] ? 1 : -1;
  hw.position[motor] += w.step;
  hw.coil_log.push_back(w);
}
}  // namespace

uint32_t step_deadline() {
  sitl::Hardware& hw = sitl::hw();
  hw.in_step_timer = true;
  for (int m = 0; m < kMotors; ++m)
    if (hw.staged_mask & (1u << m)) {
      hal::write_coils(uint8_t(m), hw.staged[m]);
      hw.coil_log.back().staged = true;
    }
  hw.staged_mask = 0;
  for (int m = 0; m < kMotors; ++m)
    if (hw.staged_pulses & (1u << m)) step_pulse(uint8_t(m), true);
  hw.staged_pulses = 0;
  const uint32_t next = firmware::on_step_timer();
  hw.in_step_timer = false;
  if (next == 0 && (hw.staged_mask != 0 || hw.staged_pulses != 0))
    hw.errors.push_back("coils staged for a deadline that never comes");
  return next;
}

void log_action(uint8_t kind) {
  sitl::Hardware& hw = sitl::hw();
  ActionEvent e = {};
  e.tick = hw.now;
  e.kind = kind;
  stepper::read_positions(e.counted);
  hw.actions.push_back(e);
}

void reset(bool blank_eeprom) {
  sitl::Hardware& hw = sitl::hw();
  uint8_t keep[sizeof hw.eeprom];
  std::memcpy(keep, hw.eeprom, sizeof keep);
  const uint32_t driven = hw.io_driven, external = hw.io_external;  // (what is wired to it stays)
  std::function<void()> sync = std::move(hw.io_sync);
  hw = Hardware();
  hw.io_driven = driven;
  hw.io_external = external;
  hw.io_sync = std::move(sync);
  if (blank_eeprom)
    std::memset(hw.eeprom, 0xFF, sizeof hw.eeprom);
  else
    std::memcpy(hw.eeprom, keep, sizeof keep);
}

}  // namespace sitl

using sitl::hw;

namespace hal {

void init() {
  // Every pin an input with its pull-up (the Nano's HAL: the free ones; the report shows those).
  hw().io_high = (uint32_t(1) << articula::kIoPins) - 1;
}

void start() {
  sitl::Hardware& hw = sitl::hw();
  hw.started = true;
  if (hw.stop_early) {
    hw.stop_early = false;
    firmware::on_realtime('!');
  }
  sitl::build_report_if_due();
}

void write_coils(uint8_t motor, uint8_t pattern) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  sitl::CoilWrite w{hw.now, motor, pattern, 0, false, hw.interrupts_off_depth != 0};
  if (motor >= sitl::kMotors || pattern > 0xF) {
    hw.errors.push_back("write_coils(" + std::to_string(motor) + ", " + std::to_string(pattern) + ")");
    hw.coil_log.push_back(w);
    return;
  }
  hw.pattern[motor] = pattern;
  // The virtual Nanos' decoder reads it (virtual-nano/coil_decoder.h), held to the motor's own
  // mode: half steps when it has two microsteps; any other count (an arm the Nano cannot take,
  // in the host's build) is driven one full-step pattern a step, as 1 is.
  vnano::CoilDecoder& d = hw.coils[motor];
  d.set_unipolar(hw.unipolar);
  const vnano::CoilChange c = d.feed(pattern);
  const int phase = vnano::phase_of(pattern, hw.unipolar);
  const bool full = hw.microsteps[motor] != 2;
  const int stride = full ? 2 : 1;  // half steps a step
  const std::string who = "motor " + std::to_string(motor) + ": ";
  if (phase == vnano::kIllegal || (full && phase >= 0 && phase % 2 == 0)) {
    hw.errors.push_back(who + "pattern " + std::to_string(pattern) + " is not in its sequence");
  } else if (c.event == vnano::CoilEvent::kFault || (c.event == vnano::CoilEvent::kStep && std::abs(c.delta_half) != stride)) {
    const int diff = (phase - vnano::phase_of(c.reference, hw.unipolar) + 8) % 8;
    hw.errors.push_back(who + "jump of " + std::to_string(diff) + " places");
  } else if (c.event == vnano::CoilEvent::kStep) {
    w.step = c.delta_half > 0 ? 1 : -1;
    hw.position[motor] += w.step;
  }
  hw.coil_log.push_back(w);
}

void set_servo_pulse(uint16_t microseconds) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  hw.servo_us = microseconds;
  hw.servo_log.push_back(sitl::ServoChange{hw.now, microseconds});
}

namespace {
// The firmware's queue holds the last `live` actions queued: the ones before them a '!'
// emptied from it (queue::clear) without beginning them.
void forget_cleared(size_t live) {
  sitl::Hardware& hw = sitl::hw();
  while (hw.in_queue.size() > live) hw.in_queue.pop_front();
}
}  // namespace

// (After queue::pop: the queue held it and the ones behind it.)
void action_began(uint8_t kind) {
  sitl::Hardware& hw = sitl::hw();
  sitl::log_action(kind);
  forget_cleared(size_t(queue::count()) + 1);
  if (hw.in_queue.empty() || hw.queued[hw.in_queue.front()].kind != kind) {
    hw.errors.push_back("an action began that was never queued");
    return;
  }
  hw.queued[hw.in_queue.front()].began = hw.actions.size() - 1;
  hw.in_queue.pop_front();
}

// (Before queue::push, and before the plan moves on to it.)
void action_queued(const queue::Action& a) {
  sitl::Hardware& hw = sitl::hw();
  forget_cleared(queue::count());
  sitl::QueuedAction q = {};
  q.tick = hw.now;
  q.kind = a.kind;
  q.began = sitl::kNever;
  const robot::State& plan = firmware::planned();
  if (a.kind == queue::kMove || a.kind == queue::kHome)
    for (int i = 0; i < sitl::kMotors; ++i) q.delta[i] = a.target[i] - plan.steps[i];
  if (a.kind == queue::kGripper) {
    q.percent = a.grip.percent;
    q.pulse_us = a.grip.pulse_us;
  }
  if (a.kind == queue::kGripper || a.kind == queue::kDwell || a.kind == queue::kWaitIn)
    q.settle_ticks = a.grip.settle_ticks;
  if (a.kind == queue::kOutput || a.kind == queue::kWaitIn) {
    q.pin = a.mask;
    q.percent = a.grip.percent;
  }
  q.max_rate = settings::value()[settings::kMaxRate];
  q.accel = settings::value()[settings::kAccel];
  q.steps = a.plan.steps;
  q.cruise4 = a.plan.cruise4;
  hw.in_queue.push_back(hw.queued.size());
  hw.queued.push_back(q);
}

void replied(uint8_t status) {
  sitl::Hardware& hw = sitl::hw();
  sitl::Reply r = {};
  r.tick = hw.now;
  r.status = status;
  r.queued = hw.queued.size();
  r.planned = firmware::planned();
  r.homed = firmware::homed();
  for (int n = 0; n < articula::kSettingCount; ++n) r.settings[n] = settings::value()[n];
  hw.replies.push_back(r);
}

bool endstop(uint8_t motor) {
  sitl::Hardware& hw = sitl::hw();
  if (motor >= sitl::kMotors || !hw.endstop_fitted[motor]) return false;
  return hw.endstop_below[motor] ? hw.position[motor] <= hw.endstop_at[motor]
                                 : hw.position[motor] >= hw.endstop_at[motor];
}

uint32_t io_levels() {
  sitl::Hardware& hw = sitl::hw();
  if (hw.io_driven && hw.io_sync) hw.io_sync();
  // An output reads its level; an input what drives it, else its pull-up (else nothing: 0).
  return (hw.io_output & hw.io_high) | (~hw.io_output & hw.io_driven & hw.io_external) |
         (~hw.io_output & ~hw.io_driven & hw.io_high);
}

void io_inputs(uint32_t pins) {
  sitl::Hardware& hw = sitl::hw();
  for (uint8_t pin = 0; pin < articula::kIoPins; ++pin) {
    const uint32_t bit = uint32_t(1) << pin;
    if (!(pins & bit)) continue;
    if (!(hw.io_high & bit)) hw.io_log.push_back({hw.now, pin, true});  // (its pull-up: high again)
    hw.io_output &= ~bit;
    hw.io_high |= bit;
  }
}

void io_write(uint8_t pin, bool high) {
  sitl::Hardware& hw = sitl::hw();
  const uint32_t bit = uint32_t(1) << pin;
  const bool was = (hw.io_high & bit) != 0;  // (what this Nano drove it to: its pull-up before)
  hw.io_output |= bit;
  hw.io_high = high ? (hw.io_high | bit) : (hw.io_high & ~bit);
  if (was != high) hw.io_log.push_back({hw.now, pin, high});
}

bool io_read(uint8_t pin) {
  const uint32_t bit = uint32_t(1) << pin;
  return (io_levels() & bit) != 0;
}

void start_step_timer(uint32_t first_ticks) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  if (first_ticks == 0) hw.errors.push_back("start_step_timer(0)");
  hw.timer_running = true;
  hw.deadline = hw.now + first_ticks;
}

void stop_step_timer() {
  sitl::Hardware& hw = sitl::hw();
  if (hw.timer_running) sitl::log_action(sitl::kTimerStopped);
  hw.timer_running = false;
  hw.staged_mask = 0;
  hw.staged_pulses = 0;
}

void stage_coils(uint8_t motor, uint8_t pattern) {
  sitl::Hardware& hw = sitl::hw();
  if (motor >= sitl::kMotors || pattern > 0xF) {
    hw.errors.push_back("stage_coils(" + std::to_string(motor) + ", " + std::to_string(pattern) + ")");
    return;
  }
  // The Nano's HAL relies on this: the step interrupt cannot write the stage meanwhile.
  if (hw.timer_running && !hw.in_step_timer) hw.errors.push_back("stage_coils outside the step timer's call");
  hw.staged[motor] = pattern;
  hw.staged_mask = uint8_t(hw.staged_mask | (1u << motor));
}

void stage_pulse(uint8_t motor, bool negative) {
  sitl::Hardware& hw = sitl::hw();
  if (motor >= sitl::kMotors) {
    hw.errors.push_back("stage_pulse(" + std::to_string(motor) + ")");
    return;
  }
  if (hw.timer_running && !hw.in_step_timer) hw.errors.push_back("stage_pulse outside the step timer's call");
  hw.dir[motor] = !negative;
  if (hw.drivers_enabled) hw.pattern[motor] = sitl::driver_inputs(motor);
  hw.staged_pulses = uint8_t(hw.staged_pulses | (1u << motor));
}

void pulse_step(uint8_t motor, bool negative) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  if (motor >= sitl::kMotors) {
    hw.errors.push_back("pulse_step(" + std::to_string(motor) + ")");
    return;
  }
  hw.dir[motor] = !negative;
  if (hw.drivers_enabled) hw.pattern[motor] = sitl::driver_inputs(motor);
  sitl::step_pulse(motor, false);
}

// Servo arms: the SITL takes a servo's steps as STEP pulses (one tick each), as the Nano's servo
// build does; where its pulse starts is the configuration's, so the machine only checks the motor.
void attach_servo(uint8_t motor, uint8_t pin, uint16_t ticks) {
  sitl::interrupt_point();
  if (motor >= sitl::kMotors || pin >= 20 || ticks == 0)
    hw().errors.push_back("attach_servo(" + std::to_string(motor) + ", " + std::to_string(pin) + ", " +
                        std::to_string(ticks) + ")");
}

void enable_drivers(bool on) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  hw.drivers_enabled = on;
  for (int m = 0; m < sitl::kMotors; ++m) {
    hw.pattern[m] = sitl::driver_inputs(uint8_t(m)) & (on ? 0xFF : 0);
    hw.coil_log.push_back(sitl::CoilWrite{hw.now, uint8_t(m), hw.pattern[m], 0, false, hw.interrupts_off_depth != 0});
  }
}

bool step_timer_running() { return hw().timer_running; }

uint32_t millis() {
  sitl::interrupt_point();
  return uint32_t(hw().now / (kTickHz / 1000));
}

int16_t serial_read() {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  if (hw.rx.empty()) return -1;
  const char c = hw.rx.front();
  hw.rx.pop_front();
  hw.last_read = uint8_t(c);
  return int16_t(uint8_t(c));
}

void serial_write(char c) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  // The Nano's HAL waits for its transmit interrupt when the buffer is full: the main loop's
  // only, with interrupts enabled.
  if (hw.interrupts_off_depth != 0 || hw.in_step_timer || hw.report_schedule.building)
    hw.errors.push_back("serial_write outside the main loop");
  ++hw.serial_writes;
  hw.tx.push_back(c);
  hw.tx_line_start = c == '\n';
  sitl::flush_report();
}

void flash_read(void* data, const void* flash, uint16_t size) { std::memcpy(data, flash, size); }

void eeprom_read(uint16_t address, void* data, uint16_t size) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  if (address + size > sizeof hw.eeprom) {
    hw.errors.push_back("eeprom_read beyond the EEPROM");
    return;
  }
  std::memcpy(data, hw.eeprom + address, size);
}

void eeprom_write(uint16_t address, const void* data, uint16_t size) {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  if (address + size > sizeof hw.eeprom) {
    hw.errors.push_back("eeprom_write beyond the EEPROM");
    return;
  }
  const uint8_t* p = static_cast<const uint8_t*>(data);
  for (uint16_t i = 0; i < size; ++i) {
    if (hw.eeprom[address + i] != p[i]) ++hw.eeprom_bytes_written;
    hw.eeprom[address + i] = p[i];
  }
}

// The harness runs the loop and advances the time itself: nothing to sleep through.
void idle() {}

uint8_t interrupts_off() {
  sitl::Hardware& hw = sitl::hw();
  sitl::interrupt_point();
  const uint8_t was_on = hw.interrupts_off_depth == 0;
  ++hw.interrupts_off_depth;
  return was_on;
}

void interrupts_restore(uint8_t state) {
  sitl::Hardware& hw = sitl::hw();
  --hw.interrupts_off_depth;
  if (state && hw.interrupts_off_depth != 0) hw.errors.push_back("unbalanced interrupts_off/restore");
}

}  // namespace hal
