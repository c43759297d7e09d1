// firmware/test/harness.cpp - the native tests' boot and their GoogleTest checks.
#include "harness.h"

#include <gtest/gtest.h>

#ifdef ARTICULA_TEST_CONFIG
#include ARTICULA_TEST_CONFIG
#endif

namespace sim {

void boot(bool blank_eeprom, const std::string& during_setup) {
#ifdef ARTICULA_TEST_CONFIG
  static const uint8_t image[articula::kConfigImageSize] = ARTICULA_BUILTIN_CONFIG;
  sitl::boot(blank_eeprom, during_setup, image);
#else
  sitl::boot(blank_eeprom, during_setup);
#endif
}

const char* robot_file() {
#ifdef ARTICULA_ROBOT_FILE
  return ARTICULA_ROBOT_FILE;
#else
  return "";  // (PlatformIO's native tests: none of them reads the robot file)
#endif
}

Status status() {
  send("?");
  tick();
  Status r{};
  const std::string l = sitl::take_report();
  if (l.empty())
    ADD_FAILURE() << "no status report after '?'";
  else
    EXPECT_TRUE(articula::parse_status(r, l.data(), uint16_t(l.size()))) << l;
  return r;
}

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

}  // namespace sim
