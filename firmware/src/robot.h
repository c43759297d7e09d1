// firmware/src/robot.h - the arm this firmware drives: robot_config.h (generated from the
// robot file by tools/robot_config.py) turned into the core's structures at start-up, so
// every computation on them is the shared core's, as on the host.
#ifndef ARTICULA_FIRMWARE_ROBOT_H
#define ARTICULA_FIRMWARE_ROBOT_H

#include <articula/actuation.h>
#include <articula/ik_ypp.h>

#include "robot_config.h"

namespace robot {

static const uint8_t kJoints = ARTICULA_NUM_JOINTS;
static_assert(kJoints >= 1 && kJoints <= 3, "the Nano's pin map wires one to three motors");

typedef articula::Actuation<float, kJoints> Actuation;
typedef articula::MotorState<kJoints> State;

// The motors and how they drive the joints (coupling_inv is not used: left zero).
extern const Actuation actuation;
// P's inverse kinematics: the arm as a yaw-pitch-pitch arm with the motors' limits. Only
// when has_ik: the robot is of that family and its coupling is the identity or the MK2's
// parallelogram (ypp_limits_from_actuation).
extern articula::YppArm<float> arm;
extern bool has_ik;
// The home pose as actuator angles (u = C^-1 q_home), and the steps they quantize to.
extern articula::Millideg home[kJoints];
extern int32_t home_steps[kJoints];

inline const articula::MotorSpec& motor(uint8_t i) { return actuation.motors[i]; }

// steps_to_millideg(motor(i), steps), the status report's A field: the same value, from a
// fraction reduced at setup, in 32-bit arithmetic for every step count it fits (all within
// the limits on the MK2), so a report costs no 64-bit division.
articula::Millideg step_angle(uint8_t i, int32_t steps);

// Once at start-up (and again when a test reboots the firmware).
void setup();

}  // namespace robot

#endif  // ARTICULA_FIRMWARE_ROBOT_H
