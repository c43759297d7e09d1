// firmware/src/pins.h - the registers of every pin of board.h (the one table of the boards'
// wiring), as the macros hal_avr.cpp writes. Only hal_avr.cpp includes it. The addresses are
// constants, so each write is the same single instruction as with avr-libc's own names.
#ifndef ARTICULA_FIRMWARE_PINS_H
#define ARTICULA_FIRMWARE_PINS_H

#include <avr/io.h>

#include "board.h"

// board.h's table as constants: enumerators are compile-time values, so the table itself is
// never placed in the Nano's RAM, and each register access is one instruction. The build for a
// CNC shield (ARTICULA_CNC_SHIELD) takes the shield's endstops and servo pin, and its STEP,
// DIR and EN pins; the 4-wire build the coil slots.
namespace pins {
using namespace board;
#if defined(ARTICULA_CNC_SHIELD)
constexpr const Pin* kEnds = kShieldEndstopPins;
constexpr Pin kServo = kShieldServoPin;
#else
constexpr const Pin* kEnds = kEndstopPins;
constexpr Pin kServo = kServoPin;
#endif
enum : uint8_t {
  kMotor0Port = port_io(kMotorPins[0].port), kMotor0Ddr = ddr_io(kMotorPins[0].port), kMotor0Shift = kMotorPins[0].shift,
  kMotor1Port = port_io(kMotorPins[1].port), kMotor1Ddr = ddr_io(kMotorPins[1].port), kMotor1Shift = kMotorPins[1].shift,
  kMotor2Port = port_io(kMotorPins[2].port), kMotor2Ddr = ddr_io(kMotorPins[2].port), kMotor2Shift = kMotorPins[2].shift,
  kServoPort = port_io(kServo.port), kServoDdr = ddr_io(kServo.port), kServoBit = kServo.bit,
  kLedPort = port_io(kLedPin.port), kLedDdr = ddr_io(kLedPin.port), kLedBit = kLedPin.bit,
  kEnd0Pin = pin_io(kEnds[0].port), kEnd0Port = port_io(kEnds[0].port), kEnd0Ddr = ddr_io(kEnds[0].port),
  kEnd0Bit = kEnds[0].bit,
  kEnd1Pin = pin_io(kEnds[1].port), kEnd1Port = port_io(kEnds[1].port), kEnd1Ddr = ddr_io(kEnds[1].port),
  kEnd1Bit = kEnds[1].bit,
  kEnd2Pin = pin_io(kEnds[2].port), kEnd2Port = port_io(kEnds[2].port), kEnd2Ddr = ddr_io(kEnds[2].port),
  kEnd2Bit = kEnds[2].bit,
  // The shield's sockets: the three STEP pins on consecutive bits of one port (motor i at
  // kStepShift + i), the three DIR pins likewise, EN on its own.
  kStepPort = port_io(kShieldSocket[0].step.port), kStepDdr = ddr_io(kShieldSocket[0].step.port),
  kStepShift = kShieldSocket[0].step.bit, kDirShift = kShieldSocket[0].dir.bit,
  kEnablePort = port_io(kShieldEnable.port), kEnableDdr = ddr_io(kShieldEnable.port), kEnableBit = kShieldEnable.bit,
};
static_assert(kShieldSocket[1].step.bit == kStepShift + 1 && kShieldSocket[2].step.bit == kStepShift + 2 &&
                  kShieldSocket[1].dir.bit == kDirShift + 1 && kShieldSocket[2].dir.bit == kDirShift + 2 &&
                  kShieldSocket[0].dir.port == kShieldSocket[0].step.port && kShieldSocket[2].step.port == kShieldSocket[0].step.port,
              "the STEP pins and the DIR pins: consecutive bits of one port, in socket order");
}  // namespace pins

// ---- stepper motors: four L298N inputs each, on four consecutive bits of one port ----
#define ARTICULA_NUM_MOTOR_PORTS 3
#define ARTICULA_MOTOR0_PORT _SFR_IO8(pins::kMotor0Port)
#define ARTICULA_MOTOR0_DDR _SFR_IO8(pins::kMotor0Ddr)
#define ARTICULA_MOTOR0_SHIFT (pins::kMotor0Shift)
#define ARTICULA_MOTOR1_PORT _SFR_IO8(pins::kMotor1Port)
#define ARTICULA_MOTOR1_DDR _SFR_IO8(pins::kMotor1Ddr)
#define ARTICULA_MOTOR1_SHIFT (pins::kMotor1Shift)
#define ARTICULA_MOTOR2_PORT _SFR_IO8(pins::kMotor2Port)
#define ARTICULA_MOTOR2_DDR _SFR_IO8(pins::kMotor2Ddr)
#define ARTICULA_MOTOR2_SHIFT (pins::kMotor2Shift)
#define ARTICULA_COIL_MASK(shift) (uint8_t(0x0F) << (shift))

// ---- STEP/DIR drivers (the build for a CNC shield) ----
#define ARTICULA_STEP_PORT _SFR_IO8(pins::kStepPort)
#define ARTICULA_STEP_DDR _SFR_IO8(pins::kStepDdr)
#define ARTICULA_STEP_SHIFT (pins::kStepShift)
#define ARTICULA_DIR_SHIFT (pins::kDirShift)
#define ARTICULA_ENABLE_PORT _SFR_IO8(pins::kEnablePort)
#define ARTICULA_ENABLE_DDR _SFR_IO8(pins::kEnableDdr)
#define ARTICULA_ENABLE_BIT (pins::kEnableBit)

// ---- gripper servo ----
#define ARTICULA_SERVO_PORT _SFR_IO8(pins::kServoPort)
#define ARTICULA_SERVO_DDR _SFR_IO8(pins::kServoDdr)
#define ARTICULA_SERVO_BIT (pins::kServoBit)

// ---- endstops: switch to GND, internal pull-up, so pressed reads 0 ----
#define ARTICULA_ENDSTOP0_PIN _SFR_IO8(pins::kEnd0Pin)
#define ARTICULA_ENDSTOP0_PORT _SFR_IO8(pins::kEnd0Port)
#define ARTICULA_ENDSTOP0_DDR _SFR_IO8(pins::kEnd0Ddr)
#define ARTICULA_ENDSTOP0_BIT (pins::kEnd0Bit)
#define ARTICULA_ENDSTOP1_PIN _SFR_IO8(pins::kEnd1Pin)
#define ARTICULA_ENDSTOP1_PORT _SFR_IO8(pins::kEnd1Port)
#define ARTICULA_ENDSTOP1_DDR _SFR_IO8(pins::kEnd1Ddr)
#define ARTICULA_ENDSTOP1_BIT (pins::kEnd1Bit)
#define ARTICULA_ENDSTOP2_PIN _SFR_IO8(pins::kEnd2Pin)
#define ARTICULA_ENDSTOP2_PORT _SFR_IO8(pins::kEnd2Port)
#define ARTICULA_ENDSTOP2_DDR _SFR_IO8(pins::kEnd2Ddr)
#define ARTICULA_ENDSTOP2_BIT (pins::kEnd2Bit)

// ---- on-board LED ----
#define ARTICULA_LED_PORT _SFR_IO8(pins::kLedPort)
#define ARTICULA_LED_DDR _SFR_IO8(pins::kLedDdr)
#define ARTICULA_LED_BIT (pins::kLedBit)

// ---- serial: USART0 on D0/D1 (the USB bridge) ----
#define ARTICULA_SERIAL_BAUD (board::kSerialBaud)

#endif  // ARTICULA_FIRMWARE_PINS_H
