// firmware/src/pins.h - every pin of the Nano, in this one file (GRBL's cpu_map.h idea).
//
// Only hal_avr.cpp includes it. Each motor's four L298N inputs IN1..IN4 sit on four bits of
// ONE port, so a new coil pattern is one port write and the four pins change on the same
// clock cycle (digitalWrite would spread them over about 76 cycles, and a pin monitor would
// see three intermediate patterns). The bits are consecutive, so pattern bit 0 (IN1) goes to
// bit ARTICULA_MOTORn_SHIFT and a shift places the whole pattern.
//
//   Nano pin  AVR pin  use
//   D0, D1    PD0,PD1  USB serial (RX, TX)
//   D2        PD2      endstop 0 (base), to GND when pressed
//   D3        PD3      gripper servo signal (pulses made in software from Timer1 COMPB)
//   D4..D7    PD4..7   motor 0 (base):     IN1..IN4 of L298N #0
//   D8..D11   PB0..3   motor 1 (shoulder): IN1..IN4 of L298N #1
//   D12       PB4      endstop 1 (shoulder)
//   D13       PB5      on-board LED
//   A0..A3    PC0..3   motor 2 (elbow):    IN1..IN4 of L298N #2
//   A4        PC4      endstop 2 (elbow)
//   A5        PC5      free
//   A6, A7    -        analog inputs only: free
//
// No conflict with the timers: Timer0 (millis) drives no pin; Timer1's compare outputs OC1A
// (D9) and OC1B (D10) stay disconnected (COM1x = 0), so D9 and D10 are plain port bits; Timer2
// is unused. D11..D13 are also the ISP header's MOSI/MISO/SCK: unplug the L298N inputs before
// flashing through ISP (the USB bootloader does not touch them).
#ifndef ARTICULA_FIRMWARE_PINS_H
#define ARTICULA_FIRMWARE_PINS_H

#include <avr/io.h>

// ---- stepper motors: four L298N inputs each, on four consecutive bits of one port ----
#define ARTICULA_NUM_MOTOR_PORTS 3

#define ARTICULA_MOTOR0_PORT PORTD  // base: D4..D7
#define ARTICULA_MOTOR0_DDR DDRD
#define ARTICULA_MOTOR0_SHIFT 4

#define ARTICULA_MOTOR1_PORT PORTB  // shoulder: D8..D11
#define ARTICULA_MOTOR1_DDR DDRB
#define ARTICULA_MOTOR1_SHIFT 0

#define ARTICULA_MOTOR2_PORT PORTC  // elbow: A0..A3
#define ARTICULA_MOTOR2_DDR DDRC
#define ARTICULA_MOTOR2_SHIFT 0

#define ARTICULA_COIL_MASK(shift) (uint8_t(0x0F) << (shift))

// ---- gripper servo ----
#define ARTICULA_SERVO_PORT PORTD  // D3
#define ARTICULA_SERVO_DDR DDRD
#define ARTICULA_SERVO_BIT PD3

// ---- endstops: switch to GND, internal pull-up, so pressed reads 0 ----
#define ARTICULA_ENDSTOP0_PIN PIND  // D2
#define ARTICULA_ENDSTOP0_PORT PORTD
#define ARTICULA_ENDSTOP0_DDR DDRD
#define ARTICULA_ENDSTOP0_BIT PD2

#define ARTICULA_ENDSTOP1_PIN PINB  // D12
#define ARTICULA_ENDSTOP1_PORT PORTB
#define ARTICULA_ENDSTOP1_DDR DDRB
#define ARTICULA_ENDSTOP1_BIT PB4

#define ARTICULA_ENDSTOP2_PIN PINC  // A4
#define ARTICULA_ENDSTOP2_PORT PORTC
#define ARTICULA_ENDSTOP2_DDR DDRC
#define ARTICULA_ENDSTOP2_BIT PC4

// ---- on-board LED ----
#define ARTICULA_LED_PORT PORTB  // D13
#define ARTICULA_LED_DDR DDRB
#define ARTICULA_LED_BIT PB5

// ---- serial: USART0 on D0/D1 (the USB bridge) ----
#define ARTICULA_SERIAL_BAUD 115200UL

#endif  // ARTICULA_FIRMWARE_PINS_H
