// firmware/test/fake_hal.cpp - hal.h on the host, for the native tests.
#include "fake_hal.h"

#include <cstring>

#include "hal.h"

namespace fake {

Hardware hw;

namespace {
// The eight half-step states, IN1..IN4 written as bits 0..3. Written out here from the
// specification, not taken from the firmware: 1000 1010 0010 0110 0100 0101 0001 1001.
const uint8_t kHalfStep[8] = {0x1, 0x5, 0x4, 0x6, 0x2, 0xA, 0x8, 0x9};
}  // namespace

int sequence_index(uint8_t pattern) {
  for (int i = 0; i < 8; ++i)
    if (kHalfStep[i] == pattern) return i;
  return -1;
}

void reset(bool blank_eeprom) {
  uint8_t keep[sizeof hw.eeprom];
  std::memcpy(keep, hw.eeprom, sizeof keep);
  hw = Hardware();
  if (blank_eeprom)
    std::memset(hw.eeprom, 0xFF, sizeof hw.eeprom);
  else
    std::memcpy(hw.eeprom, keep, sizeof keep);
}

}  // namespace fake

using fake::hw;

namespace hal {

void init() {}

void write_coils(uint8_t motor, uint8_t pattern) {
  fake::CoilWrite w{hw.now, motor, pattern, 0};
  if (motor >= fake::kMotors || pattern > 0xF) {
    hw.errors.push_back("write_coils(" + std::to_string(motor) + ", " + std::to_string(pattern) + ")");
    hw.coil_log.push_back(w);
    return;
  }
  hw.pattern[motor] = pattern;
  if (pattern != 0) {
    const int index = fake::sequence_index(pattern);
    const bool full = hw.microsteps[motor] == 1;
    if (index < 0 || (full && index % 2 == 0)) {
      hw.errors.push_back("motor " + std::to_string(motor) + ": pattern " + std::to_string(pattern) +
                          " is not in its sequence");
    } else if (hw.last_index[motor] >= 0) {
      const int stride = full ? 2 : 1;
      const int diff = (index - hw.last_index[motor] + 8) % 8;
      if (diff == stride)
        w.step = 1;
      else if (diff == 8 - stride)
        w.step = -1;
      else if (diff != 0)
        hw.errors.push_back("motor " + std::to_string(motor) + ": jump of " + std::to_string(diff) + " places");
      hw.position[motor] += w.step;
    }
    if (index >= 0) hw.last_index[motor] = index;
  }
  hw.coil_log.push_back(w);
}

void set_servo_pulse(uint16_t microseconds) {
  hw.servo_us = microseconds;
  hw.servo_log.push_back(fake::ServoChange{hw.now, microseconds});
}

bool endstop(uint8_t motor) {
  if (motor >= fake::kMotors || !hw.endstop_fitted[motor]) return false;
  return hw.endstop_below[motor] ? hw.position[motor] <= hw.endstop_at[motor]
                                 : hw.position[motor] >= hw.endstop_at[motor];
}

void start_step_timer(uint32_t first_ticks) {
  if (first_ticks == 0) hw.errors.push_back("start_step_timer(0)");
  hw.timer_running = true;
  hw.deadline = hw.now + first_ticks;
}

void stop_step_timer() { hw.timer_running = false; }

bool step_timer_running() { return hw.timer_running; }

uint32_t millis() { return uint32_t(hw.now / (kTickHz / 1000)); }

int16_t serial_read() {
  if (hw.rx.empty()) return -1;
  const char c = hw.rx.front();
  hw.rx.pop_front();
  return int16_t(uint8_t(c));
}

void serial_write(char c) { hw.tx.push_back(c); }

void eeprom_read(uint16_t address, void* data, uint16_t size) {
  if (address + size > sizeof hw.eeprom) {
    hw.errors.push_back("eeprom_read beyond the EEPROM");
    return;
  }
  std::memcpy(data, hw.eeprom + address, size);
}

void eeprom_write(uint16_t address, const void* data, uint16_t size) {
  if (address + size > sizeof hw.eeprom) {
    hw.errors.push_back("eeprom_write beyond the EEPROM");
    return;
  }
  const uint8_t* p = static_cast<const uint8_t*>(data);
  for (uint16_t i = 0; i < size; ++i) {
    if (hw.eeprom[address + i] != p[i]) ++hw.eeprom_bytes_written;
    hw.eeprom[address + i] = p[i];
  }
}

uint8_t interrupts_off() {
  const uint8_t was_on = hw.interrupts_off_depth == 0;
  ++hw.interrupts_off_depth;
  return was_on;
}

void interrupts_restore(uint8_t state) {
  --hw.interrupts_off_depth;
  if (state && hw.interrupts_off_depth != 0) hw.errors.push_back("unbalanced interrupts_off/restore");
}

}  // namespace hal
