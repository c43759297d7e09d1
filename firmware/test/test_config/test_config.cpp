// Tests the robot configuration in the firmware (robot.cpp, articula/config.h): what a fresh
// machine runs, staging `$1xx=` and `N`, the commit `$199=` (its checksum and the arm it
// describes), what a power cycle keeps, and that the arm then moves by the new motors.
#include <articula/config.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "builtin_config.h"
#include "hal_sitl.h"
#include "harness.h"
#include "robot.h"

using namespace articula;

namespace {

// The image in the SITL EEPROM (staged or committed).
std::vector<uint8_t> eeprom_image() {
  const uint8_t* e = sitl::hw().eeprom + robot::kEepromAddress + 1;
  return std::vector<uint8_t>(e, e + kConfigImageSize);
}

InfoReport banner() {
  EXPECT_EQ(sim::command("I"), "ok");
  InfoReport info{};
  EXPECT_FALSE(sim::reports().empty());
  const std::string& l = sim::reports().back();
  EXPECT_TRUE(parse_info(info, l.data(), uint16_t(l.size()))) << l;
  return info;
}

std::string commit_line(const std::vector<uint8_t>& image) {
  return "$199=" + std::to_string(config_checksum(image.data()));
}

}  // namespace

TEST(Config, AFreshMachineRunsItsArmAndSaysWhich) {
  sim::boot();
  const InfoReport info = banner();
  EXPECT_EQ(info.protocol, kProtocolVersion);
  EXPECT_EQ(info.checksum, robot::checksum());
  EXPECT_STREQ(info.name, robot::config().name);
  EXPECT_EQ(info.num_joints, robot::count());
  if (std::string(info.name) == "MK2 Plus") {  // the arm a blank EEPROM gets (the halfstep variant's is preloaded)
    const uint8_t builtin[] = ARTICULA_BUILTIN_CONFIG;
    EXPECT_EQ(info.checksum, config_checksum(builtin));
    EXPECT_EQ(info.checksum, 21232);  // docs/protocol.md's
    // written to EEPROM before the first value is staged, not at power-up (0.6 s of writing)
    EXPECT_NE(eeprom_image(), std::vector<uint8_t>(builtin, builtin + sizeof builtin));
    EXPECT_EQ(sim::command("$161=150"), "ok");  // the value it has
    EXPECT_EQ(eeprom_image(), std::vector<uint8_t>(builtin, builtin + sizeof builtin));
    EXPECT_EQ(sim::command("$199=21232"), "ok");
  }
}

TEST(Config, StagedValuesChangeNothingUntilCommitted) {
  sim::boot();
  sim::command("$0=4000");
  const uint16_t before = robot::checksum();
  const MotorSpec shoulder = robot::motor(1);
  // The shoulder motor turned round, on other gears, and a new name.
  EXPECT_EQ(sim::command("$112=" + std::to_string(-shoulder.direction)), "ok");
  EXPECT_EQ(sim::command("$113=60"), "ok");
  EXPECT_EQ(sim::command("N  Bench arm 2 "), "ok");
  EXPECT_EQ(banner().checksum, before);  // staged only
  EXPECT_EQ(robot::motor(1).gear_num, shoulder.gear_num);
  std::vector<uint8_t> image = eeprom_image();
  EXPECT_EQ(config_get(image.data(), 113), 60);
  // A wrong checksum: refused, nothing changes.
  const uint16_t staged = config_checksum(image.data());
  EXPECT_EQ(sim::command("$199=" + std::to_string(uint16_t(staged + 1))), "error:17");
  EXPECT_EQ(sim::command("$199=12.5"), "error:17");
  EXPECT_EQ(banner().checksum, before);
  // The right one: in use at once.
  EXPECT_EQ(sim::command(commit_line(image)), "ok");
  const InfoReport info = banner();
  EXPECT_EQ(info.checksum, staged);
  EXPECT_STREQ(info.name, "Bench arm 2");
  EXPECT_EQ(robot::motor(1).gear_num, 60);
  EXPECT_EQ(robot::motor(1).direction, -shoulder.direction);
  // The arm moves by the new motor: 10 degrees more on the shoulder.
  const Millideg target = clamp(Millideg(robot::motor(1).zero + 10000), robot::motor(1).min, robot::motor(1).max);
  std::string m = "M";
  for (int i = 0; i < robot::count(); ++i)
    m += " " + std::to_string((i == 1 ? target : robot::motor(uint8_t(i)).zero) / 1000.0);
  EXPECT_EQ(sim::command(m), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  const sim::Status st = sim::status();
  EXPECT_EQ(st.steps[1], quantize_within_limits(robot::motor(1), target));
  EXPECT_EQ(st.steps[1] < 0, (target - robot::motor(1).zero) * robot::motor(1).direction < 0);
  // A power cycle keeps it.
  sim::boot(false);
  EXPECT_EQ(banner().checksum, staged);
  EXPECT_STREQ(robot::config().name, "Bench arm 2");
}

TEST(Config, EveryBadValueGetsItsOwnError) {
  sim::boot();
  const std::vector<uint8_t> before = eeprom_image();
  EXPECT_EQ(sim::command("$101=3"), "error:8");       // microsteps: a power of two
  EXPECT_EQ(sim::command("$101=128"), "error:8");     //   up to 64
  EXPECT_EQ(sim::command("$102=0"), "error:8");       // a direction is 1 or -1
  EXPECT_EQ(sim::command("$100=200.5"), "error:8");   // whole steps
  EXPECT_EQ(sim::command("$130=4"), "error:8");       // three motors at most
  EXPECT_EQ(sim::command("$131=4"), "error:8");       // the drive kinds are 0..3
  EXPECT_EQ(sim::command("$161=181"), "error:8");     // a servo angle
  EXPECT_EQ(sim::command("$109=1"), "error:13");      // no such setting
  EXPECT_EQ(sim::command("$190=1"), "error:13");
  EXPECT_EQ(sim::command("N a|b"), "error:11");       // the banner's separator
  EXPECT_EQ(sim::command("N"), "error:4");
  EXPECT_EQ(sim::command("N 0123456789012345678901234"), "error:8");
  EXPECT_EQ(eeprom_image(), before);  // none of them was staged
}

TEST(Config, AnArmTheFirmwareCannotDriveIsRefusedAtTheCommit) {
  sim::boot();
  const uint16_t before = robot::checksum();
  const MotorSpec base = robot::motor(0);
  // Each value in range, together not an arm: the zero beyond the maximum.
  EXPECT_EQ(sim::command("$105=" + std::to_string(base.max / 1000 + 5)), "ok");
  EXPECT_EQ(sim::command(commit_line(eeprom_image())), "error:18");
  EXPECT_EQ(banner().checksum, before);
  EXPECT_EQ(robot::motor(0).zero, base.zero);
  // The staged image was never committed: the next power-up runs the built-in arm or the
  // last committed one, never this.
  sim::boot(false);
  EXPECT_NE(robot::motor(0).zero, base.max + 5000);
}

// A drive this build does not drive (a servo; STEP/DIR on the Nano's 4-wire build) is a valid
// image, refused at the commit; the other 4-wire one (L298N <-> ULN2003) is taken, with its
// own coil table.
TEST(Config, ADriveThisBuildDoesNotDriveIsRefusedAtTheCommit) {
  sim::boot();
  const uint16_t before = robot::checksum();
  const uint8_t drive = robot::config().drive;
  for (int kind = 0; kind < articula::kDriveKinds; ++kind) {
    if (robot::kDrives & (1u << kind)) continue;
    EXPECT_EQ(sim::command("$131=" + std::to_string(kind)), "ok");
    EXPECT_EQ(sim::command(commit_line(eeprom_image())), "error:18") << kind;
    EXPECT_EQ(banner().checksum, before);
    EXPECT_EQ(robot::config().drive, drive);
  }
  if (drive == articula::kDriveStepDir) {
    // A 4-wire drive for motors in 1/4 and 1/8 steps: refused (coils take full or half steps).
    EXPECT_EQ(sim::command("$131=0"), "ok");
    EXPECT_EQ(sim::command(commit_line(eeprom_image())), "error:18");
    EXPECT_EQ(robot::config().drive, drive);
    return;
  }
  const int other = drive == articula::kDriveL298n ? articula::kDriveUln2003 : articula::kDriveL298n;
  EXPECT_EQ(sim::command("$131=" + std::to_string(other)), "ok");
  EXPECT_EQ(sim::command(commit_line(eeprom_image())), "ok");
  EXPECT_EQ(robot::config().drive, other);
  EXPECT_NE(banner().checksum, before);
  // Its coils follow the other table: the first full step energised is 1100 on a ULN2003,
  // 1010 on an L298N (bit 0 is IN1).
  EXPECT_EQ(sim::command("L 0 5"), "ok");
  ASSERT_TRUE(sim::run_until_at_rest());
  bool seen = false;
  for (const sitl::CoilWrite& w : sitl::hw().coil_log)
    if (w.motor == 0 && w.pattern != 0 && !seen) {
      EXPECT_EQ(w.pattern, other == articula::kDriveUln2003 ? 0x3 : 0x5);
      seen = true;
    }
  EXPECT_TRUE(seen);
}

TEST(Config, TwoMotorsAndNoClosedForm) {
  sim::boot();
  EXPECT_EQ(sim::command("$130=2"), "ok");
  EXPECT_EQ(sim::command("$150=0"), "ok");
  EXPECT_EQ(sim::command(commit_line(eeprom_image())), "ok");
  EXPECT_EQ(banner().num_joints, 2);
  EXPECT_EQ(sim::status().num_joints, 2);
  const std::string m2 = "M " + std::to_string(robot::motor(0).zero / 1000.0) + " " +
                         std::to_string(robot::motor(1).zero / 1000.0);
  EXPECT_EQ(sim::command(m2), "ok");
  EXPECT_EQ(sim::command(m2 + " 0"), "error:5");
  EXPECT_EQ(sim::command("L 2 1"), "error:6");
  EXPECT_EQ(sim::command("P 200 0 100"), "error:16");
}

TEST(Config, StagingDoesNotWaitForRestButTheCommitDoes) {
  sim::boot();
  EXPECT_EQ(sim::command("$0=400"), "ok");
  const MotorSpec& m = robot::motor(0);
  EXPECT_EQ(sim::command("M " + std::to_string(m.max / 1000.0) + " " + std::to_string(robot::motor(1).zero / 1000.0) +
                         " " + std::to_string(robot::motor(2).zero / 1000.0)),
            "ok");
  EXPECT_EQ(sim::command("N Busy arm"), "ok");
  EXPECT_FALSE(sim::at_rest());  // answered while the arm still moves
  EXPECT_EQ(sim::command(commit_line(eeprom_image())), "ok");
  EXPECT_TRUE(sim::at_rest());  // answered once it stopped
  EXPECT_STREQ(robot::config().name, "Busy arm");
  const sim::Status st = sim::status();
  for (int i = 0; i < robot::count(); ++i) EXPECT_EQ(st.steps[i], 0) << i;  // as at power-up
}
