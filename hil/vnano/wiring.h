// hil/vnano/wiring.h - the Nano's wiring (firmware/src/pins.h) as an emulated Nano reads it:
// which port bits the motors' L298N inputs, the endstops, the gripper's servo and the LED sit
// on. One table for both virtual Nanos, simavr's (vnano.cpp) and the page's (avr8js, through
// the web engine: wasm/src/engine.cpp). Ports: 0 B, 1 C, 2 D.
#ifndef ARTICULA_HIL_VNANO_WIRING_H
#define ARTICULA_HIL_VNANO_WIRING_H

namespace vnano {

constexpr char kPortNames[3] = {'B', 'C', 'D'};

struct MotorPins {
  int port, shift;  // IN1..IN4 on bits shift..shift+3 of the port
  const char* pins;
};
constexpr int kWiredMotors = 3;
constexpr MotorPins kMotorPins[kWiredMotors] = {
    {2, 4, "PD4..PD7 (D4..D7)"}, {0, 0, "PB0..PB3 (D8..D11)"}, {1, 0, "PC0..PC3 (A0..A3)"}};

struct EndstopPin {
  int port, bit;
  const char* pin;
};
constexpr EndstopPin kEndstopPins[kWiredMotors] = {{2, 2, "PD2 (D2)"}, {0, 4, "PB4 (D12)"}, {1, 4, "PC4 (A4)"}};

constexpr int kServoPort = 2, kServoBit = 3;  // PD3 (D3)
constexpr int kLedPort = 0, kLedBit = 5;      // PB5 (D13)

}  // namespace vnano

#endif  // ARTICULA_HIL_VNANO_WIRING_H
