// firmware/src/pins.h - the registers of every pin of board.h (the one table of the Nano's
// wiring), as the macros hal_avr.cpp writes. Only hal_avr.cpp includes it. The addresses are
// constants, so each write is the same single instruction as with avr-libc's own names.
#ifndef ARTICULA_FIRMWARE_PINS_H
#define ARTICULA_FIRMWARE_PINS_H

#include <avr/io.h>

#include "board.h"

// board.h's table as constants: enumerators are compile-time values, so the table itself is
// never placed in the Nano's RAM, and each register access is one instruction.
namespace pins {
using namespace board;
enum : uint8_t {
  kMotor0Port = port_io(kMotorPins[0].port), kMotor0Ddr = ddr_io(kMotorPins[0].port), kMotor0Shift = kMotorPins[0].shift,
  kMotor1Port = port_io(kMotorPins[1].port), kMotor1Ddr = ddr_io(kMotorPins[1].port), kMotor1Shift = kMotorPins[1].shift,
  kMotor2Port = port_io(kMotorPins[2].port), kMotor2Ddr = ddr_io(kMotorPins[2].port), kMotor2Shift = kMotorPins[2].shift,
  kServoPort = port_io(kServoPin.port), kServoDdr = ddr_io(kServoPin.port), kServoBit = kServoPin.bit,
  kLedPort = port_io(kLedPin.port), kLedDdr = ddr_io(kLedPin.port), kLedBit = kLedPin.bit,
  kEnd0Pin = pin_io(kEndstopPins[0].port), kEnd0Port = port_io(kEndstopPins[0].port), kEnd0Ddr = ddr_io(kEndstopPins[0].port),
  kEnd0Bit = kEndstopPins[0].bit,
  kEnd1Pin = pin_io(kEndstopPins[1].port), kEnd1Port = port_io(kEndstopPins[1].port), kEnd1Ddr = ddr_io(kEndstopPins[1].port),
  kEnd1Bit = kEndstopPins[1].bit,
  kEnd2Pin = pin_io(kEndstopPins[2].port), kEnd2Port = port_io(kEndstopPins[2].port), kEnd2Ddr = ddr_io(kEndstopPins[2].port),
  kEnd2Bit = kEndstopPins[2].bit,
};
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
