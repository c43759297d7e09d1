// virtual-nano/simavr/vnano.h - the virtual Nano: the firmware's ELF running in simavr (libsimavr 1.6),
// with the Nano's wiring measured from the outside.
//
// What it watches (pins from firmware/src/pins.h):
//   motors 0, 1, 2  IN1..IN4 on PD4..PD7, PB0..PB3, PC0..PC3: decoded on every write of the
//                   port register (simavr's IOPORT_IRQ_REG_PORT), so the four bits of a
//                   pattern are seen together, never as three intermediate patterns;
//   servo           PD3: pulse widths from the cycles between its edges;
//   LED             PB5: lit while the firmware's step timer runs (separates step runs);
//   endstops        PD2, PB4, PC4: driven low while a motor's decoded position is at or
//                   below its switch (--endstop);
//   USART0          bytes in and out, one frame time apart (see README.md);
//   interrupts      every vector's flag raise, entry and RETI (simavr's per-vector
//                   "pending" and "running" IRQs), the I bit and SP after each instruction.
// Every time is a CPU cycle count (avr->cycle); nothing depends on the wall clock.
#ifndef ARTICULA_HIL_VNANO_VNANO_H
#define ARTICULA_HIL_VNANO_VNANO_H

#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coil_decoder.h"
#include "servo_decoder.h"
#include "step_dir_decoder.h"
#include "elf_symbols.h"
#include "stats.h"

struct avr_t;
struct avr_irq_t;
struct avr_uart_t;

namespace vnano {

struct EndstopSpec {
  int motor;
  int64_t closes_at;  // the switch is closed while the motor's step position <= this
};

// A motor that is a hobby servo: its signal pin (board.h's header index) and its pulse at
// step 0, in Timer1's 0.5 us ticks (the robot file's first calibration point).
struct ServoSpec {
  int motor;
  int pin;
  int64_t zero_ticks;
};

// An input driven from outside (a wire from another arm, a device): header pin `pin` reads
// `level` from `at_s` seconds of simulated time on (before the first one, its pull-up).
struct InputSpec {
  int pin;
  int level;
  double at_s;
};

// A header pin by its name ("D9", "A3": board.h's header_index), or -1.
int header_pin(const std::string& name);

struct Config {
  std::string elf;
  // The ELF is the servo build (articula-servo.elf): these motors are servos.
  std::vector<ServoSpec> servos;
  std::vector<EndstopSpec> endstops;
  std::vector<InputSpec> inputs;  // in time order
  std::vector<int> outputs;       // header pins whose level the report follows (O's)
  std::vector<int> half_step_motors;
  bool unipolar = false;       // the motors are 28BYJ-48s on ULN2003 boards (the unipolar table)
  // The ELF is the build for a CNC shield (articula-cnc.elf): the motors are on STEP/DIR
  // drivers in its sockets, the endstops and the servo on the shield's pins (board.h).
  bool cnc_shield = false;
  bool gripper_range = false;  // servo_closed_deg/servo_open_deg given: report the aperture
  double servo_closed_deg = 0, servo_open_deg = 0;
  FILE* trace = nullptr;       // CSV of coil events, or null
  // Lines from the host go in one at a time: the next one starts on the wire when the reply
  // to the one before (ok or error:N) has been sent whole, as a host that waits for each
  // reply with no time of its own would send them (the prediction's `stream` sender).
  bool paced = false;
  // A '!' at each of these times, seconds after the first step (a coil change), sent
  // whatever the lines are doing (`articula predict --stop-at`). Increasing.
  std::vector<double> stop_at_s;
};

class VirtualNano {
 public:
  static const int kMotors = 3;

  VirtualNano() = default;
  ~VirtualNano();
  VirtualNano(const VirtualNano&) = delete;
  VirtualNano& operator=(const VirtualNano&) = delete;

  // Reads the ELF, makes the MCU it names, hooks every probe, paints the stack.
  bool load(const Config& config, std::string& error);

  // Runs instructions until the cycle count reaches `cycle` or the CPU stops.
  void run_until(uint64_t cycle);
  bool halted() const { return halted_; }
  const char* cpu_state() const;

  uint64_t cycle() const;
  uint32_t frequency() const { return freq_; }
  const std::string& mcu() const { return mcu_; }

  // Serial, host side. Bytes from the host wait here and go to the USART one at a time.
  void host_send(const char* data, size_t n);
  size_t host_pending() const { return host_in_.size() + held_lines_.size() + partial_in_.size(); }
  // Paced: a line released to the firmware still waits for its reply (a T line's check may
  // keep the firmware silent for longer than the end-of-input quiet time).
  bool awaiting_reply() const { return paced_ && replies_sent_ < lines_released_; }
  // Bytes the firmware sent; the caller erases what it has passed on.
  std::string& output() { return out_; }
  // Nothing waits to reach the firmware (our queue and simavr's receive FIFO are empty).
  bool serial_idle() const;
  bool step_timer_led() const { return led_; }
  // Cycle of the last byte out, coil change or LED change.
  uint64_t last_activity() const { return last_activity_; }

  // Ends open measurements and scans the painted stack. Call once, before report().
  void finish();
  nlohmann::json report() const;
  std::string summary() const;

  // simavr notifications (C callbacks; public for the trampolines in vnano.cpp).
  void on_port_write(int port, uint8_t value);
  void on_uart_output(uint8_t byte);
  void on_uart_xon();
  void on_uart_xoff(bool off);
  void on_vector_pending(int vector, bool raised);
  void on_vector_running(int vector, bool running);
  // Paced input: the reply's LF is off the wire, the next line may go.
  void on_reply_sent();
  // A timed '!' is due (Config::stop_at_s); the cycle the next one is, 0 if none.
  uint64_t on_stop_due();
  // The next driven input's change is due (Config::inputs); the cycle the one after is, 0 if none.
  uint64_t on_input_due();

 private:
  void schedule_stop();
  struct Motor;
  std::string inputs_string(const Motor& m) const;
  uint64_t next_stop_cycle() const;
  // An interrupts-off stretch ends now: keep it if it is the longest so far.
  void end_irq_off();
  struct Motor {
    int index = 0;
    int port = 0;  // 0 B, 1 C, 2 D
    int shift = 0;
    CoilDecoder decoder;
    // On a CNC shield: the driver in the motor's socket, its STEP and DIR bits (on `port`).
    bool step_dir = false;
    int step_bit = 0, dir_bit = 0;
    StepDirDecoder driver;
    // A hobby servo: its signal pin (port `port`, bit servo_bit) and what its pulses ask for.
    bool servo = false;
    int servo_pin = 0, servo_bit = 0;  // board.h's header index, its bit
    ServoDecoder pulses;
    Stat width_us;
    int64_t steps() const { return servo ? pulses.position() : step_dir ? driver.steps() : decoder.steps(); }
    uint64_t step_events = 0, forward = 0, backward = 0, full_steps = 0, half_steps = 0;
    uint64_t releases = 0, energisations = 0, faults = 0;
    struct Fault {
      uint64_t cycle;
      uint8_t from, to, reference;
      FaultKind kind;
    };
    std::vector<Fault> fault_list;  // the first 100
    bool have_last = false;
    uint64_t last_step_cycle = 0, last_epoch = 0;
    Stat interval_us;
    // Step time against its timer deadline (see README.md, "jitter").
    Stat delay_us;
    Stat interval_error_us;  // |delay(k) - delay(k-1)| of consecutive steps of one run
    uint64_t errors_over_10us = 0;
    bool have_last_delay = false;
    double last_delay_us = 0;
    uint64_t unattributed = 0;  // steps not made inside the Timer1 COMPA interrupt
  };
  struct Endstop {
    int motor;
    int port;
    int bit;
    int64_t closes_at;
    bool pressed = false;
    uint64_t presses = 0;
    uint64_t first_press_cycle = 0;
    int64_t pressed_at_steps = 0;
  };
  struct VectorStat {
    bool hooked = false;
    uint64_t entries = 0;
    Stat latency_us;    // flag raised -> first instruction of the vector
    Stat inclusive_us;  // entry -> RETI, nested interrupts included
    Stat exclusive_us;  // the same without the nested interrupts
    bool pending = false;
    uint64_t pending_cycle = 0;
  };
  struct Frame {
    int vector;
    uint64_t start, nested;
  };

  void step_event(Motor& m, const CoilChange& c, uint8_t pattern);
  void trace_row(const Motor& m, const char* event);
  void apply_external(int port);
  void check_endstops(int motor);
  void try_inject();
  void sync_uart_frame();
  int timer1_prescale() const;
  void calibrate_timer1(uint16_t ocr);
  bool step_deadline(uint64_t now, uint64_t& deadline) const;
  bool in_vector(int vector) const;
  double us(double cycles) const { return cycles * 1e6 / double(freq_); }

  Config config_;
  avr_t* avr_ = nullptr;
  std::string mcu_;
  uint32_t freq_ = 16000000;
  bool halted_ = false;
  ElfSymbols syms_;

  // serial
  avr_uart_t* uart_ = nullptr;
  avr_irq_t* uart_in_ = nullptr;
  bool xoff_ = false, injecting_ = false;
  std::deque<uint8_t> host_in_;
  // Paced input (Config::paced): whole lines held back, replies seen, the line being read out.
  std::deque<std::string> held_lines_;
  std::string partial_in_, line_out_;
  uint64_t lines_released_ = 0, replies_sent_ = 0;
  std::vector<double> stop_at_s_;
  size_t stops_sent_ = 0;
  bool first_step_seen_ = false;
  uint64_t first_step_cycle_ = 0;  // the first coil step
  bool paced_ = false;
  void release_line();
  std::string out_;
  uint64_t bytes_in_ = 0, bytes_out_ = 0;
  uint64_t lines_in_ = 0;  // LFs the host sent (the trace's `line` rows count them)
  uint64_t frame_cycles_ = 0, simavr_frame_cycles_ = 0;
  // '?': arrival cycles of status requests not yet answered; the reply being sent.
  std::deque<uint64_t> status_waiting_;
  uint64_t status_requests_ = 0, status_replies_ = 0;
  bool in_status_line_ = false, line_start_ = true;
  uint64_t status_t0_ = 0;
  Stat status_first_us_, status_end_us_;
  uint64_t status_answered_together_ = 0;  // requests answered by a report that answered an older one
  struct StatusReply {
    uint64_t request, first, end;
  };
  std::vector<StatusReply> status_list_;  // the first 200

  // pins
  Motor motors_[kMotors];
  uint8_t port_value_[3] = {0, 0, 0};
  std::vector<Endstop> endstops_;
  // Driven inputs: the next change due, and each pin's level now (bit n header pin n).
  size_t inputs_applied_ = 0;
  uint32_t driven_ = 0, driven_high_ = 0;
  uint64_t input_cycle(size_t k) const;
  // Followed outputs: each change of the pin's level (its PORT bit: the output's level, or
  // an input's pull-up), at its cycle.
  struct OutputChange {
    int pin;
    int level;
    uint64_t cycle;
  };
  std::vector<OutputChange> output_changes_;
  int output_level_[32] = {};
  avr_irq_t* pin_irq_[3][8] = {};
  bool led_ = false;
  uint64_t epoch_ = 0;  // step timer runs (LED lit) so far
  uint64_t last_activity_ = 0;
  std::deque<uint64_t> window_;  // step cycles of every motor in the last 10 ms
  size_t peak_window_ = 0;

  // servo
  bool servo_high_ = false, have_rise_ = false;
  uint64_t servo_rise_ = 0, last_rise_ = 0;
  Stat servo_width_us_, servo_period_us_;
  std::map<uint64_t, uint64_t> servo_widths_;  // width in cycles -> pulses
  double last_width_us_ = 0;

  // Timer1: the cycle at which TCNT1 was 0, modulo a lap (from compare flag raises).
  bool cal_valid_ = false;
  int cal_prescale_ = 0;
  int64_t cal_phase_ = 0;
  uint64_t cal_accepted_ = 0, cal_outliers_ = 0;
  int cal_streak_ = 0;

  // interrupts
  VectorStat vectors_[64];
  std::vector<Frame> running_;
  uint64_t running_mismatch_ = 0;
  bool seen_sei_ = false, irq_off_ = false;
  uint64_t irq_off_start_ = 0;
  uint32_t irq_off_pc_ = 0;
  double irq_off_max_us_ = 0;
  uint32_t irq_off_max_pc_ = 0;
  uint64_t irq_off_max_cycle_ = 0;
  void* vector_ptr_[64] = {};  // simavr's avr_int_vector_t of each vector number
 public:
  // The parameter of a simavr notification: which object, which port or vector.
  struct Hook {
    VirtualNano* self;
    int index;
  };

 private:
  Hook port_hooks_[3] = {};
  Hook vector_hooks_[64] = {};
  // The byte in simavr's receive FIFO: when it was complete at the receiver.
  bool rx_outstanding_ = false;
  uint64_t rx_arrival_ = 0;
  Stat rx_wait_us_;
  uint64_t rx_overrun_risk_ = 0;

  // stack
  uint16_t static_end_ = 0, ramend_ = 0;
  uint16_t min_sp_ = 0xFFFF;
  uint64_t slept_cycles_ = 0;
  uint64_t dbg_sleeps_ = 0;  // cycles the CPU spent asleep (the firmware's idle), jumped over
  uint32_t min_sp_pc_ = 0;
  bool finished_ = false;
  int lowest_touched_ = -1;  // lowest painted byte overwritten, -1 none
};

}  // namespace vnano

#endif  // ARTICULA_HIL_VNANO_VNANO_H
