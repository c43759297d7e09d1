// virtual-nano/simavr/vnano.cpp - see vnano.h and hil/README.md.
#include "vnano.h"

#include <articula/motion.h>
#include <articula/servo.h>

#include "board.h"

#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_io.h>
#include <avr_extint.h>
#include <avr_ioport.h>
#include <avr_uart.h>
#include <sim_regbit.h>

#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <cstring>
#include <sstream>


namespace vnano {

namespace {

// ATmega328P data-space addresses (avr/iom328p.h) of the registers read from outside.
const uint16_t kTCCR1B = 0x81, kOCR1AL = 0x88, kOCR1BL = 0x8A;
const uint16_t kUCSR0A = 0xC0, kUCSR0B = 0xC1, kUCSR0C = 0xC2, kUBRR0L = 0xC4, kUBRR0H = 0xC5;
const uint8_t kU2X0 = 1, kUCSZ02 = 2, kRXEN0 = 4, kUSBS0 = 3;
const int kVecTimer1CompA = 11, kVecTimer1CompB = 12, kVecUsartRx = 18;

const char* const kVectorNames[26] = {
    "RESET",       "INT0",        "INT1",        "PCINT0",     "PCINT1",      "PCINT2",     "WDT",
    "TIMER2_COMPA", "TIMER2_COMPB", "TIMER2_OVF",  "TIMER1_CAPT", "TIMER1_COMPA", "TIMER1_COMPB", "TIMER1_OVF",
    "TIMER0_COMPA", "TIMER0_COMPB", "TIMER0_OVF",  "SPI_STC",    "USART_RX",    "USART_UDRE", "USART_TX",
    "ADC",         "EE_READY",    "ANALOG_COMP", "TWI",        "SPM_READY"};

std::string vector_name(int v) {
  if (v >= 0 && v < 26) return kVectorNames[v];
  return "VECTOR_" + std::to_string(v);
}

// The Nano's pins are the firmware's own table, firmware/src/board.h.
using board::kEndstopPins;
using board::kMotorPins;

namespace {
// The gripper's and the endstops' pins: the Nano's own, or a CNC shield's.
const board::Pin& servo_pin_of(bool cnc) { return cnc ? board::kShieldServoPin : board::kServoPin; }
const board::Pin& endstop_pin_of(bool cnc, int motor) { return cnc ? board::kShieldEndstopPins[motor] : kEndstopPins[motor]; }
}  // namespace
using board::kPortNames;

const uint8_t kPaint = 0xA5;  // stack painting pattern
const size_t kMaxFaultsListed = 100;

int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
int64_t pos_mod(int64_t a, int64_t b) { return a - floor_div(a, b) * b; }

// simavr's log, to stderr (stdout may carry the serial line), errors and warnings only.
void vnano_logger(avr_t*, const int level, const char* format, va_list ap) {
  if (level > LOG_WARNING) return;
  std::fputs("simavr: ", stderr);
  std::vfprintf(stderr, format, ap);
}

// The firmware sleeps between polls (hal::idle): simavr then jumps to its next timer event,
// and this callback, called with the cycles slept, does not pace them to the wall clock as
// simavr's default (usleep) would. simavr adds the cycles itself.
void no_sleep(avr_t*, avr_cycle_count_t) {}

using Hook = VirtualNano::Hook;

void port_cb(avr_irq_t*, uint32_t value, void* p) {
  Hook* h = static_cast<Hook*>(p);
  h->self->on_port_write(h->index, uint8_t(value));
}
void uart_out_cb(avr_irq_t*, uint32_t value, void* p) { static_cast<VirtualNano*>(p)->on_uart_output(uint8_t(value)); }
void uart_xon_cb(avr_irq_t*, uint32_t, void* p) { static_cast<VirtualNano*>(p)->on_uart_xon(); }
void uart_xoff_cb(avr_irq_t*, uint32_t value, void* p) { static_cast<VirtualNano*>(p)->on_uart_xoff(value != 0); }
void vector_pending_cb(avr_irq_t*, uint32_t value, void* p) {
  Hook* h = static_cast<Hook*>(p);
  h->self->on_vector_pending(h->index, value != 0);
}
void vector_running_cb(avr_irq_t*, uint32_t value, void* p) {
  Hook* h = static_cast<Hook*>(p);
  h->self->on_vector_running(h->index, value != 0);
}

}  // namespace

avr_cycle_count_t input_due_cb(avr_t*, avr_cycle_count_t, void* p);

VirtualNano::~VirtualNano() {
  if (avr_) avr_terminate(avr_);
}

bool VirtualNano::load(const Config& config, std::string& error) {
  config_ = config;
  paced_ = config.paced;
  stop_at_s_ = config.stop_at_s;
  if (!syms_.load(config.elf, error)) return false;
  avr_global_logger_set(vnano_logger);  // before simavr's loader talks (stdout may be the serial line)
  elf_firmware_t fw;
  std::memset(&fw, 0, sizeof fw);
  if (elf_read_firmware(config.elf.c_str(), &fw) != 0) {
    error = "simavr cannot read " + config.elf;
    return false;
  }
  if (!fw.mmcu[0]) {
    error = config.elf + " has no simavr .mmcu section (AVR_MCU): build it with firmware/avr.cmake";
    return false;
  }
  mcu_ = fw.mmcu;
  if (mcu_ != "atmega328p" && mcu_ != "atmega328") {
    error = config.elf + " is for " + mcu_ + ": the virtual Nano knows the ATmega328P's wiring only";
    return false;
  }
  avr_ = avr_make_mcu_by_name(fw.mmcu);
  if (!avr_) {
    error = "simavr does not know the MCU " + mcu_;
    return false;
  }
  avr_init(avr_);
  avr_load_firmware(avr_, &fw);
  if (!fw.frequency) avr_->frequency = 16000000;
  freq_ = avr_->frequency;
  avr_->log = LOG_WARNING;
  avr_->sleep = no_sleep;
  // INT0 (D2) and INT1 (D3): the firmware uses neither (it reads the endstops), but simavr
  // polls a low-level external interrupt every cycle while its pin is low (a coil output, a
  // closed endstop), which would wake the sleeping CPU every other cycle.
  avr_extint_set_strict_lvl_trig(avr_, 0, 0);
  avr_extint_set_strict_lvl_trig(avr_, 1, 0);

  // USART0: no usleep when the firmware polls, no echo on simavr's console.
  uint32_t flags = 0;
  avr_ioctl(avr_, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~uint32_t(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
  avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  for (avr_io_t* io = avr_->io_port; io; io = io->next) {
    if (io->kind && !std::strcmp(io->kind, "uart") && reinterpret_cast<avr_uart_t*>(io)->name == '0')
      uart_ = reinterpret_cast<avr_uart_t*>(io);
  }
  if (!uart_) {
    error = "simavr has no USART0 for " + mcu_;
    return false;
  }
  uart_in_ = avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), uart_out_cb, this);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), uart_xon_cb, this);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), uart_xoff_cb, this);

  // Ports: the whole PORTx register on each write (IOPORT_IRQ_REG_PORT), and the pin IRQs
  // that drive the endstop inputs.
  for (int p = 0; p < 3; ++p) {
    port_hooks_[p] = {this, p};
    avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_IOPORT_GETIRQ(kPortNames[p]), IOPORT_IRQ_REG_PORT), port_cb,
                            &port_hooks_[p]);
    for (int b = 0; b < 8; ++b) pin_irq_[p][b] = avr_io_getirq(avr_, AVR_IOCTL_IOPORT_GETIRQ(kPortNames[p]), b);
  }
  for (int i = 0; i < kMotors; ++i) {
    motors_[i].decoder = CoilDecoder(config.unipolar);
    motors_[i].index = i;
    motors_[i].port = kMotorPins[i].port;
    motors_[i].shift = kMotorPins[i].shift;
    if (config.cnc_shield) {
      motors_[i].step_dir = true;
      motors_[i].port = board::kShieldSocket[i].step.port;  // (DIR on the same port: pins.h asserts it)
      motors_[i].step_bit = board::kShieldSocket[i].step.bit;
      motors_[i].dir_bit = board::kShieldSocket[i].dir.bit;
    }
  }
  for (const ServoSpec& sv : config.servos) {
    if (sv.motor < 0 || sv.motor >= kMotors || sv.pin < 0 || sv.pin >= board::kHeaderPins) {
      error = "--servo: no motor " + std::to_string(sv.motor) + " (0 to 2) or no such pin";
      return false;
    }
    Motor& m = motors_[sv.motor];
    m.servo = true;
    m.servo_pin = sv.pin;
    m.port = board::kHeaderPin[sv.pin].port;
    m.servo_bit = board::kHeaderPin[sv.pin].bit;
    m.pulses = ServoDecoder(freq_ / articula::kStepTickHz, sv.zero_ticks);
  }
  for (int m : config.half_step_motors)
    if (m >= 0 && m < kMotors) motors_[m].decoder.force_half_step();
  for (const EndstopSpec& s : config.endstops) {
    if (s.motor < 0 || s.motor >= kMotors) {
      error = "--endstop: no motor " + std::to_string(s.motor) + " (0 to 2)";
      return false;
    }
    Endstop e;
    e.motor = s.motor;
    e.port = endstop_pin_of(config.cnc_shield, s.motor).port;
    e.bit = endstop_pin_of(config.cnc_shield, s.motor).bit;
    e.closes_at = s.closes_at;
    endstops_.push_back(e);
  }
  for (Endstop& e : endstops_) {
    e.pressed = 0 <= e.closes_at;  // every motor is at step 0 at power-up
    if (e.pressed) {
      e.presses = 1;
      e.first_press_cycle = 0;
    }
  }
  for (const InputSpec& in : config.inputs)
    if (in.pin < 0 || in.pin >= board::kHeaderPins || (in.level != 0 && in.level != 1) || !(in.at_s >= 0)) {
      error = "--input: no header pin " + std::to_string(in.pin) + ", or a level not 0 or 1, or a time before 0";
      return false;
    }
  // (simavr does not model the chip's pull-ups: a driven pin reads 1 before its first change,
  // as its pull-up makes it with nothing driving it)
  for (const InputSpec& in : config.inputs) driven_high_ |= driven_ |= 1u << in.pin;
  for (int p = 0; p < 3; ++p) apply_external(p);
  if (!config.inputs.empty()) {
    const uint64_t first = on_input_due();  // (those at 0 s now)
    if (first) avr_cycle_timer_register(avr_, first - avr_->cycle, input_due_cb, this);
  }

  // Every interrupt vector: its flag ("pending") and its execution ("running").
  for (int i = 0; i < avr_->interrupts.vector_count; ++i) {
    avr_int_vector_t* v = avr_->interrupts.vector[i];
    if (!v || v->vector >= 64 || vectors_[v->vector].hooked) continue;
    vectors_[v->vector].hooked = true;
    vector_ptr_[v->vector] = v;
    vector_hooks_[v->vector] = {this, v->vector};
    avr_irq_register_notify(v->irq + AVR_INT_IRQ_PENDING, vector_pending_cb, &vector_hooks_[v->vector]);
    avr_irq_register_notify(v->irq + AVR_INT_IRQ_RUNNING, vector_running_cb, &vector_hooks_[v->vector]);
  }

  // Stack painting: every byte from the end of static RAM to RAMEND.
  ramend_ = uint16_t(avr_->ramend);
  static_end_ = uint16_t(syms_.static_ram_end());
  if (static_end_ == 0 || static_end_ > ramend_) {
    error = config.elf + ": cannot tell where static RAM ends (no __heap_start, _end or .bss)";
    return false;
  }
  for (uint32_t a = static_end_; a <= ramend_; ++a) avr_->data[a] = kPaint;

  if (config_.trace) std::fprintf(config_.trace, "cycle,motor,steps,pattern,event,time_us\n");
  return true;
}

const char* VirtualNano::cpu_state() const {
  static const char* names[] = {"limbo", "stopped", "running", "sleeping", "step", "step done", "done", "crashed"};
  const int s = avr_ ? avr_->state : 0;
  return s >= 0 && s < 8 ? names[s] : "unknown";
}

uint64_t VirtualNano::cycle() const { return avr_ ? avr_->cycle : 0; }

void VirtualNano::run_until(uint64_t end) {
  if (halted_) return;
  sync_uart_frame();
  try_inject();
  while (avr_->cycle < end) {
    const uint64_t before = avr_->cycle;
    const bool asleep = avr_->state == cpu_Sleeping;
    const int state = avr_run(avr_);
    if (asleep) slept_cycles_ += avr_->cycle - before;
    const uint16_t sp = uint16_t(avr_->data[R_SPL] | (avr_->data[R_SPH] << 8));
    if (sp < min_sp_) {
      min_sp_ = sp;
      min_sp_pc_ = avr_->pc;
    }
    if (avr_->sreg[S_I]) {
      if (irq_off_) {
        end_irq_off();
        irq_off_ = false;
      }
      seen_sei_ = true;
    } else if (!irq_off_ && seen_sei_) {  // the start-up code before the first sei() is not counted
      irq_off_ = true;
      irq_off_start_ = avr_->cycle;
      irq_off_pc_ = avr_->pc;
    }
    if (state == cpu_Done || state == cpu_Crashed || state == cpu_Stopped) {
      halted_ = true;
      break;
    }
  }
}

// ---- serial ----

void VirtualNano::host_send(const char* data, size_t n) {
  if (!paced_) {
    for (size_t i = 0; i < n; ++i) host_in_.push_back(uint8_t(data[i]));
    try_inject();
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    partial_in_.push_back(data[i]);
    if (data[i] != '\n') continue;
    // Each line held until the ones before it are answered (release_line).
    held_lines_.push_back(partial_in_);
    partial_in_.clear();
  }
  release_line();
}

// Paced: the next held line to the USART once every line released so far has its reply.
void VirtualNano::release_line() {
  while (!held_lines_.empty() && replies_sent_ >= lines_released_) {
    const std::string line = held_lines_.front();
    held_lines_.pop_front();
    // A line of realtime bytes (and blanks) only is how a stream file writes them: they go
    // out alone, without the LF (docs/protocol.md, "Realtime bytes"), and get no reply.
    // Every other line is answered (a blank one error:1, a comment ok).
    bool answered = false;
    for (char c : line)
      if (c != '?' && c != '!' && c != ' ' && c != '\t' && c != '\r' && c != '\n') answered = true;
    for (char c : line)
      if (answered || c == '?' || c == '!') host_in_.push_back(uint8_t(c));
    if (answered) ++lines_released_;
    // (an unanswered line leaves the condition true: the next one goes behind it)
  }
  try_inject();
}

namespace {
avr_cycle_count_t reply_sent_cb(avr_t*, avr_cycle_count_t, void* p) {
  static_cast<VirtualNano*>(p)->on_reply_sent();
  return 0;
}
}  // namespace

avr_cycle_count_t input_due_cb(avr_t*, avr_cycle_count_t, void* p) {
  return static_cast<VirtualNano*>(p)->on_input_due();
}

avr_cycle_count_t stop_due_cb(avr_t*, avr_cycle_count_t, void* p) {
  return static_cast<VirtualNano*>(p)->on_stop_due();
}

// When the next timed '!' goes on the wire, so that it is in at its time (one frame after it
// starts); 0 when none is left.
uint64_t VirtualNano::next_stop_cycle() const {
  if (stops_sent_ >= stop_at_s_.size()) return 0;
  const uint64_t in = first_step_cycle_ + uint64_t(std::llround(stop_at_s_[stops_sent_] * freq_));
  const uint64_t start = in > uart_->cycles_per_byte ? in - uart_->cycles_per_byte : 0;
  return std::max(start, avr_->cycle + 1);
}

void VirtualNano::schedule_stop() {
  const uint64_t at = next_stop_cycle();
  if (at != 0) avr_cycle_timer_register(avr_, at - avr_->cycle, stop_due_cb, this);
}

// (simavr: the callback's answer is the cycle it is due again, 0 for never)
uint64_t VirtualNano::on_stop_due() {
  ++stops_sent_;
  host_in_.push_front('!');  // (behind a byte already on the wire, if any)
  try_inject();
  return next_stop_cycle();
}

void VirtualNano::on_reply_sent() {
  ++replies_sent_;
  release_line();
}

bool VirtualNano::serial_idle() const { return host_in_.empty() && (uart_->input.read == uart_->input.write); }

// simavr charges 11 bit times a byte (start, 8 data, a parity bit that 8N1 does not have,
// stop). The real frame is 1 + data bits + parity + stop bits, from the firmware's own
// UCSR0A/B/C and UBRR0: 10 bit times for 8N1 (1,360 cycles at 117,647 baud with U2X0).
void VirtualNano::sync_uart_frame() {
  const uint8_t* d = avr_->data;
  if (!(d[kUCSR0B] & (1u << kRXEN0))) return;  // not set up by the firmware yet
  const uint32_t ubrr = d[kUBRR0L] | ((d[kUBRR0H] & 0x0Fu) << 8);
  const uint64_t bit = uint64_t(ubrr + 1) * ((d[kUCSR0A] & (1u << kU2X0)) ? 8 : 16);
  static const int kDataBits[8] = {5, 6, 7, 8, 8, 8, 8, 9};
  const int data_bits = kDataBits[((d[kUCSR0C] >> 1) & 3) | ((d[kUCSR0B] & (1u << kUCSZ02)) ? 4 : 0)];
  const int parity = ((d[kUCSR0C] >> 4) & 3) ? 1 : 0;
  const int stop = (d[kUCSR0C] & (1u << kUSBS0)) ? 2 : 1;
  const uint64_t frame = bit * uint64_t(1 + data_bits + parity + stop);
  if (uart_->cycles_per_byte != frame) {
    simavr_frame_cycles_ = uart_->cycles_per_byte;
    uart_->cycles_per_byte = frame;
  }
  frame_cycles_ = frame;
}

// One byte into the USART when its receive FIFO is empty (and simavr has not said XOFF):
// the byte is complete at the receiver one frame later, as on a wire, and the firmware never
// finds more than one byte waiting. Called after each run slice and from XON (the firmware
// has just read the last byte).
void VirtualNano::try_inject() {
  if (injecting_ || host_in_.empty() || xoff_ || !uart_) return;
  if (!(avr_->data[kUCSR0B] & (1u << kRXEN0))) return;  // receiver off: the byte would be lost
  if (!(uart_->input.read == uart_->input.write)) return;
  injecting_ = true;
  sync_uart_frame();
  const uint8_t b = host_in_.front();
  host_in_.pop_front();
  if (b == '?') {
    ++status_requests_;
    status_waiting_.push_back(avr_->cycle + uart_->cycles_per_byte);  // its stop bit is in
  }
  ++bytes_in_;
  rx_outstanding_ = true;
  rx_arrival_ = avr_->cycle + uart_->cycles_per_byte;
  // A line's end in the trace (motor -1, event `line`): the pins' rows before it are from before
  // the firmware had the line, whatever the host's clock said when it sent it.
  if (b == '\n') {
    if (config_.trace)
      std::fprintf(config_.trace, "%" PRIu64 ",-1,%" PRIu64 ",,line,%.4f\n", uint64_t(rx_arrival_), lines_in_,
                   us(double(rx_arrival_)));
    ++lines_in_;
  }

  avr_raise_irq(uart_in_, b);
  injecting_ = false;
}

void VirtualNano::on_uart_xon() {
  xoff_ = false;
  try_inject();
}

void VirtualNano::on_uart_xoff(bool off) { xoff_ = off; }

void VirtualNano::on_uart_output(uint8_t c) {
  const uint64_t now = avr_->cycle;
  out_.push_back(char(c));
  if (paced_) {
    line_out_.push_back(char(c));
    if (c == '\n') {
      // A reply: the host has it when its LF is off the wire, one frame from now.
      if (line_out_ == "ok\n" || line_out_.rfind("error:", 0) == 0)
        avr_cycle_timer_register(avr_, uart_->cycles_per_byte, reply_sent_cb, this);
      line_out_.clear();
    }
  }
  ++bytes_out_;
  last_activity_ = now;
  if (line_start_ && c == '<' && !status_waiting_.empty()) {
    // A status report starts: it answers every '?' that has arrived so far. Its latency is
    // counted from the oldest of them (what the host that sent it waited).
    status_t0_ = status_waiting_.front();
    status_answered_together_ += status_waiting_.size() - 1;
    status_waiting_.clear();
    if (now >= status_t0_) status_first_us_.add(us(double(now - status_t0_)));
    if (status_list_.size() < 200) status_list_.push_back({status_t0_, now, 0});
    in_status_line_ = true;
    ++status_replies_;
  }
  if (c == '\n' && in_status_line_) {
    // The LF is complete on the wire one frame after it enters UDR0.
    const uint64_t done = now + uart_->cycles_per_byte;
    if (done >= status_t0_) status_end_us_.add(us(double(done - status_t0_)));
    if (!status_list_.empty() && status_list_.back().request == status_t0_) status_list_.back().end = done;
    in_status_line_ = false;
  }
  line_start_ = c == '\n';
}

// ---- pins ----


// A motor's driver inputs for the trace: its coils' IN1..IN4, or STEP, DIR and EN as "S1D0E1".
std::string VirtualNano::inputs_string(const Motor& m) const {
  if (m.servo) {  // the pulse's width, us
    char b[32];
    std::snprintf(b, sizeof b, "%.1fus", double(m.pulses.position() + m.pulses.zero_ticks()) / 2.0);
    return b;
  }
  if (!m.step_dir) return pattern_string(m.decoder.pattern());
  const bool en = !(port_value_[board::kShieldEnable.port] & (1u << board::kShieldEnable.bit));
  return std::string("S") + (m.driver.step_high() ? "1" : "0") + "D" + (m.driver.dir_high() ? "1" : "0") + "E" +
         (en ? "1" : "0");
}

void VirtualNano::on_port_write(int port, uint8_t value) {
  const uint64_t now = avr_->cycle;
  const uint8_t old = port_value_[port];
  port_value_[port] = value;
  for (int pin : config_.outputs)
    if (board::kHeaderPin[pin].port == port) {
      const int level = (value >> board::kHeaderPin[pin].bit) & 1;
      if (level != output_level_[pin]) {
        output_level_[pin] = level;
        output_changes_.push_back({pin, level, now});
      }
    }
  const bool enabled = !(port_value_[board::kShieldEnable.port] & (1u << board::kShieldEnable.bit));  // EN low
  for (Motor& m : motors_) {
    if (m.servo) {
      if (m.port != port || !((old ^ value) & (1u << m.servo_bit))) continue;
      const ServoChange c = m.pulses.feed((value >> m.servo_bit) & 1, now);
      if (c.pulse) m.width_us.add(us(double(c.cycles)));
      if (c.delta != 0) {
        last_activity_ = now;
        CoilChange cc;
        cc.event = CoilEvent::kStep;
        cc.delta_half = int(2 * c.delta);
        step_event(m, cc, 0);
      }
      continue;
    }
    if (m.step_dir) {
      if (m.port != port && !(port == board::kShieldEnable.port)) continue;
      const uint8_t v = port_value_[m.port];
      const StepDirChange c = m.driver.feed((v >> m.step_bit) & 1, (v >> m.dir_bit) & 1, enabled, now);
      if (c.delta != 0 || c.ignored) {
        last_activity_ = now;
        CoilChange cc;
        cc.event = c.ignored ? CoilEvent::kFault : CoilEvent::kStep;
        cc.fault = c.ignored ? FaultKind::kIllegalPattern : FaultKind::kNone;
        cc.delta_half = 2 * c.delta;
        step_event(m, cc, uint8_t(v));
      }
      continue;
    }
    if (m.port != port) continue;
    const uint8_t pattern = uint8_t((value >> m.shift) & 0xF);
    if (pattern == ((old >> m.shift) & 0xF) && pattern == m.decoder.pattern()) continue;
    const CoilChange c = m.decoder.feed(pattern);
    if (c.event == CoilEvent::kNone) continue;
    last_activity_ = now;
    step_event(m, c, pattern);
  }
  const board::Pin& servo = servo_pin_of(config_.cnc_shield);
  if (port == servo.port && ((old ^ value) & (1u << servo.bit))) {
    if (value & (1u << servo.bit)) {
      if (have_rise_) servo_period_us_.add(us(double(now - last_rise_)));
      last_rise_ = servo_rise_ = now;
      have_rise_ = servo_high_ = true;
    } else if (servo_high_) {
      const uint64_t w = now - servo_rise_;
      servo_width_us_.add(us(double(w)));
      ++servo_widths_[w];
      last_width_us_ = us(double(w));
      servo_high_ = false;
    }
    // Not "activity": the servo pulses forever once set.
  }
  if (port == board::kLedPin.port && ((old ^ value) & (1u << board::kLedPin.bit))) {
    led_ = (value & (1u << board::kLedPin.bit)) != 0;
    if (led_) ++epoch_;
    last_activity_ = now;
  }
}

void VirtualNano::step_event(Motor& m, const CoilChange& c, uint8_t pattern) {
  const uint64_t now = avr_->cycle;
  switch (c.event) {
    case CoilEvent::kReleased:
      ++m.releases;
      m.have_last_delay = false;
      trace_row(m, "released");
      return;
    case CoilEvent::kEnergised:
      ++m.energisations;
      trace_row(m, "energised");
      return;
    case CoilEvent::kFault:
      ++m.faults;
      m.have_last_delay = false;
      if (m.fault_list.size() < kMaxFaultsListed) m.fault_list.push_back({now, c.from, pattern, c.reference, c.fault});
      trace_row(m, c.fault == FaultKind::kIllegalPattern ? "fault-illegal" : "fault-skipped");
      return;
    case CoilEvent::kStep:
      break;
    default:
      return;
  }
  ++m.step_events;
  (c.delta_half > 0 ? m.forward : m.backward) += 1;
  (c.delta_half == 2 || c.delta_half == -2 ? m.full_steps : m.half_steps) += 1;
  const bool same_run = m.have_last && m.last_epoch == epoch_ && led_;
  if (same_run) m.interval_us.add(us(double(now - m.last_step_cycle)));
  m.have_last = true;
  m.last_step_cycle = now;
  m.last_epoch = epoch_;

  uint64_t deadline = 0;
  const bool on_deadline = in_vector(kVecTimer1CompA) && step_deadline(now, deadline);
  if (!first_step_seen_) {  // the timed stops count from the step's deadline
    first_step_seen_ = true;
    first_step_cycle_ = on_deadline ? deadline : now;
    schedule_stop();
  }
  if (on_deadline) {
    const double delay = us(double(now - deadline));
    m.delay_us.add(delay);
    if (same_run && m.have_last_delay) {
      const double e = std::fabs(delay - m.last_delay_us);
      m.interval_error_us.add(e);
      if (e > 10.0) ++m.errors_over_10us;
    }
    m.have_last_delay = true;
    m.last_delay_us = delay;
  } else {
    ++m.unattributed;
    m.have_last_delay = false;
  }

  const uint64_t w = freq_ / 100;  // 10 ms
  window_.push_back(now);
  while (!window_.empty() && window_.front() + w <= now) window_.pop_front();
  if (window_.size() > peak_window_) peak_window_ = window_.size();

  trace_row(m, c.delta_half > 0 ? "step+" : "step-");
  check_endstops(m.index);
}

void VirtualNano::trace_row(const Motor& m, const char* event) {
  if (!config_.trace) return;
  std::fprintf(config_.trace, "%" PRIu64 ",%d,%" PRId64 ",%s,%s,%.4f\n", uint64_t(avr_->cycle), m.index,
               m.steps(), inputs_string(m).c_str(), event, us(double(avr_->cycle)));
}

// The switches and the driven inputs (--input) of one port, as external levels: simavr applies them whenever it updates the
// port's pins (a PORTx write would otherwise put the pull-up's 1 back on a pressed switch).
void VirtualNano::apply_external(int port) {
  uint8_t mask = 0, value = 0;
  for (const Endstop& e : endstops_) {
    if (e.port != port) continue;
    mask = uint8_t(mask | (1u << e.bit));
    if (!e.pressed) value = uint8_t(value | (1u << e.bit));
  }
  for (int pin = 0; pin < board::kHeaderPins; ++pin) {  // (and the inputs driven from outside)
    if (!(driven_ & (1u << pin)) || board::kHeaderPin[pin].port != port) continue;
    const int bit = board::kHeaderPin[pin].bit;
    mask = uint8_t(mask | (1u << bit));
    if (driven_high_ & (1u << pin)) value = uint8_t(value | (1u << bit));
  }
  if (!mask) return;
  avr_ioport_external_t ext;
  std::memset(&ext, 0, sizeof ext);
  ext.name = uint8_t(kPortNames[port]) & 0x7F;
  ext.mask = mask;
  ext.value = value;
  avr_ioctl(avr_, AVR_IOCTL_IOPORT_SET_EXTERNAL(kPortNames[port]), &ext);
  for (const Endstop& e : endstops_)
    if (e.port == port) avr_raise_irq(pin_irq_[port][e.bit], e.pressed ? 0 : 1);
  for (int pin = 0; pin < board::kHeaderPins; ++pin)
    if ((driven_ & (1u << pin)) && board::kHeaderPin[pin].port == port)
      avr_raise_irq(pin_irq_[port][board::kHeaderPin[pin].bit], (driven_high_ >> pin) & 1);
}

uint64_t VirtualNano::input_cycle(size_t k) const {
  return uint64_t(std::llround(config_.inputs[k].at_s * freq_));
}

// Every change due now, then the cycle of the next (simavr's answer: 0 for none).
uint64_t VirtualNano::on_input_due() {
  while (inputs_applied_ < config_.inputs.size() && input_cycle(inputs_applied_) <= avr_->cycle) {
    const InputSpec& in = config_.inputs[inputs_applied_++];
    driven_ |= 1u << in.pin;
    driven_high_ = in.level ? (driven_high_ | (1u << in.pin)) : (driven_high_ & ~(1u << in.pin));
    apply_external(board::kHeaderPin[in.pin].port);
  }
  return inputs_applied_ < config_.inputs.size() ? input_cycle(inputs_applied_) : 0;
}

void VirtualNano::check_endstops(int motor) {
  for (Endstop& e : endstops_) {
    if (e.motor != motor) continue;
    const int64_t pos = motors_[motor].steps();
    const bool pressed = pos <= e.closes_at;
    if (pressed == e.pressed) continue;
    e.pressed = pressed;
    if (pressed) {
      if (e.presses++ == 0) {
        e.first_press_cycle = avr_->cycle;
        e.pressed_at_steps = pos;
      }
    }
    apply_external(e.port);
  }
}

// ---- Timer1 and the step deadlines ----

int VirtualNano::timer1_prescale() const {
  static const int kPrescale[8] = {0, 1, 8, 64, 256, 1024, 0, 0};
  return kPrescale[avr_->data[kTCCR1B] & 7];
}

// At a compare flag raise TCNT1 equals the compare register: that gives the cycle at which
// the free-running counter was 0, modulo one lap. The flag is seen at an instruction
// boundary (up to a few cycles late), so the earliest consistent observation is kept;
// observations more than two timer ticks off are outliers (a match simavr made somewhere
// else), and three outliers in a row start the calibration over.
void VirtualNano::calibrate_timer1(uint16_t ocr) {
  const int ps = timer1_prescale();
  if (!ps) return;
  const int64_t lap = int64_t(65536) * ps;
  const int64_t obs = pos_mod(int64_t(avr_->cycle) - int64_t(ps) * ocr, lap);
  if (!cal_valid_ || ps != cal_prescale_ || cal_streak_ >= 3) {
    cal_valid_ = true;
    cal_prescale_ = ps;
    cal_phase_ = obs;
    cal_streak_ = 0;
    ++cal_accepted_;
    return;
  }
  const int64_t d = pos_mod(obs - cal_phase_ + lap / 2, lap) - lap / 2;
  if (d >= -2 * ps && d <= 2 * ps) {
    if (d < 0) cal_phase_ = obs;
    ++cal_accepted_;
    cal_streak_ = 0;
  } else {
    ++cal_outliers_;
    ++cal_streak_;
  }
}

// The deadline of a step made now inside the COMPA interrupt: OCR1A still holds it (the HAL
// arms the next one after the firmware returns), so it is the last cycle at or before now
// at which TCNT1 equalled OCR1A.
bool VirtualNano::step_deadline(uint64_t now, uint64_t& deadline) const {
  const int ps = timer1_prescale();
  if (!cal_valid_ || ps != cal_prescale_) return false;
  const uint16_t ocr = uint16_t(avr_->data[kOCR1AL] | (avr_->data[kOCR1AL + 1] << 8));
  const int64_t lap = int64_t(65536) * ps;
  const int64_t base = cal_phase_ + int64_t(ps) * ocr;
  const int64_t t = base + floor_div(int64_t(now) - base, lap) * lap;
  if (t < 0 || int64_t(now) - t >= lap / 2) return false;
  deadline = uint64_t(t);
  return true;
}

bool VirtualNano::in_vector(int vector) const {
  for (const Frame& f : running_)
    if (f.vector == vector) return true;
  return false;
}

// ---- interrupts ----

// simavr raises a vector's "pending" IRQ with 1 when the flag is set, whether the interrupt
// is enabled or not, and with 0 when the flag is cleared (by the entry, or by the firmware).
// An interrupt is requested when its flag is raised while it is enabled (simavr raises the
// flag again when the enable bit is set for the UART's UDRE; a timer flag raised while masked
// is never taken by simavr). Latency counts from the first such raise: a flag raised again
// before it was served (simavr's USART re-raises RXC once a frame) does not restart it.
void VirtualNano::on_vector_pending(int vector, bool raised) {
  VectorStat& v = vectors_[vector];
  if (!raised) {
    v.pending = false;
  } else if (!v.pending && vector_ptr_[vector] &&
             avr_regbit_get(avr_, static_cast<avr_int_vector_t*>(vector_ptr_[vector])->enable)) {
    v.pending_cycle = avr_->cycle;
    v.pending = true;
  }
  if (!raised) return;
  if (vector == kVecTimer1CompA) calibrate_timer1(uint16_t(avr_->data[kOCR1AL] | (avr_->data[kOCR1AL + 1] << 8)));
  if (vector == kVecTimer1CompB) calibrate_timer1(uint16_t(avr_->data[kOCR1BL] | (avr_->data[kOCR1BL + 1] << 8)));
}

void VirtualNano::on_vector_running(int vector, bool running) {
  const uint64_t now = avr_->cycle;
  VectorStat& v = vectors_[vector];
  if (running) {
    ++v.entries;
    if (v.pending) {
      const double lat = us(double(now - v.pending_cycle));
      v.latency_us.add(lat);
      v.pending = false;
    }
    if (vector == kVecUsartRx && rx_outstanding_ && now >= rx_arrival_) {
      // From the byte's stop bit to the receive interrupt. A real USART holds two received
      // bytes: one not read within two frame times would be overwritten by a host that
      // sends back to back (this virtual wire never does: it waits for the FIFO to empty).
      rx_wait_us_.add(us(double(now - rx_arrival_)));
      if (frame_cycles_ && now - rx_arrival_ > 2 * frame_cycles_) ++rx_overrun_risk_;
      rx_outstanding_ = false;
    }
    running_.push_back({vector, now, 0});
    return;
  }
  // RETI: simavr returns from the most recent vector.
  size_t i = running_.size();
  while (i > 0 && running_[i - 1].vector != vector) --i;
  if (i == 0) {
    ++running_mismatch_;
    return;
  }
  if (i != running_.size()) ++running_mismatch_;
  const Frame f = running_[i - 1];
  running_.erase(running_.begin() + long(i - 1), running_.end());
  const uint64_t incl = now - f.start;
  v.inclusive_us.add(us(double(incl)));
  v.exclusive_us.add(us(double(incl - std::min(incl, f.nested))));
  if (!running_.empty()) running_.back().nested += incl;
}

// ---- the end ----

void VirtualNano::end_irq_off() {
  const double span = us(double(avr_->cycle - irq_off_start_));
  if (span > irq_off_max_us_) {
    irq_off_max_us_ = span;
    irq_off_max_pc_ = irq_off_pc_;
    irq_off_max_cycle_ = irq_off_start_;
  }
}

void VirtualNano::finish() {
  if (finished_ || !avr_) return;
  finished_ = true;
  if (irq_off_) end_irq_off();
  for (uint32_t a = static_end_; a <= ramend_; ++a)
    if (avr_->data[a] != kPaint) {
      lowest_touched_ = int(a);
      break;
    }
  if (config_.trace) std::fflush(config_.trace);
}

nlohmann::json VirtualNano::report() const {
  using nlohmann::json;
  json r;
  r["elf"] = config_.elf;
  r["mcu"] = mcu_;
  r["frequency_hz"] = freq_;
  r["cycles"] = cycle();
  r["slept_s"] = Stat::round3(double(slept_cycles_) / freq_);  // the firmware asleep (hal::idle)
  r["simulated_s"] = Stat::round3(double(cycle()) / freq_ * 1000.0) / 1000.0;
  r["cpu_state"] = cpu_state();

  json uart;
  uart["frame_cycles"] = frame_cycles_;
  uart["frame_us"] = Stat::round3(us(double(frame_cycles_)));
  uart["simavr_frame_cycles"] = simavr_frame_cycles_;
  uart["bytes_in"] = bytes_in_;
  uart["bytes_out"] = bytes_out_;
  uart["rx_wait_us"] = rx_wait_us_.json();
  uart["rx_overrun_risk"] = rx_overrun_risk_;
  r["uart"] = uart;

  json motors = json::array();
  double jitter = 0;
  bool have_jitter = false;
  uint64_t total_faults = 0;
  for (const Motor& m : motors_) {
    json j;
    j["motor"] = m.index;
    if (m.servo) {
      j["pins"] = std::string("signal ") + board::kHeaderPin[m.servo_pin].pin;
      j["mode"] = "servo";
      j["driver"] = "servo";
      j["steps"] = m.pulses.position();
      j["pattern"] = inputs_string(m);
      j["energised"] = true;
      j["pulses"] = m.pulses.pulses();
      j["width_us"] = m.width_us.json();
      j["period_min_us"] = Stat::round3(us(double(m.pulses.min_period_cycles())));
      j["period_max_us"] = Stat::round3(us(double(m.pulses.max_period_cycles())));
      // The most a width lay off its whole tick: the edges' jitter, us.
      j["width_off_tick_max_us"] = Stat::round3(us(double(m.pulses.max_off_cycles())));
      json offs = json::object();
      for (int off = -8; off < 8; ++off)
        if (m.pulses.off_count(off)) offs[std::to_string(off)] = m.pulses.off_count(off);
      j["width_off_tick_cycles"] = offs;  // how many widths lay that many cycles off their tick
    } else if (m.step_dir) {
      const board::Socket& s = board::kShieldSocket[m.index];
      j["pins"] = std::string("socket ") + s.axis + ": STEP " + s.step.pin + ", DIR " + s.dir.pin;
      j["mode"] = "step-dir";
      j["driver"] = "step-dir";
      j["steps"] = m.driver.steps();
      j["pattern"] = inputs_string(m);
      j["energised"] = !(port_value_[board::kShieldEnable.port] & (1u << board::kShieldEnable.bit));
      // The driver's timing as the pins kept it (drive.h: the datasheets' minimums).
      const auto cycles_us = [&](uint64_t c) { return c == StepDirDecoder::kNone ? json(nullptr) : json(Stat::round3(us(double(c)))); };
      j["pulses"] = m.driver.pulses();
      j["ignored_pulses"] = m.driver.ignored();
      j["step_high_min_us"] = cycles_us(m.driver.min_pulse_cycles());
      j["step_high_max_us"] = cycles_us(m.driver.max_pulse_cycles());
      j["dir_setup_min_us"] = cycles_us(m.driver.min_dir_setup_cycles());
    } else {
      j["pins"] = kMotorPins[m.index].pins;
      j["mode"] = m.decoder.half_step_mode() ? "half" : "full";
      j["driver"] = m.decoder.unipolar() ? "uln2003" : "l298n";
      j["steps"] = m.decoder.steps();
      j["half_steps"] = m.decoder.half_steps();
      j["pattern"] = pattern_string(m.decoder.pattern());
      j["energised"] = m.decoder.energised();
    }
    j["step_events"] = m.step_events;
    j["forward"] = m.forward;
    j["backward"] = m.backward;
    j["full_step_events"] = m.full_steps;
    j["half_step_events"] = m.half_steps;
    j["releases"] = m.releases;
    j["faults"] = m.faults;
    total_faults += m.faults;
    json fl = json::array();
    for (const Motor::Fault& f : m.fault_list)
      fl.push_back({{"cycle", f.cycle},
                    {"time_us", Stat::round3(us(double(f.cycle)))},
                    {"kind", fault_name(f.kind)},
                    {"from", pattern_string(f.from)},
                    {"to", pattern_string(f.to)},
                    {"reference", pattern_string(f.reference)}});
    j["fault_list"] = fl;
    j["interval_us"] = m.interval_us.json();
    j["max_rate_steps_per_s"] = m.interval_us.count ? Stat::round3(1e6 / m.interval_us.min) : 0.0;
    j["deadline_delay_us"] = m.delay_us.json();
    j["interval_error_us"] = m.interval_error_us.json();
    const double mj = m.interval_error_us.count ? m.interval_error_us.max : 0.0;
    j["jitter_us"] = Stat::round3(mj);
    j["interval_errors_over_10us"] = m.errors_over_10us;
    j["unattributed_steps"] = m.unattributed;
    if (m.interval_error_us.count) {
      jitter = std::max(jitter, mj);
      have_jitter = true;
    }
    motors.push_back(j);
  }
  r["motors"] = motors;
  r["faults"] = total_faults;
  r["jitter_us"] = have_jitter ? json(Stat::round3(jitter)) : json(nullptr);
  r["peak_steps_per_s_10ms"] = double(peak_window_) * 100.0;
  r["timer1_calibration"] = {{"valid", cal_valid_}, {"accepted", cal_accepted_}, {"outliers", cal_outliers_}};

  json servo;
  servo["pin"] = servo_pin_of(config_.cnc_shield).pin;
  servo["pulses"] = servo_width_us_.count;
  servo["width_us"] = servo_width_us_.json();
  servo["period_us"] = servo_period_us_.json();
  json widths = json::array();
  for (const auto& kv : servo_widths_)
    widths.push_back({{"us", Stat::round3(us(double(kv.first)))}, {"pulses", kv.second}});
  servo["widths"] = widths;
  if (servo_width_us_.count) {
    servo["last_us"] = Stat::round3(last_width_us_);
    const double angle = articula::servo_angle_deg(last_width_us_);
    servo["last_angle_deg"] = Stat::round3(angle);
    if (config_.gripper_range && config_.servo_open_deg != config_.servo_closed_deg)
      servo["last_aperture_percent"] =
          Stat::round3(articula::servo_aperture_percent(angle, config_.servo_closed_deg, config_.servo_open_deg));
  } else {
    servo["last_us"] = nullptr;
    servo["last_angle_deg"] = nullptr;
  }
  r["servo"] = servo;

  json ends = json::array();
  for (const Endstop& e : endstops_) {
    json j;
    j["motor"] = e.motor;
    j["pin"] = endstop_pin_of(config_.cnc_shield, e.motor).pin;
    j["closes_at_or_below"] = e.closes_at;
    j["pressed"] = e.pressed;
    j["presses"] = e.presses;
    if (e.presses) {
      j["first_press_us"] = Stat::round3(us(double(e.first_press_cycle)));
      j["first_press_steps"] = e.pressed_at_steps;
    }
    ends.push_back(j);
  }
  r["endstops"] = ends;
  json outs = json::array();
  for (int pin : config_.outputs) {
    json changes = json::array();
    for (const OutputChange& o : output_changes_)
      if (o.pin == pin) changes.push_back({{"level", o.level}, {"t_s", double(o.cycle) / freq_}});
    outs.push_back({{"pin", board::kHeaderPin[pin].pin}, {"changes", changes}});
  }
  json ins = json::array();
  for (const InputSpec& in : config_.inputs)
    ins.push_back({{"pin", board::kHeaderPin[in.pin].pin}, {"level", in.level}, {"at_s", in.at_s}});
  r["io"] = {{"outputs", outs}, {"inputs", ins}};

  json st;
  st["requests"] = status_requests_;
  st["replies"] = status_replies_;
  st["first_byte_us"] = status_first_us_.json();
  st["line_end_us"] = status_end_us_.json();
  st["answered_together"] = status_answered_together_;
  st["waiting"] = status_waiting_.size();
  json sl = json::array();
  for (const StatusReply& x : status_list_)
    sl.push_back({{"request_us", Stat::round3(us(double(x.request)))},
                  {"first_byte_us", Stat::round3(us(double(x.first - x.request)))},
                  {"line_end_us", x.end ? json(Stat::round3(us(double(x.end - x.request)))) : json(nullptr)}});
  st["replies_list"] = sl;
  r["status"] = st;

  json ints = json::array();
  double longest = 0, longest_excl = 0;
  std::string longest_name, longest_excl_name;
  for (int i = 0; i < 64; ++i) {
    const VectorStat& v = vectors_[i];
    if (!v.entries) continue;
    json j;
    j["vector"] = i;
    j["name"] = vector_name(i);
    j["entries"] = v.entries;
    j["entry_latency_us"] = v.latency_us.json();
    j["duration_us"] = v.inclusive_us.json();
    j["exclusive_us"] = v.exclusive_us.json();
    ints.push_back(j);
    if (v.inclusive_us.count && v.inclusive_us.max > longest) {
      longest = v.inclusive_us.max;
      longest_name = vector_name(i);
    }
    if (v.exclusive_us.count && v.exclusive_us.max > longest_excl) {
      longest_excl = v.exclusive_us.max;
      longest_excl_name = vector_name(i);
    }
  }
  r["interrupts"] = ints;
  r["longest_interrupt"] = {{"us", Stat::round3(longest)},
                            {"vector", longest_name},
                            {"exclusive_us", Stat::round3(longest_excl)},
                            {"exclusive_vector", longest_excl_name}};
  r["longest_interrupts_disabled"] = {{"us", Stat::round3(irq_off_max_us_)},
                                      {"at_us", Stat::round3(us(double(irq_off_max_cycle_)))},
                                      {"pc", irq_off_max_pc_},
                                      {"function", syms_.function_at(irq_off_max_pc_)}};
  r["vector_nesting_mismatches"] = running_mismatch_;

  json stack;
  stack["static_ram_end"] = static_end_;
  stack["static_ram_end_from"] = syms_.static_ram_end_source();
  stack["ramend"] = ramend_;
  stack["painted_bytes"] = ramend_ - static_end_ + 1;
  const int lowest = lowest_touched_ >= 0 ? lowest_touched_ : ramend_ + 1;
  stack["lowest_touched"] = lowest_touched_ >= 0 ? json(lowest_touched_) : json(nullptr);
  stack["min_free_bytes"] = lowest - static_end_;
  stack["min_sp"] = min_sp_;
  stack["min_sp_function"] = syms_.function_at(min_sp_pc_);
  stack["min_free_bytes_by_sp"] = int(min_sp_) + 1 - int(static_end_);
  r["stack"] = stack;
  return r;
}

std::string VirtualNano::summary() const {
  const nlohmann::json r = report();
  std::ostringstream s;
  char buf[400];
  auto num = [](const nlohmann::json& j, const char* k) {
    return j.contains(k) && j[k].is_number() ? j[k].get<double>() : 0.0;
  };
  for (const auto& m : r["motors"]) {
    const auto& iv = m["interval_us"];
    std::snprintf(buf, sizeof buf,
                  "  motor %d %-18s at %6" PRId64 " (%s steps), %" PRIu64 " steps made, %" PRIu64 " faults",
                  m["motor"].get<int>(), m["pins"].get<std::string>().c_str(), m["steps"].get<int64_t>(),
                  m["mode"].get<std::string>().c_str(), m["step_events"].get<uint64_t>(), m["faults"].get<uint64_t>());
    s << buf;
    if (iv["count"].get<uint64_t>()) {
      std::snprintf(buf, sizeof buf,
                    "; interval %.1f..%.1f us (up to %.0f steps/s); jitter %.2f us, delay %.2f..%.2f us",
                    num(iv, "min"), num(iv, "max"), num(m, "max_rate_steps_per_s"), num(m, "jitter_us"),
                    num(m["deadline_delay_us"], "min"), num(m["deadline_delay_us"], "max"));
      s << buf;
    }
    s << "\n";
  }
  const auto& sv = r["servo"];
  if (sv["pulses"].get<uint64_t>()) {
    std::snprintf(buf, sizeof buf, "  servo PD3: %" PRIu64 " pulses, %.1f..%.1f us, last %.1f us (%.1f deg)\n",
                  sv["pulses"].get<uint64_t>(), num(sv["width_us"], "min"), num(sv["width_us"], "max"),
                  num(sv, "last_us"), num(sv, "last_angle_deg"));
    s << buf;
  } else {
    s << "  servo PD3: no pulses\n";
  }
  for (const auto& e : r["endstops"]) {
    std::snprintf(buf, sizeof buf,
                  "  endstop %s (motor %d, closes at <= %" PRId64 "): pressed %" PRIu64 " times, now %s\n",
                  e["pin"].get<std::string>().c_str(), e["motor"].get<int>(), e["closes_at_or_below"].get<int64_t>(),
                  e["presses"].get<uint64_t>(), e["pressed"].get<bool>() ? "pressed" : "open");
    s << buf;
  }
  const auto& st = r["status"];
  std::snprintf(buf, sizeof buf, "  status '?': %" PRIu64 " sent, %" PRIu64 " reports", st["requests"].get<uint64_t>(),
                st["replies"].get<uint64_t>());
  s << buf;
  if (st["first_byte_us"]["count"].get<uint64_t>()) {
    std::snprintf(buf, sizeof buf, "; first byte after %.1f..%.1f us, LF after %.1f..%.1f us",
                  num(st["first_byte_us"], "min"), num(st["first_byte_us"], "max"), num(st["line_end_us"], "min"),
                  num(st["line_end_us"], "max"));
    s << buf;
  }
  s << "\n";
  const auto& li = r["longest_interrupt"];
  const auto& ld = r["longest_interrupts_disabled"];
  std::snprintf(buf, sizeof buf,
                "  interrupts: longest %.1f us (%s; %.1f us without nested ones, %s); "
                "interrupts off at most %.1f us (%s)\n",
                num(li, "us"), li["vector"].get<std::string>().c_str(), num(li, "exclusive_us"),
                li["exclusive_vector"].get<std::string>().c_str(), num(ld, "us"),
                ld["function"].get<std::string>().c_str());
  s << buf;
  for (const auto& v : r["interrupts"]) {
    std::snprintf(buf, sizeof buf,
                  "    %-13s %8" PRIu64 " entries, entry latency %.2f..%.2f us, duration %.2f..%.2f us\n",
                  v["name"].get<std::string>().c_str(), v["entries"].get<uint64_t>(), num(v["entry_latency_us"], "min"),
                  num(v["entry_latency_us"], "max"), num(v["duration_us"], "min"), num(v["duration_us"], "max"));
    s << buf;
  }
  const auto& sk = r["stack"];
  std::snprintf(buf, sizeof buf, "  stack: %d of %d bytes never used (painted); lowest SP 0x%x (%d bytes free)\n",
                sk["min_free_bytes"].get<int>(), sk["painted_bytes"].get<int>(), sk["min_sp"].get<int>(),
                sk["min_free_bytes_by_sp"].get<int>());
  s << buf;
  return s.str();
}

int header_pin(const std::string& name) { return board::header_index(name.c_str()); }

}  // namespace vnano
