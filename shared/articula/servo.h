// articula/servo.h - the gripper's hobby servo: the aperture the protocol asks for (G, S) as
// the pulse width the firmware sends, and a pulse width read back as an angle and an
// aperture (what an emulated Nano sees on the servo's pin). One home for the Nano
// (firmware/src/gripper.cpp), the host (firmware/sitl runs the firmware's own) and both emulated
// Nanos (simavr's in virtual-nano/simavr, the page's through the web engine).
//
// The Arduino Servo library's scale: 544 us at 0 degrees, 2400 us at 180, linear between.
// The servo angle is linear in the aperture, from the robot file's servo_closed (0 %) to
// servo_open (100 %), limited to 0..180 degrees.
#ifndef ARTICULA_SERVO_H
#define ARTICULA_SERVO_H

#include "platform.h"

namespace articula {

static const uint16_t kServoPulseAt0Us = 544;
static const uint16_t kServoPulseAt180Us = 2400;

// The pulse width for an aperture in thousandths of a percent (0 .. 100000), rounded to the
// nearest microsecond. Computed in Scalar (float on the Nano, and in the host's model of it,
// so both round alike).
template <typename Scalar>
inline uint16_t servo_pulse_us(Scalar closed_deg, Scalar open_deg, int32_t aperture) {
  Scalar deg = closed_deg + (open_deg - closed_deg) * (Scalar(aperture) / Scalar(100000));
  deg = clamp(deg, Scalar(0), Scalar(180));
  return uint16_t(Scalar(kServoPulseAt0Us) + deg * (Scalar(kServoPulseAt180Us - kServoPulseAt0Us) / Scalar(180)) +
                  Scalar(0.5));
}

// The servo angle a pulse width asks for, degrees.
template <typename Scalar>
inline Scalar servo_angle_deg(Scalar width_us) {
  return (width_us - Scalar(kServoPulseAt0Us)) * Scalar(180) / Scalar(kServoPulseAt180Us - kServoPulseAt0Us);
}

// The aperture an angle gives, percent: 0 at servo_closed, 100 at servo_open.
template <typename Scalar>
inline Scalar servo_aperture_percent(Scalar angle_deg, Scalar closed_deg, Scalar open_deg) {
  return (angle_deg - closed_deg) * Scalar(100) / (open_deg - closed_deg);
}

}  // namespace articula

#endif  // ARTICULA_SERVO_H
