// firmware/src/hal_avr.cpp - hal.h on the ATmega328P of the Arduino Nano.
//
// The only file with the firmware's interrupt handlers:
//   TIMER1_COMPA  the step timer: writes the coils staged for the deadline, then calls
//                 firmware::on_step_timer();
//   TIMER1_COMPB  the gripper servo's pulses (no Servo library: the Debian core has none);
//   USART_RX      a received byte: '?' builds the status report (firmware::status_line()),
//                 '!' goes to firmware::on_realtime(), others are queued;
//   USART_UDRE    sends the next byte: the status report's at a line boundary, else the
//                 next queued byte;
//   USART_TX      (only after a report that a '?' asked for again) builds the next one.
//   TIMER0_COMPA  the millisecond tick (hal::millis, and the idle sleep's latest wake-up).
// No Arduino core is linked: every register this firmware uses is set here, the rest keep
// their reset values (Timer2 and the ADC stay off).
//
// Timer1 runs free at 2 MHz (prescaler 8) in normal mode and is never reset or written:
// both channels move their compare register forward from the previous deadline
// (OCR1x += interval), so an interrupt's own latency never adds up, and no behaviour of a
// compare register rewritten in the middle of a count is relied upon (simavr has bugs
// there). Intervals longer than the 16-bit counter wait whole laps of 65,536 ticks first.
//
// Rules for the firmware's callbacks:
//   - firmware::on_step_timer() runs with interrupts enabled: the servo's compare, Timer0
//     (millis) and the receiver can interrupt it; the transmitter and the step interrupt
//     itself stay masked. The receiver stays open because the first step of a move takes
//     about 170 us to compute (a 32-bit division or two): two bytes' time at 115,200 baud,
//     after which a third byte of a streamed line would be lost. A '?' or '!' received
//     there is acted on at the step interrupt's end, so on_step_timer() never overlaps
//     on_realtime() or status_line(), and the servo's pulse edges keep their time even
//     while a step takes long to compute.
//   - firmware::on_realtime() ('!') runs in the receive interrupt with interrupts off (or at
//     the step interrupt's end, for a '!' received during it): it should only note the
//     request.
//   - firmware::status_line() ('?') runs in the receive interrupt (or TX-complete, or at the
//     end of the step interrupt) with interrupts enabled: the step timer, the servo, Timer0
//     and the serial interrupts themselves may preempt it (the report flags below keep a
//     second build from starting); it must read shared state in a critical section. It never
//     runs within the step computation: a '?' taken there (between catch-up steps) is built
//     at the end of the step interrupt.
//   - serial_write() belongs to the main loop, with interrupts enabled: when the transmit
//     buffer is full it waits for the UDRE interrupt to make room.
#if defined(__AVR__)

#include "hal.h"

#include <avr/cpufunc.h>
#include <avr/eeprom.h>
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/pgmspace.h>
#include <avr/sleep.h>

#include "articula/protocol.h"
#include "firmware.h"
#include "pins.h"
#include "robot.h"
#include "report.h"

namespace {

static_assert(F_CPU / 8 == hal::kTickHz, "Timer1 runs at F_CPU / 8");

// ---------------------------------------------------------------------------------------
// The step timer (Timer1, channel A)

// A deadline this close (or closer, or past) when it is armed may be missed by the compare
// unit; the interrupt then runs the step at once instead. 2 ticks = 1 us.
const uint16_t kMinLead = 2;
// The first deadline after start_step_timer() is at least this far away, so that the
// compare register is written before the counter gets there. 16 ticks = 8 us.
const uint16_t kStartLead = 16;
// Steps run back to back at most this many times in one interrupt when their deadlines
// are already past; after that the schedule slips (restarts from now + kSlipTicks), so a
// firmware asking for more than the CPU can do still leaves time for the main loop.
const uint8_t kMaxCatchUp = 4;
const uint16_t kSlipTicks = 40;  // 20 us

volatile bool g_step_running;
volatile bool g_in_step;  // the compare-A interrupt is running (see the rules above)
uint16_t g_step_laps;  // whole 65,536-tick laps still to wait (OCR1A unchanged meanwhile)
uint16_t g_step_rest;  // then the last part of the interval, below one lap (0: none)

// Moves OCR1A `rest` ticks past its current value, the previous deadline. Returns false when
// the new deadline is already due (past, or under kMinLead ahead): then no compare interrupt
// will come for it, and the caller runs the step itself.
bool arm_rest(uint16_t rest) {
  const uint16_t from = OCR1A;
  const uint16_t at = uint16_t(from + rest);
  OCR1A = at;
  const uint16_t elapsed = uint16_t(TCNT1 - from);  // since the previous deadline
  if (elapsed < rest && uint16_t(rest - elapsed) >= kMinLead) return true;
  // Due already. Wait until the counter is 2 ticks past `at`, so that a match the compare
  // unit may have seen has set its flag by now, and clear that flag: one step, one call.
  while (int16_t(TCNT1 - at) < 2) {
  }
  TIFR1 = _BV(OCF1A);
  return false;
}

// Arms the deadline `ticks` after the previous one; false when it is already due.
bool schedule(uint32_t ticks) {
  g_step_laps = uint16_t(ticks >> 16);
  g_step_rest = uint16_t(ticks);
  if (g_step_laps != 0) return true;  // OCR1A unchanged: it matches again one lap later
  return arm_rest(g_step_rest);
}

// Calls the firmware with interrupts enabled except the transmitter's and this one, so the
// servo's compare and the receiver can interrupt a long step computation. Interrupts are off
// again on return.
uint32_t call_firmware() {
  const uint8_t ucsr = UCSR0B;
  UCSR0B = ucsr & uint8_t(~(_BV(UDRIE0) | _BV(TXCIE0)));
  TIMSK1 &= uint8_t(~_BV(OCIE1A));
  sei();
  const uint32_t next = firmware::on_step_timer();
  cli();
  UCSR0B = ucsr;
  return next;
}

// Coil patterns for the next deadline (stage_coils), bits 0..3; or, on a CNC shield, the
// motors with a STEP pulse at it (stage_pulse).
uint8_t g_stage_mask;  // bit i: motor i has one
uint8_t g_stage[3];

#if defined(ARTICULA_CNC_SHIELD)
// hal.h's STEP pulse width and DIR setup time, in CPU cycles (the instructions around each
// wait add a few more).
const uint8_t kStepPulseCycles = uint8_t(F_CPU / 1000000UL * hal::kStepPulseNs / 1000);
const uint8_t kDirSetupCycles = uint8_t(F_CPU / 1000000UL * hal::kDirSetupNs / 1000);

// The staged STEP pulses, first thing at a deadline: every one raised by one port write, held
// kStepPulseCycles, lowered by one write. Interrupts off (the port's other bits are DIR's and
// the serial line's).
inline void write_staged() {
  const uint8_t m = g_stage_mask;
  if (m == 0) return;
  const uint8_t bits = uint8_t(m << ARTICULA_STEP_SHIFT);
  ARTICULA_STEP_PORT |= bits;
  __builtin_avr_delay_cycles(kStepPulseCycles);
  ARTICULA_STEP_PORT &= uint8_t(~bits);
  g_stage_mask = 0;
}

// A motor's DIR pin: high towards more steps.
inline void set_dir(uint8_t motor, bool negative) {
  const uint8_t bit = uint8_t(1u << (ARTICULA_DIR_SHIFT + motor));
  const uint8_t sreg = hal::interrupts_off();
  if (negative)
    ARTICULA_STEP_PORT &= uint8_t(~bit);
  else
    ARTICULA_STEP_PORT |= bit;
  hal::interrupts_restore(sreg);
}
#elif defined(ARTICULA_SERVO_ARM)
inline void write_staged();  // with the servos, below
#else
// The staged patterns to the ports, first thing at a deadline: the three writes are a few
// cycles apart and a fixed number of cycles after the interrupt's entry, whatever the
// firmware computes afterwards. Interrupts off (a port's other bits belong to the servo, an
// endstop's pull-up and the LED).
inline void write_staged() {
  const uint8_t m = g_stage_mask;
  if (m == 0) return;
  // The patterns' shifts fold into a swap or nothing; every motor's bits come from its own byte.
  if (m & 1)
    ARTICULA_MOTOR0_PORT = uint8_t((ARTICULA_MOTOR0_PORT & ~ARTICULA_COIL_MASK(ARTICULA_MOTOR0_SHIFT)) |
                                   uint8_t(g_stage[0] << ARTICULA_MOTOR0_SHIFT));
  if (m & 2)
    ARTICULA_MOTOR1_PORT = uint8_t((ARTICULA_MOTOR1_PORT & ~ARTICULA_COIL_MASK(ARTICULA_MOTOR1_SHIFT)) |
                                   uint8_t(g_stage[1] << ARTICULA_MOTOR1_SHIFT));
  if (m & 4)
    ARTICULA_MOTOR2_PORT = uint8_t((ARTICULA_MOTOR2_PORT & ~ARTICULA_COIL_MASK(ARTICULA_MOTOR2_SHIFT)) |
                                   uint8_t(g_stage[2] << ARTICULA_MOTOR2_SHIFT));
  g_stage_mask = 0;
}
#endif

void stop_in_isr() {
  TIMSK1 &= uint8_t(~_BV(OCIE1A));
  g_step_running = false;
  g_stage_mask = 0;
  ARTICULA_LED_PORT &= uint8_t(~_BV(ARTICULA_LED_BIT));
}

// Runs the step that is due and arms the next deadline; catches up on deadlines that are
// already past. Interrupts are off on entry and on return.
void run_due_steps() {
  for (uint8_t runs = 1;; ++runs) {
    write_staged();
    const uint32_t next = call_firmware();
    if (next == 0 || !g_step_running) {  // the firmware is done, or stopped the timer itself
      stop_in_isr();
      return;
    }
    if (schedule(next)) break;
    if (runs == kMaxCatchUp) {
      // Overloaded: the due step waits kSlipTicks from now, and the schedule restarts there.
      // (schedule() only fails for an interval under one lap, so no laps are pending.)
      OCR1A = uint16_t(TCNT1 + kSlipTicks);
      break;
    }
    // The next step is due at once. First let in the interrupts that have been waiting (a
    // received byte, the transmitter, millis; this one stays masked), so that a run of late
    // steps cannot hold the receiver off long enough to lose a byte. The instruction after
    // sei() always runs before a pending interrupt, hence the nop.
    sei();
    _NOP();
    cli();
  }
  TIMSK1 |= _BV(OCIE1A);
}

// ---------------------------------------------------------------------------------------
// The millisecond tick (Timer0, CTC): 16 MHz / 64 / 250 = exactly 1 kHz.

const uint8_t kMillisTop = F_CPU / 64 / 1000 - 1;
static_assert(F_CPU / 64 % 1000 == 0 && F_CPU / 64 / 1000 <= 256, "Timer0 counts one millisecond in 8 bits");
volatile uint32_t g_millis;

// ---------------------------------------------------------------------------------------
// The servo (Timer1, channel B): the pin goes high at the start of each 20 ms period and low
// `width` ticks later. The width is taken at the start of a period, so a change never cuts
// a pulse short.

const uint16_t kServoPeriodTicks = 20000U * 2;      // 20 ms
const uint16_t kServoMinUs = 200, kServoMaxUs = 3000;  // keeps the pulse inside the period

// A header pin (board.h's kHeaderPin index: D0..D7 on port D, D8..D13 on B, A0..A5 on C) as its
// PORT register, with its PIN and DDR registers two and one below it, and its bit.
__attribute__((noinline)) volatile uint8_t* header_port(uint8_t pin, uint8_t& bit) {
  static_assert(board::kHeaderPins == 20 && board::port_io(board::kPortD) == 0x0B && board::port_io(board::kPortB) == 0x05 &&
                    board::port_io(board::kPortC) == 0x08,
                "D0..D7 on PORTD, D8..D13 on PORTB, A0..A5 on PORTC");
  uint8_t io = 0x0B;
  if (pin >= 14) {
    io = 0x08;
    pin = uint8_t(pin - 14);
  } else if (pin >= 8) {
    io = 0x05;
    pin = uint8_t(pin - 8);
  }
  bit = uint8_t(1u << pin);
  return &_SFR_IO8(io);
}

#if defined(ARTICULA_SERVO_ARM)
// The servo arm's build: a channel for each motor's servo and the gripper's last. In each
// period every channel with a width gives its pulse in turn, kServoGapTicks apart; the period's
// rest follows. Each edge is armed kServoLeadTicks early and its interrupt waits for the
// edge's tick with interrupts off, so another interrupt running when the compare comes (the
// serial ones, millis, the step interrupt's few cycles with interrupts off) moves no edge; both
// edges of a pulse then lie the same few cycles after their ticks, and the width is the
// channel's ticks to the cycle. Four channels of at most 2,600 us and their gaps fit a period.
const uint8_t kServoChannels = 4;  // motors 0..2, the gripper
const uint8_t kGripperChannel = 3;
const uint16_t kServoLeadTicks = 40;  // 20 us: longer than any stretch with interrupts off (15 us at most)
const uint16_t kServoGapTicks = 64;   // 32 us: the lead, and the interrupt's own time after an edge
enum : uint8_t { kServoRest, kServoRise, kServoFall };

volatile uint16_t g_servo_ticks[kServoChannels];  // each channel's width; 0: no pulse
volatile uint8_t* g_servo_ports[kServoChannels];  // its pin's PORT register
uint8_t g_servo_bits[kServoChannels];             // and bit
uint8_t g_servo_phase;                 // what the next compare is: the rest's end, a rise, a fall
uint8_t g_servo_at;                    // the channel rising or falling next
uint16_t g_servo_edge;                 // Timer1's count at the next edge (or the rest's end)
uint16_t g_servo_used;                 // ticks of the period used by its pulses and gaps so far
uint16_t g_servo_width;                // the width of the pulse rising or falling next


// After an edge (or the rest's end, `first`): arms the next channel's rise, or the period's rest.
inline void servo_next(bool first) {
  uint8_t at = first ? 0 : uint8_t(g_servo_at + 1);
  while (at < kServoChannels && g_servo_ticks[at] == 0) ++at;
  const uint16_t from = g_servo_edge;
  if (at < kServoChannels) {
    g_servo_at = at;
    g_servo_width = g_servo_ticks[at];  // taken here, a gap before its pulse
    g_servo_phase = kServoRise;
    g_servo_edge = uint16_t(from + kServoGapTicks);
    g_servo_used = uint16_t(g_servo_used + kServoGapTicks + g_servo_width);
  } else {
    g_servo_phase = kServoRest;
    g_servo_edge = uint16_t(from + kServoPeriodTicks - g_servo_used);
    g_servo_used = 0;
  }
  OCR1B = uint16_t(g_servo_edge - kServoLeadTicks);
}

// Starts the pulses if they are not running: the first period begins shortly. Interrupts off.
void servo_start() {
  if (TIMSK1 & _BV(OCIE1B)) return;
  g_servo_phase = kServoRest;
  g_servo_used = 0;
  g_servo_edge = uint16_t(TCNT1 + kStartLead + kServoLeadTicks);
  OCR1B = uint16_t(g_servo_edge - kServoLeadTicks);
  TIFR1 = _BV(OCF1B);
  TIMSK1 |= _BV(OCIE1B);
}
// The staged ticks, first thing at a deadline: each staged motor's width one tick longer, or
// shorter (g_stage[i] = 1). Interrupts off, so the servo's interrupt never reads half a width.
inline void write_staged() {
  const uint8_t m = g_stage_mask;
  if (m == 0) return;
  for (uint8_t i = 0; i < 3; ++i)
    if (m & (1u << i)) g_servo_ticks[i] = uint16_t(g_servo_ticks[i] + (g_stage[i] ? -1 : 1));
  g_stage_mask = 0;
}
#else
volatile uint16_t g_servo_width;  // ticks; 0: no more pulses
uint16_t g_servo_pulse;           // the width of the pulse being output
bool g_servo_high;
#endif

// ---------------------------------------------------------------------------------------
// Serial (USART0): two ring buffers, sizes powers of two below 256, and the status report's
// own buffer.

const uint8_t kRxSize = 64;  // a whole protocol line (the host waits for each reply)
const uint8_t kTxSize = 64;  // a reply or a setting line; longer output waits for room
static_assert((kRxSize & (kRxSize - 1)) == 0 && (kTxSize & (kTxSize - 1)) == 0, "powers of two");

char g_rx[kRxSize];
volatile uint8_t g_rx_head;  // written by the receive interrupt
volatile uint8_t g_rx_tail;  // written by serial_read
char g_tx[kTxSize];
volatile uint8_t g_tx_head;  // written by serial_write
volatile uint8_t g_tx_tail;  // written by the UDRE interrupt
bool g_tx_line_start;        // the last byte sent from g_tx was an LF (or none was): a report may go

// The status report, sent as it is built: firmware::status_line() writes it into g_report
// with interrupts enabled while tx_next() sends from the same buffer every byte already
// written (non-zero) and zeroes it behind itself, so a report can start going out before it
// is complete (its first byte, '<', is put in place before the build starts). When it is
// built and when it goes: report.h's rules (g_sched, changed with interrupts off only).
const uint8_t kReportSize = articula::status_report_size(3);  // the most motors the Nano drives
char g_report[kReportSize];   // all zero when no report is waiting or going out
uint8_t g_report_pos;         // the next byte of it to send
report::Schedule g_sched;
volatile bool g_started;     // hal::start() has run: the firmware is set up
volatile bool g_stop_early;  // a '!' received before start()
volatile bool g_stop_in_step;  // a '!' received during the step interrupt: acted on at its end

// The UDRE interrupt's work: puts the next byte into UDR0 when it is empty: the report's
// while one is going out, or is waiting at a line boundary; else the next queued byte, except
// that a report on its way (requested or being built) keeps a line boundary for itself. With
// nothing to send now, masks UDRE (serial_write and build_report() set it again). A '?' that
// came while the report went out is built from the TX-complete interrupt once its LF is
// sent. Inlined: the UDRE interrupt then calls nothing and saves few registers (it runs once
// a byte, and its time delays a step deadline that falls in it).
__attribute__((always_inline)) inline void tx_next() {
  if (!(UCSR0A & _BV(UDRE0))) return;  // a nested call filled it meanwhile: UDRE comes again
  if (g_sched.report_next(g_tx_line_start, g_report[0] != 0)) {
    const uint8_t pos = g_report_pos;
    const char c = g_report[pos];
    if (c == 0) {  // not written yet: build_report() sets UDRE again when it is done
      UCSR0B &= uint8_t(~_BV(UDRIE0));
      return;
    }
    UDR0 = c;
    g_report[pos] = 0;
    const bool lf = c == '\n';
    if (!lf) {
      g_report_pos = uint8_t(pos + 1);
    } else {
      g_report[0] = 0;  // the builder may have written it again after it went out
      g_report_pos = 0;
    }
    if (g_sched.on_report_byte(lf)) UCSR0B |= _BV(TXCIE0);  // the LF's frame completes: the next report is built then
    return;
  }
  const uint8_t tail = g_tx_tail;
  if (tail == g_tx_head || !g_sched.queue_may_send(g_tx_line_start)) {
    UCSR0B &= uint8_t(~_BV(UDRIE0));
    return;
  }
  const char c = g_tx[tail];
  UDR0 = c;
  g_tx_tail = uint8_t((tail + 1) & (kTxSize - 1));
  g_tx_line_start = c == '\n';
}

// Builds the requested report: firmware::status_line() with interrupts enabled, so the step
// timer and the servo keep their time, the receive interrupt keeps reading and the transmit
// interrupt sends what is written. From the receive, TX-complete or step interrupt (at its
// end), never within the step computation; g_report is all zero. When a '?' came while the
// report went out and its LF has gone before the build returned, builds the next at once.
// Interrupts off on entry and on return.
__attribute__((noinline)) void build_report() {
  do {
    g_sched.begin_build();
    g_report[0] = '<';  // how every status report starts: it may go out at once
    UCSR0B |= _BV(UDRIE0);
    sei();
    const uint8_t n = firmware::status_line(g_report, kReportSize);
    cli();
    g_sched.end_build();
    if (n == 0) g_report[1] = '\n';  // never (the buffer fits any report); ends the line begun
    UCSR0B |= _BV(UDRIE0);            // the transmitter may have caught up with the builder
  } while (g_sched.build_again());
}

// Builds a requested report now if it may be built here.
inline void build_report_if_due() {
  if (g_sched.due(g_started, g_in_step)) build_report();
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Interrupts

ISR(TIMER1_COMPA_vect) {
  // A real deadline is never more than half a lap behind the counter; a flag left over from
  // an earlier compare value (or an emulator's extra match) is ahead of it: ignore it.
  if (uint16_t(TCNT1 - OCR1A) >= 0x8000U) return;
  if (g_step_laps != 0) {
    if (--g_step_laps != 0) return;                       // more whole laps to wait
    if (g_step_rest != 0 && arm_rest(g_step_rest)) return;  // the last part is armed
    // else the end of this lap is the deadline (or the last part is due already)
  }
  g_in_step = true;
  run_due_steps();
  g_in_step = false;
  // A '!' or '?' received during the step work: the stop noted now; the report built now
  // (the step interrupt is enabled again and may preempt the build like any other).
  if (g_stop_in_step) {
    g_stop_in_step = false;
    firmware::on_realtime('!');
  }
  build_report_if_due();
}

#if defined(ARTICULA_SERVO_ARM)
ISR(TIMER1_COMPB_vect) {
  const uint8_t phase = g_servo_phase;
  if (phase != kServoRest) {
    // An edge: armed kServoLeadTicks early; its tick is waited for here, interrupts off, and
    // the port's new value (worked out first) written at once: both edges of a pulse a few
    // instructions after their ticks, never another interrupt's time. (Only the counter's low
    // byte is polled: a shorter loop, and the lead is far below 128 ticks.) The loop's turn (6
    // cycles) is not a tick's 8, so where in its tick an edge falls depends on when the
    // interrupt came: a width lies up to a few cycles off its whole ticks (bench_drives.py).
    const uint8_t edge = uint8_t(g_servo_edge);
    volatile uint8_t* const port = g_servo_ports[g_servo_at];
    const uint8_t bit = g_servo_bits[g_servo_at];
    const uint8_t value = phase == kServoRise ? uint8_t(*port | bit) : uint8_t(*port & ~bit);
    while (int8_t(TCNT1L - edge) < 0) {
    }
    *port = value;
    if (phase == kServoRise) {
      g_servo_phase = kServoFall;
      g_servo_edge = uint16_t(g_servo_edge + g_servo_width);
      OCR1B = uint16_t(g_servo_edge - kServoLeadTicks);
      return;
    }
  }
  servo_next(phase == kServoRest);
}
#else
ISR(TIMER1_COMPB_vect) {
  if (g_servo_high) {
    ARTICULA_SERVO_PORT &= uint8_t(~_BV(ARTICULA_SERVO_BIT));
    g_servo_high = false;
    OCR1B += uint16_t(kServoPeriodTicks - g_servo_pulse);
    return;
  }
  g_servo_pulse = g_servo_width;
  if (g_servo_pulse == 0) {  // stopped: the pin stays low, no more interrupts
    TIMSK1 &= uint8_t(~_BV(OCIE1B));
    return;
  }
  ARTICULA_SERVO_PORT |= _BV(ARTICULA_SERVO_BIT);
  g_servo_high = true;
  OCR1B += g_servo_pulse;
}
#endif

ISR(USART_RX_vect) {
  const uint8_t status = UCSR0A;
  const char c = char(UDR0);
  if (status & _BV(FE0)) return;  // a framing error: noise or a wrong baud rate, not a byte
  const articula::RealtimeCommand rt = articula::realtime_command(c);
  if (rt == articula::kRealtimeStatus) {
    // One report answers every '?' until it starts going out; one that comes while it is
    // going out gets one more after it.
    g_sched.on_request(g_report[0] != 0);
    build_report_if_due();
    return;
  }
  if (rt != articula::kRealtimeNone) {
    if (!g_started)
      g_stop_early = true;
    else if (g_in_step)
      g_stop_in_step = true;
    else
      firmware::on_realtime(c);
    return;
  }
  const uint8_t head = g_rx_head;
  const uint8_t next = uint8_t((head + 1) & (kRxSize - 1));
  if (next == g_rx_tail) return;  // full: dropped (a host that waits for replies never fills it)
  g_rx[head] = c;
  g_rx_head = next;
}

ISR(USART_UDRE_vect) { tx_next(); }

ISR(TIMER0_COMPA_vect) { g_millis = g_millis + 1; }

// Enabled only when the LF of a report has gone into UDR0 and a '?' came while it went out.
ISR(USART_TX_vect) {
  UCSR0B &= uint8_t(~_BV(TXCIE0));
  build_report_if_due();
}

// ---------------------------------------------------------------------------------------
// hal.h

namespace hal {

void init() {
  cli();

#if defined(ARTICULA_CNC_SHIELD)
  // The drivers disabled (EN high) before it becomes an output, STEP and DIR low.
  ARTICULA_ENABLE_PORT |= _BV(ARTICULA_ENABLE_BIT);
  ARTICULA_ENABLE_DDR |= _BV(ARTICULA_ENABLE_BIT);
  const uint8_t step_dir = uint8_t((0x07 << ARTICULA_STEP_SHIFT) | (0x07 << ARTICULA_DIR_SHIFT));
  ARTICULA_STEP_PORT &= uint8_t(~step_dir);
  ARTICULA_STEP_DDR |= step_dir;
#elif defined(ARTICULA_SERVO_ARM)
  // The motors' servo pins become outputs when attached (attach_servo), the gripper's here.
  for (uint8_t i = 0; i < kServoChannels; ++i) g_servo_ticks[i] = 0;
  g_servo_ports[kGripperChannel] = &ARTICULA_SERVO_PORT;
  g_servo_bits[kGripperChannel] = _BV(ARTICULA_SERVO_BIT);
#else
  // Coils off before the pins become outputs, so no motor twitches at start-up.
  ARTICULA_MOTOR0_PORT &= uint8_t(~ARTICULA_COIL_MASK(ARTICULA_MOTOR0_SHIFT));
  ARTICULA_MOTOR0_DDR |= ARTICULA_COIL_MASK(ARTICULA_MOTOR0_SHIFT);
  ARTICULA_MOTOR1_PORT &= uint8_t(~ARTICULA_COIL_MASK(ARTICULA_MOTOR1_SHIFT));
  ARTICULA_MOTOR1_DDR |= ARTICULA_COIL_MASK(ARTICULA_MOTOR1_SHIFT);
  ARTICULA_MOTOR2_PORT &= uint8_t(~ARTICULA_COIL_MASK(ARTICULA_MOTOR2_SHIFT));
  ARTICULA_MOTOR2_DDR |= ARTICULA_COIL_MASK(ARTICULA_MOTOR2_SHIFT);
#endif

  ARTICULA_SERVO_PORT &= uint8_t(~_BV(ARTICULA_SERVO_BIT));
  ARTICULA_SERVO_DDR |= _BV(ARTICULA_SERVO_BIT);
  ARTICULA_LED_PORT &= uint8_t(~_BV(ARTICULA_LED_BIT));
  ARTICULA_LED_DDR |= _BV(ARTICULA_LED_BIT);

  // (The pins O and W may use become inputs with their pull-ups once a configuration is in
  // use: io_inputs. A servo arm's depend on it.)

  // Endstops: inputs with pull-ups.
  ARTICULA_ENDSTOP0_DDR &= uint8_t(~_BV(ARTICULA_ENDSTOP0_BIT));
  ARTICULA_ENDSTOP0_PORT |= _BV(ARTICULA_ENDSTOP0_BIT);
  ARTICULA_ENDSTOP1_DDR &= uint8_t(~_BV(ARTICULA_ENDSTOP1_BIT));
  ARTICULA_ENDSTOP1_PORT |= _BV(ARTICULA_ENDSTOP1_BIT);
  ARTICULA_ENDSTOP2_DDR &= uint8_t(~_BV(ARTICULA_ENDSTOP2_BIT));
  ARTICULA_ENDSTOP2_PORT |= _BV(ARTICULA_ENDSTOP2_BIT);

  // Timer2 and the ADC stay off, as the reset left them: nothing here uses either, they draw
  // nothing while the CPU sleeps (hal::idle), and an emulator need not count their ticks.
  // (A bootloader may have used Timer0, Timer1 and the USART: those are all set below.)

  // Timer0: the millisecond tick, CTC at 1 kHz, no output pins.
  g_millis = 0;
  TCCR0A = _BV(WGM01);
  TCCR0B = _BV(CS01) | _BV(CS00);  // clk/64
  TCNT0 = 0;
  OCR0A = kMillisTop;
  TIFR0 = _BV(OCF0B) | _BV(OCF0A) | _BV(TOV0);
  TIMSK0 = _BV(OCIE0A);

  // Timer1: normal mode, clk/8, no output pins.
  TCCR1A = 0;
  TCCR1B = _BV(CS11);
  TCCR1C = 0;
  TIMSK1 = 0;
  TIFR1 = _BV(ICF1) | _BV(OCF1B) | _BV(OCF1A) | _BV(TOV1);
  g_step_running = false;
  g_in_step = false;
  g_stage_mask = 0;
#if !defined(ARTICULA_SERVO_ARM)
  g_servo_width = 0;
  g_servo_high = false;
#endif

  // USART0: 115200 8N1. With U2X0 the divisor 16 gives 117,647 baud (+2.1 %), closer than
  // the 111,111 (-3.5 %) without it; the Arduino core makes the same choice.
  g_rx_head = g_rx_tail = 0;
  g_tx_head = g_tx_tail = 0;
  g_tx_line_start = true;
  g_report_pos = 0;
  g_sched.reset();
  g_started = false;
  g_stop_early = false;
  g_stop_in_step = false;
  // Off first: a bootloader that jumps here (the old one does, without a reset) leaves it on
  // at its own rate, and the rate is set with the receiver and transmitter disabled.
  UCSR0B = 0;
  UCSR0A = _BV(U2X0);
  UBRR0 = uint16_t((F_CPU / (8UL * ARTICULA_SERIAL_BAUD)) - 1);
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);

  sei();  // from here on, whatever the state before (the reset's: off)
}

void start() {
  const uint8_t sreg = interrupts_off();
  g_started = true;
  if (g_stop_early) {
    g_stop_early = false;
    firmware::on_realtime('!');
  }
  if (g_sched.requested) build_report();  // a '?' received during set-up
  interrupts_restore(sreg);
}

void write_coils(uint8_t motor, uint8_t pattern) {
#if defined(ARTICULA_CNC_SHIELD)
  (void)motor;
  (void)pattern;
#else
  const uint8_t sreg = interrupts_off();  // a port's other bits belong to others (servo, endstop pull-ups, LED)
  switch (motor) {
    case 0: {
      const uint8_t mask = ARTICULA_COIL_MASK(ARTICULA_MOTOR0_SHIFT);
      ARTICULA_MOTOR0_PORT = uint8_t((ARTICULA_MOTOR0_PORT & ~mask) | ((pattern << ARTICULA_MOTOR0_SHIFT) & mask));
      break;
    }
    case 1: {
      const uint8_t mask = ARTICULA_COIL_MASK(ARTICULA_MOTOR1_SHIFT);
      ARTICULA_MOTOR1_PORT = uint8_t((ARTICULA_MOTOR1_PORT & ~mask) | ((pattern << ARTICULA_MOTOR1_SHIFT) & mask));
      break;
    }
    case 2: {
      const uint8_t mask = ARTICULA_COIL_MASK(ARTICULA_MOTOR2_SHIFT);
      ARTICULA_MOTOR2_PORT = uint8_t((ARTICULA_MOTOR2_PORT & ~mask) | ((pattern << ARTICULA_MOTOR2_SHIFT) & mask));
      break;
    }
    default:
      break;
  }
  interrupts_restore(sreg);
#endif
}

void set_servo_pulse(uint16_t microseconds) {
  uint16_t us = microseconds;
  if (us != 0 && us < kServoMinUs) us = kServoMinUs;
  if (us > kServoMaxUs) us = kServoMaxUs;
  const uint8_t sreg = interrupts_off();
#if defined(ARTICULA_SERVO_ARM)
  g_servo_ticks[kGripperChannel] = uint16_t(us * 2);
  if (us != 0) servo_start();
#else
  g_servo_width = uint16_t(us * 2);
  if (us != 0 && !(TIMSK1 & _BV(OCIE1B))) {
    // Not pulsing: the first period starts shortly; the chain runs from there.
    g_servo_high = false;
    OCR1B = uint16_t(TCNT1 + kStartLead);
    TIFR1 = _BV(OCF1B);
    TIMSK1 |= _BV(OCIE1B);
  }
#endif
  interrupts_restore(sreg);
}

void attach_servo(uint8_t motor, uint8_t pin, uint16_t ticks) {
#if defined(ARTICULA_SERVO_ARM)
  if (motor >= kGripperChannel || pin >= board::kHeaderPins) return;
  uint8_t bit;
  volatile uint8_t* const port = header_port(pin, bit);
  const uint8_t sreg = interrupts_off();
  *port &= uint8_t(~bit);
  *(port - 1) |= bit;  // DDRx sits just below PORTx
  g_servo_ports[motor] = port;
  g_servo_bits[motor] = bit;
  g_servo_ticks[motor] = ticks;
  servo_start();
  interrupts_restore(sreg);
#else
  (void)motor;
  (void)pin;
  (void)ticks;
#endif
}

bool endstop(uint8_t motor) {
  switch (motor) {
    case 0:
      return !(ARTICULA_ENDSTOP0_PIN & _BV(ARTICULA_ENDSTOP0_BIT));
    case 1:
      return !(ARTICULA_ENDSTOP1_PIN & _BV(ARTICULA_ENDSTOP1_BIT));
    case 2:
      return !(ARTICULA_ENDSTOP2_PIN & _BV(ARTICULA_ENDSTOP2_BIT));
    default:
      return false;
  }
}

void io_inputs(uint32_t pins) {
  const uint8_t d = uint8_t(pins), b = uint8_t(pins >> 8) & 0x3F, c = uint8_t(pins >> 14) & 0x3F;
  const uint8_t sreg = interrupts_off();  // (the step and servo interrupts write these ports too)
  DDRD &= uint8_t(~d);
  PORTD |= d;
  DDRB &= uint8_t(~b);
  PORTB |= b;
  DDRC &= uint8_t(~c);
  PORTC |= c;
  interrupts_restore(sreg);
}

void io_write(uint8_t pin, bool high) {
  uint8_t bit;
  volatile uint8_t* const port = header_port(pin, bit);
  const uint8_t sreg = interrupts_off();  // (the step and servo interrupts write these ports too)
  if (high)
    *port |= bit;
  else
    *port &= uint8_t(~bit);
  *(port - 1) |= bit;
  interrupts_restore(sreg);
}

bool io_read(uint8_t pin) {
  uint8_t bit;
  volatile uint8_t* const port = header_port(pin, bit);
  return (*(port - 2) & bit) != 0;
}

uint32_t io_levels() { return PIND | (uint32_t(PINB & 0x3F) << 8) | (uint32_t(PINC & 0x3F) << 14); }

void start_step_timer(uint32_t first_ticks) {
  uint32_t t = first_ticks < kStartLead ? kStartLead : first_ticks;
  if (t > 0xFFFEFFFFUL) t = 0xFFFEFFFFUL;  // 35 minutes: keeps the lap count in 16 bits
  t -= kStartLead;
  const uint8_t sreg = interrupts_off();
  // The chain starts with a compare kStartLead ticks from now, counted as one more lap; the
  // rest of the interval follows from there as from any deadline.
  g_step_laps = uint16_t((t >> 16) + 1);
  g_step_rest = uint16_t(t);
  OCR1A = uint16_t(TCNT1 + kStartLead);
  TIFR1 = _BV(OCF1A);
  g_step_running = true;
  TIMSK1 |= _BV(OCIE1A);
  ARTICULA_LED_PORT |= _BV(ARTICULA_LED_BIT);  // the LED shows the step timer running
  interrupts_restore(sreg);
}

void stop_step_timer() {
  const uint8_t sreg = interrupts_off();
  stop_in_isr();
  interrupts_restore(sreg);
}

void stage_coils(uint8_t motor, uint8_t pattern) {
  // Only on_step_timer() (the step interrupt masked) and the main loop with the timer
  // stopped get here: write_staged() cannot run meanwhile.
  if (motor > 2) return;
  g_stage[motor] = uint8_t(pattern & 0x0F);
  g_stage_mask = uint8_t(g_stage_mask | (1u << motor));
}

// STEP/DIR: only the build for a CNC shield has the pins (the 4-wire build never calls these:
// robot::step_dir() is a constant there).
void stage_pulse(uint8_t motor, bool negative) {
#if defined(ARTICULA_CNC_SHIELD)
  if (motor > 2) return;
  set_dir(motor, negative);
  g_stage_mask = uint8_t(g_stage_mask | (1u << motor));
#elif defined(ARTICULA_SERVO_ARM)
  if (motor > 2) return;
  g_stage[motor] = negative ? 1 : 0;
  g_stage_mask = uint8_t(g_stage_mask | (1u << motor));
#else
  (void)motor;
  (void)negative;
#endif
}

void pulse_step(uint8_t motor, bool negative) {
#if defined(ARTICULA_CNC_SHIELD)
  if (motor > 2) return;
  set_dir(motor, negative);
  __builtin_avr_delay_cycles(kDirSetupCycles);
  const uint8_t bit = uint8_t(1u << (ARTICULA_STEP_SHIFT + motor));
  const uint8_t sreg = interrupts_off();
  ARTICULA_STEP_PORT |= bit;
  __builtin_avr_delay_cycles(kStepPulseCycles);
  ARTICULA_STEP_PORT &= uint8_t(~bit);
  interrupts_restore(sreg);
#elif defined(ARTICULA_SERVO_ARM)
  if (motor > 2) return;
  const uint8_t sreg = interrupts_off();
  g_servo_ticks[motor] = uint16_t(g_servo_ticks[motor] + (negative ? -1 : 1));
  interrupts_restore(sreg);
#else
  (void)motor;
  (void)negative;
#endif
}

void enable_drivers(bool on) {
#if defined(ARTICULA_CNC_SHIELD)
  const uint8_t sreg = interrupts_off();
  if (on)
    ARTICULA_ENABLE_PORT &= uint8_t(~_BV(ARTICULA_ENABLE_BIT));
  else
    ARTICULA_ENABLE_PORT |= _BV(ARTICULA_ENABLE_BIT);
  interrupts_restore(sreg);
#else
  (void)on;
#endif
}

bool step_timer_running() { return g_step_running; }

uint32_t millis() {
  const uint8_t sreg = interrupts_off();
  const uint32_t ms = g_millis;
  interrupts_restore(sreg);
  return ms;
}

int16_t serial_read() {
  const uint8_t tail = g_rx_tail;
  if (tail == g_rx_head) return -1;
  const uint8_t c = uint8_t(g_rx[tail]);
  g_rx_tail = uint8_t((tail + 1) & (kRxSize - 1));
  return c;
}

void serial_write(char c) {
  const uint8_t head = g_tx_head;
  const uint8_t next = uint8_t((head + 1) & (kTxSize - 1));
  while (next == g_tx_tail) {
    // Full: the UDRE interrupt makes room (the main loop's only: interrupts are enabled).
  }
  g_tx[head] = c;
  g_tx_head = next;
  const uint8_t sreg = interrupts_off();
  UCSR0B |= _BV(UDRIE0);
  interrupts_restore(sreg);
}

void eeprom_read(uint16_t address, void* data, uint16_t size) {
  if (address > E2END) return;
  if (size > E2END + 1 - address) size = uint16_t(E2END + 1 - address);
  eeprom_read_block(data, reinterpret_cast<const void*>(address), size);
}

void eeprom_write(uint16_t address, const void* data, uint16_t size) {
  if (address > E2END) return;
  if (size > E2END + 1 - address) size = uint16_t(E2END + 1 - address);
  eeprom_update_block(data, reinterpret_cast<void*>(address), size);
}

void flash_read(void* data, const void* flash, uint16_t size) { memcpy_P(data, flash, size); }

void idle() {
  cli();
  if (g_rx_tail == g_rx_head) {
    set_sleep_mode(SLEEP_MODE_IDLE);
    sleep_enable();
    sei();
    sleep_cpu();  // (runs before any pending interrupt: the datasheet, 7.7)
    sleep_disable();
  }
  sei();
}

uint8_t interrupts_off() {
  const uint8_t sreg = SREG;
  cli();
  return sreg;
}

void interrupts_restore(uint8_t sreg) { SREG = sreg; }

}  // namespace hal

#endif  // __AVR__
