// firmware/src/board.h - every pin of the Nano, in this one table (GRBL's cpu_map.h idea).
// The firmware's registers come from it (pins.h); both emulated Nanos read the pins by it
// (simavr's in virtual-nano/simavr, the page's avr8js through the nano decoder module, virtual-nano/web/nano_parts.cpp).
// Plain C++11 with no AVR header, so the host compiles it too.
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
// Each motor's four L298N inputs IN1..IN4 sit on four consecutive bits of ONE port, so a new
// coil pattern is one port write and the four pins change on the same clock cycle
// (digitalWrite would spread them over about 76 cycles, and a pin monitor would see three
// intermediate patterns): pattern bit 0 (IN1) goes to bit `shift`.
//
// No conflict with the timers: Timer0 (millis) drives no pin; Timer1's compare outputs OC1A
// (D9) and OC1B (D10) stay disconnected (COM1x = 0), so D9 and D10 are plain port bits; Timer2
// is unused (hal::init stops it, and the ADC). D11..D13 are also the ISP header's
// MOSI/MISO/SCK: unplug the L298N inputs before flashing through ISP (the USB bootloader does
// not touch them).
#ifndef ARTICULA_FIRMWARE_BOARD_H
#define ARTICULA_FIRMWARE_BOARD_H

namespace board {

// The ports, by index: 0 B, 1 C, 2 D.
enum Port { kPortB = 0, kPortC = 1, kPortD = 2 };
constexpr char kPortNames[3] = {'B', 'C', 'D'};
// Their registers' I/O addresses on the ATmega328P (PINx, DDRx, PORTx are three in a row).
constexpr int pin_io(int port) { return 0x03 + 3 * port; }
constexpr int ddr_io(int port) { return 0x04 + 3 * port; }
constexpr int port_io(int port) { return 0x05 + 3 * port; }

struct MotorPins {
  int port, shift;  // IN1..IN4 on bits shift..shift+3 of the port
  const char* pins;
};
constexpr int kWiredMotors = 3;
constexpr MotorPins kMotorPins[kWiredMotors] = {
    {kPortD, 4, "PD4..PD7 (D4..D7)"}, {kPortB, 0, "PB0..PB3 (D8..D11)"}, {kPortC, 0, "PC0..PC3 (A0..A3)"}};

struct Pin {
  int port, bit;
  const char* pin;
};
constexpr Pin kEndstopPins[kWiredMotors] = {{kPortD, 2, "PD2 (D2)"}, {kPortB, 4, "PB4 (D12)"}, {kPortC, 4, "PC4 (A4)"}};
constexpr Pin kServoPin = {kPortD, 3, "PD3 (D3)"};
constexpr Pin kLedPin = {kPortB, 5, "PB5 (D13)"};

constexpr unsigned long kSerialBaud = 115200UL;  // USART0 on D0/D1 (the USB bridge)

}  // namespace board

#endif  // ARTICULA_FIRMWARE_BOARD_H
