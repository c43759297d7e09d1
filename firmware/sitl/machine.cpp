// firmware/sitl/machine.cpp - the Nano's main loop and interrupts on the virtual clock.
#include "machine.h"

#include <articula/config.h>
#include <articula/protocol.h>

#include <cstring>
#include <deque>

#include "firmware.h"
#include "hal.h"
#include "queue.h"
#include "robot.h"
#include "stepper.h"

namespace sitl {

namespace {
std::string g_partial;  // output not yet ended by an LF
std::vector<std::string> g_lines;
std::vector<std::string> g_reports;
size_t g_tx_seen = 0;

// The serial line from the host: bytes with the tick each arrives, in order.
struct Arrival {
  uint64_t tick;
  char c;
};
std::deque<Arrival> g_line;
uint64_t g_line_free = 0;  // when the last frame sent is in

void collect() {
  const std::string& tx = sitl::hw.tx;
  for (; g_tx_seen < tx.size(); ++g_tx_seen) {
    const char c = tx[g_tx_seen];
    if (c == '\n') {
      g_lines.push_back(g_partial);
      g_partial.clear();
    } else {
      g_partial.push_back(c);
    }
  }
}

bool is_reply(const std::string& s) { return s == "ok" || s.rfind("error:", 0) == 0; }
}  // namespace

void boot(bool blank_eeprom, const std::string& during_setup, const uint8_t* config) {
  sitl::reset(blank_eeprom);
  if (config != nullptr) {
    // The arm as `articula configure ROBOT` would have left it in EEPROM.
    uint8_t* e = sitl::hw.eeprom + robot::kEepromAddress;
    if (blank_eeprom || e[0] != robot::kEepromVersion) {
      const uint16_t crc = articula::config_checksum(config);
      e[0] = robot::kEepromVersion;
      std::memcpy(e + 1, config, articula::kConfigImageSize);
      e[1 + articula::kConfigImageSize] = uint8_t(crc);
      e[2 + articula::kConfigImageSize] = uint8_t(crc >> 8);
    }
  }
  g_partial.clear();
  g_lines.clear();
  g_reports.clear();
  g_tx_seen = 0;
  g_line.clear();
  g_line_free = 0;
  hal::init();  // as main.cpp
  for (char c : during_setup) sitl::receive(c);
  firmware::setup();
  for (int i = 0; i < robot::kJoints; ++i) sitl::hw.microsteps[i] = robot::actuation().motors[i].microsteps;
  hal::start();
}

void send(const std::string& bytes) {
  for (char c : bytes) sitl::receive(c);
}

uint64_t send_at(uint64_t tick, const std::string& bytes) {
  uint64_t t = tick < sitl::hw.now ? sitl::hw.now : tick;
  if (t < g_line_free) t = g_line_free;
  for (char c : bytes) {
    t += kByteTicks;
    g_line.push_back(Arrival{t, c});
  }
  g_line_free = t;
  return t;
}

size_t on_the_line() { return g_line.size(); }

void tick() {
  Hardware& hw = sitl::hw;
  firmware::poll();
  const uint64_t end = hw.now + kPollTicks;
  for (;;) {
    // The next event: a step deadline or a byte's arrival (a deadline first at the same tick:
    // the step timer's interrupt has the higher priority on the ATmega328P).
    const bool step = hw.timer_running && hw.deadline <= end;
    const bool byte = !g_line.empty() && g_line.front().tick <= end;
    if (!step && !byte) break;
    if (step && (!byte || hw.deadline <= g_line.front().tick)) {
      hw.now = hw.deadline;
      const uint32_t next = sitl::step_deadline();
      if (next == 0)
        hw.timer_running = false;
      else
        hw.deadline += next;
    } else {
      hw.now = g_line.front().tick;
      const char c = g_line.front().c;
      g_line.pop_front();
      sitl::receive(c);
    }
  }
  hw.now = end;
  collect();
}

bool run_until(const std::function<bool()>& done, uint64_t max_ticks) {
  const uint64_t end = sitl::hw.now + max_ticks;
  while (sitl::hw.now < end) {
    tick();
    if (done()) return true;
  }
  return false;
}

std::vector<std::string> take_lines() {
  collect();
  std::vector<std::string> out;
  out.swap(g_lines);
  return out;
}

std::string take_report() {
  collect();
  for (size_t i = 0; i < g_lines.size(); ++i) {
    if (!g_lines[i].empty() && g_lines[i][0] == '<') {
      const std::string l = g_lines[i];
      g_lines.erase(g_lines.begin() + long(i));
      return l;
    }
  }
  return "";
}

std::string command(const std::string& line, uint64_t max_ticks) {
  g_reports.clear();
  send(line + "\n");
  std::string reply;
  run_until(
      [&] {
        collect();
        while (!g_lines.empty() && reply.empty()) {
          const std::string l = g_lines.front();
          g_lines.erase(g_lines.begin());
          if (is_reply(l))
            reply = l;
          else
            g_reports.push_back(l);
        }
        return !reply.empty();
      },
      max_ticks);
  return reply;
}

const std::vector<std::string>& reports() { return g_reports; }

bool at_rest() {
  return !stepper::busy() && queue::empty() && !stepper::stop_requested() && !sitl::hw.timer_running;
}

bool run_until_at_rest(uint64_t max_ticks) {
  // Two passes at rest in a row: the queue may still hold actions a pass has not started.
  int quiet = 0;
  return run_until(
      [&] {
        quiet = at_rest() ? quiet + 1 : 0;
        return quiet >= 2;
      },
      max_ticks);
}

articula::MotionSettings motion_settings() { return stepper::motion_settings(); }

std::vector<Step> steps_of(int motor, uint64_t from_tick) {
  std::vector<Step> out;
  for (const sitl::CoilWrite& w : sitl::hw.coil_log)
    if (w.motor == motor && w.step != 0 && w.tick >= from_tick) out.push_back(Step{w.tick, w.step});
  return out;
}

std::string hal_errors() {
  std::string s;
  for (const std::string& e : sitl::hw.errors) s += e + "\n";
  return s;
}

}  // namespace sitl
