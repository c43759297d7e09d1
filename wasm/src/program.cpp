// wasm/src/program.cpp - programs for JavaScript (the twin of python/src/program.cpp): the
// firmware on its virtual clock (`articula predict --json`), the kinematic model (`run --json`), protocol
// lines through the firmware's arithmetic (`quantize --json`), and a program's time line.
#include <emscripten/bind.h>

#include "blocks.h"
#include "draw.h"
#include "predict.h"
#include "records_json.h"
#include "quantize.h"
#include "robot.h"
#include "run.h"
#include "timeline.h"

namespace articula::web {

std::string predict(const WebRobot& robot, const std::string& text, const std::string& name, const std::string& settings) {
  return guarded([&] {
    const Robot& r = robot.robot();
    if (!r.has_motors)
      throw std::invalid_argument(r.name + " has no motors: there are no steps to predict (run executes programs "
                                           "on the kinematic model)");
    const host::Program p = host::parse_program(text, name, r);
    host::ControllerSettings s;
    if (!settings.empty()) host::apply_settings_text(s, settings, r.actuation.num_motors);
    return host::prediction_json(r, p, host::predict_program(r, p, s)).dump();
  });
}

std::string run(const WebRobot& robot, const std::string& text, const std::string& name) {
  return guarded([&] {
    const host::Program p = host::parse_program(text, name, robot.robot());
    return host::run_json(robot.robot(), p, host::run_program(robot.robot(), p)).dump();
  });
}

std::string quantize(const WebRobot& robot, const std::string& lines_json) {
  return guarded([&] {
    const Robot& r = robot.robot();
    if (!r.has_motors) throw std::invalid_argument(r.name + " has no motors: nothing to quantize");
    json out = json::array();
    for (const auto& q : host::quantize_lines(r, json::parse(lines_json).get<std::vector<std::string>>()))
      out.push_back(host::quantize_record_json(r, q));
    return out.dump();
  });
}

// A program as the parser reads it (host::program_json): the studio opens it as blocks.
std::string parse_program(const WebRobot& robot, const std::string& text, const std::string& name) {
  return guarded([&] {
    const Robot& r = robot.robot();
    return host::program_json(r, host::parse_program(text, name, r), text).dump();
  });
}

// Whether a program fits the robot (host::program_fit): {fits, other_arm, line, problem}.
std::string program_fit(const WebRobot& robot, const std::string& text, const std::string& name) {
  return guarded([&] { return host::program_fit_json(host::program_fit(text, name, robot.robot())).dump(); });
}

// Blocks to a program and back, and the protocol's one line formatter (host/lib/blocks.h).
std::string blocks_program(const WebRobot& robot, const std::string& ops_json) {
  return guarded([&] { return host::blocks_program_json(robot.robot(), robot.ik(), json::parse(ops_json)).dump(); });
}
std::string program_actions(const WebRobot& robot, const std::string& text, const std::string& name) {
  return guarded([&] { return host::program_actions_json(robot.robot(), text, name).dump(); });
}
std::string protocol_line(const WebRobot& robot, const std::string& word, const std::string& values_json) {
  return guarded([&] {
    if (word.size() != 1) throw std::invalid_argument("a protocol command is one letter");
    return json(host::protocol_line(robot.robot(), word[0], numbers(json::parse(values_json), "values"))).dump();
  });
}
std::string move_line(const WebRobot& robot, const std::string& q_json) {
  return guarded([&] { return json(host::move_line(robot.robot(), numbers(json::parse(q_json), "q"))).dump(); });
}

// A drawing for a pen in the gripper (host/lib/draw.h): the request as JSON, the drawing's JSON.
std::string drawing(const WebRobot& robot, const std::string& request_json) {
  return guarded([&] {
    return host::drawing_with_ink_json(robot.robot(), robot.ik(), host::draw_request_from_json(json::parse(request_json))).dump();
  });
}

// The ink a virtual Nano's steps leave (host/lib/draw.h): {steps, z, pen, lift} -> {strokes, points}.
std::string ink(const WebRobot& robot, const std::string& request_json) {
  return guarded([&] { return host::ink_json(robot.robot(), json::parse(request_json)).dump(); });
}

// Where on a sheet the pen reaches the paper (host/lib/draw.h): {area, cell, z, pen} -> the map.
std::string reach_map(const WebRobot& robot, const std::string& request_json) {
  return guarded([&] { return host::reach_map_json(robot.robot(), robot.ik(), json::parse(request_json)).dump(); });
}

// A program's ink against a drawing exercise's target (host/lib/draw.h).
std::string drawing_check(const WebRobot& robot, const std::string& request_json) {
  return guarded([&] { return host::drawing_check_json(robot.robot(), robot.ik(), json::parse(request_json)).dump(); });
}

std::string program_format(const std::string& text, const std::string& name) {
  return host::detect_format(text, name) == host::Program::Format::kRoboSim ? "robosim" : "protocol";
}

// A program's time line (host/lib/timeline.h), as the studio plays it: made from a program
// on a robot, then asked for the arm at any instant.
class WebTimeline {
 public:
  // A prediction (a robot with motors) or a run from start_q (deg or mm; without motors):
  // the time line's JSON ({start_q, duration, summary, records}), or {"error", "line"}.
  std::string make(const WebRobot& robot, const std::string& text, const std::string& name, const std::string& start_json) {
    return guarded([&] {
      if (!robot.loaded()) throw std::invalid_argument("no robot loaded");
      const Robot& r = *robot.shared();
      const std::vector<double> start = host::joints_out(r, host::joints_in(r, numbers(json::parse(start_json), "start"), "start").data());
      const host::Program p = host::parse_program(text, name, r);
      auto tl = std::make_unique<host::Timeline>(host::Timeline::of_program(r, p, start));
      json out = host::timeline_json(*tl);
      out["samples"] = host::timeline_samples_json(r, *tl);
      out["format"] = p.format == host::Program::Format::kRoboSim ? "robosim" : "protocol";
      tl_ = std::move(tl);
      return out.dump();
    });
  }
  // The arm at time t: {t, line, q, q_ideal, steps, error_mm, gripper}.
  std::string at(double t) const {
    return guarded([&] {
      if (!tl_) throw std::invalid_argument("no program: make the time line first");
      return host::timeline_pose_json(tl_->at(t)).dump();
    });
  }
  double duration() const { return tl_ ? tl_->duration() : 0.0; }

 private:
  std::unique_ptr<host::Timeline> tl_;
};

}  // namespace articula::web

EMSCRIPTEN_BINDINGS(articula_program) {
  using namespace emscripten;
  using articula::web::WebTimeline;
  function("predict", &articula::web::predict);
  function("run", &articula::web::run);
  function("quantize", &articula::web::quantize);
  function("parseProgram", &articula::web::parse_program);
  function("programFormat", &articula::web::program_format);
  function("programFit", &articula::web::program_fit);
  function("blocksProgram", &articula::web::blocks_program);
  function("programActions", &articula::web::program_actions);
  function("protocolLine", &articula::web::protocol_line);
  function("moveLine", &articula::web::move_line);
  function("drawing", &articula::web::drawing);
  function("ink", &articula::web::ink);
  function("reachMap", &articula::web::reach_map);
  function("drawingCheck", &articula::web::drawing_check);
  function("penFields", +[] { return articula::host::pen_fields_json().dump(); });
  class_<WebTimeline>("Timeline")
      .constructor<>()
      .function("make", &WebTimeline::make)
      .function("at", &WebTimeline::at)
      .function("duration", &WebTimeline::duration);
}
