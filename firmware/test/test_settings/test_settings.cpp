// Tests firmware/src/settings.cpp: the defaults on a blank or corrupt EEPROM image (and
// W:14 said once, in whichever report comes first), every setting's round trip through
// $n=v, the listing and a reboot, the values each setting refuses, and the image format
// (version byte, CRC-16/CCITT-FALSE).
#include <articula/motion.h>
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"
#include "settings.h"

using namespace articula;

namespace {

// The documented defaults (docs/protocol.md, Settings), setting -> value.
const std::map<int, int32_t> kDefaults = {{0, 600}, {1, 2000}, {2, 2000}, {3, 0}, {4, 200}, {5, 300}, {6, 50}, {7, 100}};

std::map<int, int32_t> listing() {
  std::map<int, int32_t> m;
  for (const auto& kv : sim::settings_listing()) {
    EXPECT_EQ(kv.second % 1000, 0);
    EXPECT_EQ(m.count(kv.first), 0u) << "listed twice: " << kv.first;
    m[kv.first] = kv.second / 1000;
  }
  return m;
}

uint8_t warning_of_status() { return sim::status().warning; }

uint8_t warning_of_info() {
  EXPECT_EQ(sim::command("I"), "ok");
  InfoReport r;
  const std::string& l = sim::reports().at(0);
  EXPECT_TRUE(parse_info(r, l.data(), uint16_t(l.size())));
  return r.warning;
}

void store_some_settings() {
  sim::boot();
  ASSERT_EQ(sim::command("$0=321"), "ok");
  ASSERT_EQ(sim::command("$5=0"), "ok");
  sim::boot(false);
  ASSERT_EQ(listing().at(0), 321);
  ASSERT_EQ(warning_of_status(), 0);
}

}  // namespace

TEST(Settings, Crc16IsCcittFalse) {
  const char* check = "123456789";
  EXPECT_EQ(articula::crc16(reinterpret_cast<const uint8_t*>(check), 9), 0x29B1);
  EXPECT_EQ(articula::crc16(nullptr, 0), 0xFFFF);
}

TEST(Settings, BlankEepromLoadsDefaultsWritesThemAndWarnsOnce) {
  sim::boot(true);
  EXPECT_EQ(listing(), kDefaults);
  // Written back: version, the values, a CRC that checks.
  const uint8_t* e = sitl::hw().eeprom + settings::kAddress;
  EXPECT_EQ(e[0], settings::kVersion);
  const uint16_t crc = articula::crc16(e, settings::kImageSize - 2);
  EXPECT_EQ(e[settings::kImageSize - 2], crc & 0xFF);
  EXPECT_EQ(e[settings::kImageSize - 1], crc >> 8);
  // W:14 in the first report only (here a status report), not in the next ones.
  sim::boot(true);
  EXPECT_EQ(warning_of_status(), kSettingsReset);
  EXPECT_EQ(warning_of_status(), 0);
  EXPECT_EQ(warning_of_info(), 0);
  // Next power-up: the image is good now, no warning.
  sim::boot(false);
  EXPECT_EQ(warning_of_info(), 0);
  EXPECT_EQ(warning_of_status(), 0);
  EXPECT_EQ(listing(), kDefaults);
}

// One flipped bit anywhere in the image (version, a value, the CRC) loads the defaults and
// warns once, in the info line when that comes first.
TEST(Settings, CorruptImageLoadsDefaults) {
  for (uint16_t at = 0; at < settings::kImageSize; ++at) {
    store_some_settings();
    sitl::hw().eeprom[settings::kAddress + at] ^= 0x10;
    sim::boot(false);
    EXPECT_EQ(warning_of_info(), kSettingsReset) << "byte " << at;
    EXPECT_EQ(warning_of_status(), 0) << "byte " << at;
    EXPECT_EQ(listing(), kDefaults) << "byte " << at;
  }
  // A good CRC over a value no setting allows (a future or foreign image): defaults too.
  store_some_settings();
  uint8_t* e = sitl::hw().eeprom + settings::kAddress;
  e[1] = e[2] = e[3] = e[4] = 0;  // $0 = 0
  const uint16_t crc = articula::crc16(e, settings::kImageSize - 2);
  e[settings::kImageSize - 2] = uint8_t(crc);
  e[settings::kImageSize - 1] = uint8_t(crc >> 8);
  sim::boot(false);
  EXPECT_EQ(warning_of_status(), kSettingsReset);
  EXPECT_EQ(listing(), kDefaults);
}

// Each setting at its lowest, highest and a middle value: set, listed, kept over a reboot,
// and the listing sent back restores them all.
TEST(Settings, EverySettingRoundTrips) {
  sim::boot();
  for (int n = 0; n < settings::kCount; ++n) {
    const articula::SettingRange r = articula::setting_range(uint8_t(n), robot::kJoints);
    for (uint32_t v : {r.min, r.max, (r.min + r.max) / 2}) {
      const std::string line = "$" + std::to_string(n) + "=" + std::to_string(v);
      ASSERT_EQ(sim::command(line), "ok") << line;
      EXPECT_EQ(listing().at(n), int32_t(v)) << line;
      sim::boot(false);
      EXPECT_EQ(listing().at(n), int32_t(v)) << line << " after a reboot";
      EXPECT_EQ(warning_of_status(), 0);
    }
  }
  // A listing is the commands that restore it.
  sim::boot();
  const std::vector<std::string> custom = {"$0=123", "$1=4567", "$2=89", "$3=0", "$4=321", "$5=45"};
  for (const std::string& l : custom) ASSERT_EQ(sim::command(l), "ok");
  ASSERT_EQ(sim::command("$"), "ok");
  const std::vector<std::string> saved = sim::reports();
  ASSERT_EQ(saved.size(), size_t(settings::kCount));
  EXPECT_EQ(saved[0], "$0=123.000");
  sim::boot(true);
  EXPECT_EQ(listing(), kDefaults);
  for (const std::string& l : saved) ASSERT_EQ(sim::command(l), "ok") << l;
  sim::boot(false);
  ASSERT_EQ(sim::command("$"), "ok");
  EXPECT_EQ(sim::reports(), saved);
  // Setting a value it already has writes nothing.
  const uint32_t written = sitl::hw().eeprom_bytes_written;
  ASSERT_EQ(sim::command("$0=123"), "ok");
  EXPECT_EQ(sitl::hw().eeprom_bytes_written, written);
}

TEST(Settings, RefusedValuesChangeNothing) {
  sim::boot();
  const uint32_t written = sitl::hw().eeprom_bytes_written;
  for (int n = 0; n < settings::kCount; ++n) {
    const articula::SettingRange r = articula::setting_range(uint8_t(n), robot::kJoints);
    const std::string p = "$" + std::to_string(n) + "=";
    if (r.min > 0) {
      EXPECT_EQ(sim::command(p + std::to_string(r.min - 1)), "error:8") << n;
    }
    EXPECT_EQ(sim::command(p + std::to_string(r.max + 1)), "error:8") << n;
    EXPECT_EQ(sim::command(p + "-1"), "error:8") << n;
    EXPECT_EQ(sim::command(p + std::to_string(r.min) + ".5"), "error:8") << n;
    EXPECT_EQ(sim::command(p + "1000000"), "error:8") << n;
  }
  EXPECT_EQ(sim::command("$" + std::to_string(settings::kCount) + "=1"), "error:13");
  EXPECT_EQ(sim::command("$999=1"), "error:13");
  EXPECT_EQ(listing(), kDefaults);
  EXPECT_EQ(sitl::hw().eeprom_bytes_written, written);
  // The endstop mask allows one bit per motor.
  EXPECT_EQ(articula::setting_range(settings::kEndstops, robot::kJoints).max, (1u << robot::kJoints) - 1);
}

// Every pair of rate and acceleration the settings allow is a valid profile (the firmware
// never checks the combination at run time).
TEST(Settings, EveryAllowedRateAndAccelerationIsAValidProfile) {
  const articula::SettingRange v = articula::setting_range(settings::kMaxRate, robot::kJoints);
  const articula::SettingRange a = articula::setting_range(settings::kAccel, robot::kJoints);
  for (uint32_t rate : {v.min, v.min + 1, v.fallback, v.max - 1, v.max})
    for (uint32_t acc : {a.min, a.min + 1, a.fallback, a.max - 1, a.max})
      EXPECT_EQ(validate(MotionSettings{2000000, rate, acc}), kMotionOk) << rate << " " << acc;
  const articula::SettingRange h = articula::setting_range(settings::kHomingRate, robot::kJoints);
  EXPECT_GE(h.min, 1u);
  EXPECT_LE(2000000u / h.min, kMaxStepTicks);
}

#include "pio_main.h"  // PlatformIO runs each test folder as a program of its own
