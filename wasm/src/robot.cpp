// wasm/src/robot.cpp - articula's Robot for JavaScript (the twin of python/src/robot.cpp): the
// robot file, its description, poses, IK, motors, URDF, the hot paths.
#include <emscripten/bind.h>

#include "robot.h"

EMSCRIPTEN_BINDINGS(articula_robot) {
  using namespace emscripten;
  using articula::web::WebRobot;
  class_<WebRobot>("Robot")
      .constructor<>()
      .function("load", &WebRobot::load)
      .function("parse", &WebRobot::parse)
      .function("fromLegacy", &WebRobot::from_legacy)
      .function("setLinkLengths", &WebRobot::set_link_lengths)
      .function("loaded", &WebRobot::loaded)
      .function("info", &WebRobot::info)
      .function("nanoConfig", &WebRobot::nano_config)
      .function("pose", &WebRobot::pose)
      .function("jacobian", &WebRobot::jacobian)
      .function("ik", &WebRobot::ik_solve)
      .function("urdf", &WebRobot::urdf)
      .function("jointsFromMotors", &WebRobot::joints_from_motors)
      .function("motorsFromJoints", &WebRobot::motors_from_joints)
      .function("scratch", &WebRobot::scratch)
      .function("fkScratch", &WebRobot::fk_scratch)
      .function("ikScratch", &WebRobot::ik_scratch);
}
