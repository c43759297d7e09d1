// virtual-nano/web/nano_parts.cpp - the virtual Nano's parts for the page's emulated Nano (avr8js, in the
// studio's nano worker), through embind: a motor's coil decoder (virtual-nano/coil_decoder.h), STEP/DIR
// decoder (step_dir_decoder.h) or servo pulse decoder (servo_decoder.h),
// the board's pins (firmware/src/board.h) and the servo's scale (shared/articula/servo.h). The
// same code as simavr's virtual Nano (virtual-nano/simavr), in a module of its own, so the Nano's worker
// loads a few kilobytes, not the engine with ODE. No logic of its own.
#include <emscripten/bind.h>

#include <articula/motion.h>
#include <articula/servo.h>

#include <nlohmann/json.hpp>
#include <string>

#include "board.h"
#include "coil_decoder.h"
#include "servo_decoder.h"
#include "step_dir_decoder.h"

namespace articula::web {

// One stepper motor's four driver inputs (an L298N's, or a ULN2003's) as the emulated Nano sees them.
class WebCoilDecoder {
 public:
  // A new IN1..IN4 pattern (bit 0 = IN1): 0 no change, 1 a step, 2 released, 3 energised,
  // 4 a fault (a pattern the motor cannot follow).
  int feed(int pattern) {
    const vnano::CoilChange c = d_.feed(uint8_t(pattern));
    if (c.event == vnano::CoilEvent::kFault) ++faults_;
    return int(c.event);
  }
  void force_half_step() { d_.force_half_step(); }
  // A 28BYJ-48 on a ULN2003 (the unipolar table), before its first energised pattern.
  void set_unipolar(bool u) { d_.set_unipolar(u); }
  double steps() const { return double(d_.steps()); }
  double half_steps() const { return double(d_.half_steps()); }
  int faults() const { return faults_; }
  int pattern() const { return d_.pattern(); }

 private:
  vnano::CoilDecoder d_;
  int faults_ = 0;
};

// One STEP/DIR driver module (a CNC shield's socket) as the emulated Nano sees its pins.
class WebStepDirDecoder {
 public:
  // The STEP and DIR levels and whether the drivers are enabled, at a CPU cycle: 0 nothing,
  // 1 a step, 4 a fault (a STEP pulse while disabled). As WebCoilDecoder's feed.
  int feed(bool step, bool dir, bool enabled, double cycle) {
    const vnano::StepDirChange c = d_.feed(step, dir, enabled, uint64_t(cycle));
    return c.ignored ? 4 : c.delta != 0 ? 1 : 0;
  }
  double steps() const { return double(d_.steps()); }
  int faults() const { return int(d_.ignored()); }
  // The shortest STEP high time and DIR setup seen, in cycles (-1: none yet).
  double min_pulse_cycles() const { return cycles(d_.min_pulse_cycles()); }
  double min_dir_setup_cycles() const { return cycles(d_.min_dir_setup_cycles()); }

 private:
  static double cycles(uint64_t c) { return c == vnano::StepDirDecoder::kNone ? -1.0 : double(c); }
  vnano::StepDirDecoder d_;
};

// One hobby servo's signal pin as the emulated Nano sees it: its position in 0.5 us ticks less
// the width at step 0 (within one tick of the firmware's: servo_decoder.h).
class WebServoDecoder {
 public:
  WebServoDecoder(double cycles_per_tick, double zero_ticks) : d_(uint64_t(cycles_per_tick), int64_t(zero_ticks)) {}
  // The pin's level at a CPU cycle: 0 nothing, 1 a pulse that moved the position, 2 a pulse
  // within the deadband.
  int feed(bool level, double cycle) {
    const vnano::ServoChange c = d_.feed(level, uint64_t(cycle));
    if (c.pulse) last_width_cycles_ = double(c.cycles);
    return c.delta != 0 ? 1 : c.pulse ? 2 : 0;
  }
  double steps() const { return double(d_.position()); }
  double pulses() const { return double(d_.pulses()); }
  double last_width_cycles() const { return last_width_cycles_; }
  double max_off_cycles() const { return double(d_.max_off_cycles()); }
  int faults() const { return 0; }  // (a pulse of any width is a position: no illegal pattern)

 private:
  vnano::ServoDecoder d_;
  double last_width_cycles_ = 0;
};

// A header pin by name ("D9", "A3"): {port, bit}, or null.
std::string header_pin(const std::string& name) {
  const int k = board::header_index(name.c_str());
  if (k < 0) return "null";
  return nlohmann::json{{"port", std::string(1, board::kPortNames[board::kHeaderPin[k].port])},
                        {"bit", board::kHeaderPin[k].bit}}
      .dump();
}

// The board's pins: ports "B", "C", "D"; motors [{port, shift}] (on a CNC shield [{port, step,
// dir}] and enable {port, bit}), endstops [{port, bit}], servo and led {port, bit}.
std::string board_wiring(bool cnc) {
  using nlohmann::json;
  auto port = [](int p) { return std::string(1, board::kPortNames[p]); };
  auto pin = [&](const board::Pin& p) { return json{{"port", port(p.port)}, {"bit", p.bit}}; };
  json motors = json::array(), endstops = json::array();
  for (int m = 0; m < board::kWiredMotors; ++m) {
    if (cnc) {
      const board::Socket& s = board::kShieldSocket[m];
      motors.push_back({{"port", port(s.step.port)}, {"step", s.step.bit}, {"dir", s.dir.bit}});
      endstops.push_back(pin(board::kShieldEndstopPins[m]));
    } else {
      motors.push_back({{"port", port(board::kMotorPins[m].port)}, {"shift", board::kMotorPins[m].shift}});
      endstops.push_back(pin(board::kEndstopPins[m]));
    }
  }
  json out = {{"motors", motors},
              {"endstops", endstops},
              {"servo", pin(cnc ? board::kShieldServoPin : board::kServoPin)},
              {"led", pin(board::kLedPin)}};
  if (cnc) out["enable"] = pin(board::kShieldEnable);
  return out.dump();
}

}  // namespace articula::web

EMSCRIPTEN_BINDINGS(articula_nano) {
  using namespace emscripten;
  using articula::web::WebCoilDecoder;
  class_<WebCoilDecoder>("CoilDecoder")
      .constructor<>()
      .function("feed", &WebCoilDecoder::feed)
      .function("forceHalfStep", &WebCoilDecoder::force_half_step)
      .function("setUnipolar", &WebCoilDecoder::set_unipolar)
      .function("steps", &WebCoilDecoder::steps)
      .function("halfSteps", &WebCoilDecoder::half_steps)
      .function("faults", &WebCoilDecoder::faults)
      .function("pattern", &WebCoilDecoder::pattern);
  using articula::web::WebStepDirDecoder;
  class_<WebStepDirDecoder>("StepDirDecoder")
      .constructor<>()
      .function("feed", &WebStepDirDecoder::feed)
      .function("steps", &WebStepDirDecoder::steps)
      .function("faults", &WebStepDirDecoder::faults)
      .function("minPulseCycles", &WebStepDirDecoder::min_pulse_cycles)
      .function("minDirSetupCycles", &WebStepDirDecoder::min_dir_setup_cycles);
  using articula::web::WebServoDecoder;
  class_<WebServoDecoder>("ServoDecoder")
      .constructor<double, double>()
      .function("feed", &WebServoDecoder::feed)
      .function("steps", &WebServoDecoder::steps)
      .function("pulses", &WebServoDecoder::pulses)
      .function("lastWidthCycles", &WebServoDecoder::last_width_cycles)
      .function("maxOffCycles", &WebServoDecoder::max_off_cycles)
      .function("faults", &WebServoDecoder::faults);
  function("headerPin", &articula::web::header_pin);
  constant("stepTickHz", articula::kStepTickHz);
  function("boardWiring", &articula::web::board_wiring);
  function("servoAngleDeg", +[](double us) { return articula::servo_angle_deg(us); });
  function("servoAperturePercent",
           +[](double angle, double closed, double open) { return articula::servo_aperture_percent(angle, closed, open); });
}
