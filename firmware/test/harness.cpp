// firmware/test/harness.cpp - the simulated main loop and interrupts.
#include "harness.h"

#include <gtest/gtest.h>

#include <cstring>

#include "firmware.h"
#include "hal.h"
#include "queue.h"
#include "stepper.h"
#ifdef ARTICULA_TEST_CONFIG
#include ARTICULA_TEST_CONFIG
#endif

namespace sim {

namespace {
std::string g_partial;  // output not yet ended by an LF
std::vector<std::string> g_lines;
std::vector<std::string> g_reports;
size_t g_tx_seen = 0;

void collect() {
  const std::string& tx = fake::hw.tx;
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

void boot(bool blank_eeprom, const std::string& during_setup) {
  fake::reset(blank_eeprom);
#ifdef ARTICULA_TEST_CONFIG
  // This variant's arm, as `articula configure ROBOT` would have left it in EEPROM.
  uint8_t* e = fake::hw.eeprom + robot::kEepromAddress;
  if (blank_eeprom || e[0] != robot::kEepromVersion) {
    static const uint8_t image[articula::kConfigImageSize] = ARTICULA_BUILTIN_CONFIG;
    const uint16_t crc = articula::config_checksum(image);
    e[0] = robot::kEepromVersion;
    std::memcpy(e + 1, image, sizeof image);
    e[1 + sizeof image] = uint8_t(crc);
    e[2 + sizeof image] = uint8_t(crc >> 8);
  }
#endif
  g_partial.clear();
  g_lines.clear();
  g_reports.clear();
  g_tx_seen = 0;
  hal::init();  // as main.cpp
  for (char c : during_setup) fake::receive(c);
  firmware::setup();
  for (int i = 0; i < robot::kJoints; ++i) fake::hw.microsteps[i] = robot::actuation().motors[i].microsteps;
  hal::start();
}

void send(const std::string& bytes) {
  for (char c : bytes) fake::receive(c);
}

void tick() {
  fake::Hardware& hw = fake::hw;
  firmware::poll();
  const uint64_t end = hw.now + kPollTicks;
  while (hw.timer_running && hw.deadline <= end) {
    hw.now = hw.deadline;
    const uint32_t next = fake::step_deadline();
    if (next == 0)
      hw.timer_running = false;
    else
      hw.deadline += next;
  }
  hw.now = end;
  collect();
}

bool run_until(const std::function<bool()>& done, uint64_t max_ticks) {
  const uint64_t end = fake::hw.now + max_ticks;
  while (fake::hw.now < end) {
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

Status status() {
  send("?");
  tick();
  collect();
  Status r{};
  for (size_t i = 0; i < g_lines.size(); ++i) {
    if (!g_lines[i].empty() && g_lines[i][0] == '<') {
      const std::string l = g_lines[i];
      g_lines.erase(g_lines.begin() + long(i));
      EXPECT_TRUE(articula::parse_status(r, l.data(), uint16_t(l.size()))) << l;
      return r;
    }
  }
  ADD_FAILURE() << "no status report after '?'";
  return r;
}

bool at_rest() {
  return !stepper::busy() && queue::empty() && !stepper::stop_requested() && !fake::hw.timer_running;
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

std::vector<std::pair<int, int32_t>> settings_listing() {
  std::vector<std::pair<int, int32_t>> out;
  EXPECT_EQ(command("$"), "ok");
  for (const std::string& l : reports()) {
    articula::BasicCommand<4> c;
    EXPECT_EQ(articula::parse_line(c, l.data(), uint8_t(l.size()), robot::count()), articula::kOk) << l;
    EXPECT_EQ(c.type, articula::kCmdSetSetting) << l;
    out.push_back(std::make_pair(int(c.arg[0]), c.arg[1]));
  }
  return out;
}

articula::MotionSettings motion_settings_from_listing() {
  articula::MotionSettings s = {2000000, 0, 0};
  for (const auto& kv : settings_listing()) {
    if (kv.first == 0) s.max_rate = uint32_t(kv.second / 1000);
    if (kv.first == 1) s.accel = uint32_t(kv.second / 1000);
  }
  return s;
}

std::vector<Step> steps_of(int motor, uint64_t from_tick) {
  std::vector<Step> out;
  for (const fake::CoilWrite& w : fake::hw.coil_log)
    if (w.motor == motor && w.step != 0 && w.tick >= from_tick) out.push_back(Step{w.tick, w.step});
  return out;
}

std::string hal_errors() {
  std::string s;
  for (const std::string& e : fake::hw.errors) s += e + "\n";
  return s;
}

}  // namespace sim
