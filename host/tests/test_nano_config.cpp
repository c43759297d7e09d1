// The robot configuration of a Nano (host/lib/nano_config.h, articula/config.h).
#include <gtest/gtest.h>

#include <articula/protocol.h>

#include "builtin_config.h"
#include "nano_config.h"
#include "predict.h"
#include "robot_file.h"

using namespace articula;
using namespace articula::host;

namespace {
Robot load(const std::string& path) { return load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/" + path); }

// The lines as the firmware takes them: parsed by the protocol, each value checked and
// staged into an image (robot.cpp's stage and stage_name), the commit's checksum compared.
bool stage_lines(const std::vector<std::string>& lines, std::vector<uint8_t>& image, int32_t& commit) {
  commit = -1;
  for (const auto& l : lines) {
    Command c;
    if (parse_line(c, l.data(), uint8_t(l.size()), 3) != kOk) return false;
    if (c.type == kCmdName) {
      if (config_check_name(l.data() + c.arg[0], uint8_t(c.arg[1])) != kOk) return false;
      config_name_bytes(image.data() + kConfigNameOffset, l.data() + c.arg[0], uint8_t(c.arg[1]));
    } else if (c.type == kCmdSetSetting && c.arg[0] == kCommitSetting) {
      commit = c.arg[1] / 1000;
    } else if (c.type == kCmdSetSetting) {
      if (config_check(uint16_t(c.arg[0]), c.arg[1]) != kOk) return false;
      config_put(image.data(), uint16_t(c.arg[0]), c.arg[1]);
    } else {
      return false;
    }
  }
  return true;
}
}  // namespace

TEST(NanoConfig, TheBuiltInConfigurationIsTheMk2s) {
  // firmware/src/builtin_config.h is made by `articula configure mk2plus --header`: it must
  // still be what the host makes of the robot file.
  const uint8_t builtin[] = ARTICULA_BUILTIN_CONFIG;
  const NanoConfig c = nano_config(load("robots/mk2plus.json"));
  ASSERT_EQ(sizeof builtin, c.image.size());
  EXPECT_EQ(std::vector<uint8_t>(builtin, builtin + sizeof builtin), c.image)
      << "regenerate: articula configure mk2plus --header > firmware/src/builtin_config.h";
  EXPECT_STREQ(c.arm.name, "MK2 Plus");
  EXPECT_TRUE(c.arm.has_point);
}

TEST(NanoConfig, TheDriveIsInTheImage) {
  EXPECT_EQ(nano_config(load("robots/mk2plus.json")).arm.drive, kDriveL298n);
  EXPECT_EQ(nano_config(load("hil/robots/mk2-28byj48.json")).arm.drive, kDriveUln2003);
  const NanoConfig cnc = nano_config(load("robots/mk2plus-cnc.json"));
  EXPECT_EQ(cnc.arm.drive, kDriveStepDir);
  EXPECT_EQ(cnc.arm.actuation.motors[0].microsteps, 8);
  // The 4-wire build refuses it (microsteps beyond half steps, and the drive); the shield's takes it.
  ConfiguredArm<3> arm;
  EXPECT_EQ(config_read(arm, cnc.image.data(), uint8_t((1u << kDriveL298n) | (1u << kDriveUln2003))), kConfigBadDrive);
  EXPECT_EQ(config_read(arm, cnc.image.data(), uint8_t(1u << kDriveStepDir)), kConfigOk);
}

// A servo arm (the shipped meArm): each servo's step-0 pulse and pin, and its servos' rate and
// acceleration in ticks (the file's speed 90 deg/s and accel 360 deg/s^2, 22 ticks a degree on
// the slowest-geared servos). Only the servo build takes it.
TEST(NanoConfig, AServoArmCarriesItsPinsPulsesAndRates) {
  const NanoConfig c = nano_config(load("robots/mearm.json"));
  EXPECT_EQ(c.arm.drive, kDriveServo);
  const uint16_t zero[3] = {1544, 1265, 1472};
  const uint8_t pin[3] = {9, 10, 11};  // D9, D10, D11
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(c.arm.servo_zero_us[i], zero[i]) << i;
    EXPECT_EQ(c.arm.servo_pin[i], pin[i]) << i;
  }
  EXPECT_EQ(c.arm.rate_cap, 1980);   // floor(90 * 22)
  EXPECT_EQ(c.arm.accel_cap, 7920u);  // 360 * 22
  ConfiguredArm<3> arm;
  EXPECT_EQ(config_read(arm, c.image.data(), uint8_t((1u << kDriveL298n) | (1u << kDriveUln2003))), kConfigBadDrive);
  EXPECT_EQ(config_read(arm, c.image.data(), uint8_t(1u << kDriveServo)), kConfigOk);
  // The servo build's built-in arm is this file's image.
  const std::string lines = c.lines.back();
  EXPECT_EQ(lines, "$199=" + std::to_string(c.checksum) + ".000");
  // Two servos on one pin, a pin on the serial line, no step-0 pulse: refused by the reader.
  for (const auto& [setting, value] : {std::pair<uint16_t, int32_t>{136, 9000}, {135, 1000}, {133, 0}}) {
    std::vector<uint8_t> bad = c.image;
    config_put(bad.data(), setting, value);
    EXPECT_EQ(config_read(arm, bad.data(), uint8_t(1u << kDriveServo)), kConfigBadDrive) << setting;
  }
  // A stepper arm's image has none of them.
  const NanoConfig mk2 = nano_config(load("robots/mk2plus.json"));
  for (uint16_t n = 132; n <= 139; ++n) EXPECT_EQ(config_get(mk2.image, n), 0) << n;
}

TEST(NanoConfig, TheLinesWriteTheImageAndTheCommitNamesItsChecksum) {
  for (const char* f : {"robots/mk2plus.json", "robots/mk2plus-cnc.json", "hil/robots/mk2-28byj48.json", "hil/robots/mk2-halfstep.json", "hil/robots/mk2-regeared.json",
                        "hil/robots/thesis-example-arm.json", "hil/robots/three-link-arm.json"}) {
    const NanoConfig c = nano_config(load(f));
    std::vector<uint8_t> image(kConfigImageSize, 0xA5);  // whatever the EEPROM held
    int32_t commit = -1;
    ASSERT_TRUE(stage_lines(c.lines, image, commit)) << f;
    EXPECT_EQ(image, c.image) << f;  // every byte written
    EXPECT_EQ(commit, c.checksum) << f;
    EXPECT_EQ(config_checksum(image.data()), c.checksum) << f;
    for (const auto& l : c.lines) EXPECT_LE(l.size(), kMaxLineLength) << l;
  }
}

TEST(NanoConfig, TheArmReadBackIsTheRobotFiles) {
  const Robot r = load("hil/robots/mk2-regeared.json");
  const ConfiguredArm<3> a = nano_config(r).arm;
  ASSERT_EQ(a.actuation.num_motors, 3);
  for (int i = 0; i < 3; ++i) {
    const MotorSpec& m = r.actuation.motors[i];
    const MotorSpec& b = a.actuation.motors[i];
    EXPECT_EQ(b.gear_num, m.gear_num);
    EXPECT_EQ(b.gear_den, m.gear_den);
    EXPECT_EQ(b.direction, m.direction);
    EXPECT_EQ(b.zero, m.zero);
    EXPECT_EQ(b.min, m.min);
    EXPECT_EQ(b.max, m.max);
  }
  EXPECT_EQ(a.actuation.motors[1].direction, -1);
  EXPECT_EQ(a.actuation.coupling[2][1], -1.0f);
  // The home pose (0, 90, -90) as motor angles through the parallelogram: (0, 90, 0).
  EXPECT_EQ(a.home[0], 0);
  EXPECT_EQ(a.home[1], 90000);
  EXPECT_EQ(a.home[2], 0);
  EXPECT_TRUE(a.has_point);
  EXPECT_TRUE(a.arm.parallelogram);
  EXPECT_EQ(a.arm.upper, 135.0f);
  EXPECT_EQ(a.servo_closed_deg, 150.0f);
  // The prediction's firmware is put in use with the same arm.
  EXPECT_EQ(firmware_arm(r).home[1], 90000);
  EXPECT_FALSE(nano_config(load("hil/robots/thesis-example-arm.json")).arm.has_point);
  EXPECT_TRUE(nano_config(load("hil/robots/three-link-arm.json")).arm.has_point);
}

TEST(NanoConfig, ARobotTheNanoCannotDriveIsRefusedWithTheReason) {
  auto why = [](const Robot& r) {
    try {
      nano_config(r);
    } catch (const NanoConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(why(load("robots/thesis-example.json")).find("has no motors"), std::string::npos);
  Robot four = load("robots/mk2plus.json");
  four.actuation.num_motors = 4;
  four.actuation.motors[3] = four.actuation.motors[2];
  four.motor_names.push_back("wrist");
  EXPECT_NE(why(four).find("4 motors: the Nano drives at most 3"), std::string::npos);
  Robot micro = load("robots/mk2plus.json");
  micro.actuation.motors[1].microsteps = 8;
  EXPECT_NE(why(micro).find("shoulder motor has 8 microsteps"), std::string::npos);
  Robot coupled = load("robots/mk2plus.json");
  coupled.actuation.coupling[2][1] = -1.0 / 3.0;
  EXPECT_NE(why(coupled).find("coupling entry [2][1]"), std::string::npos);
}

TEST(NanoConfig, EveryValueIsRangeChecked) {
  EXPECT_EQ(config_check(100, 200000), kOk);
  EXPECT_EQ(config_check(100, 200500), kValueOutOfRange);  // steps are whole
  EXPECT_EQ(config_check(101, 3000), kValueOutOfRange);    // the L298N: full or half steps
  EXPECT_EQ(config_check(102, 0), kValueOutOfRange);       // a direction is +1 or -1
  EXPECT_EQ(config_check(112, -1000), kOk);
  EXPECT_EQ(config_check(130, 4000), kValueOutOfRange);    // three motors at most
  EXPECT_EQ(config_check(109, 0), kSettingUnknown);
  EXPECT_EQ(config_check(149, 0), kSettingUnknown);
  EXPECT_EQ(config_check(161, 180001), kValueOutOfRange);  // a servo angle
  EXPECT_EQ(config_check(145, -1500), kOk);                // coupling keeps three decimals
  EXPECT_EQ(config_check_name("MK2 Plus", 8), kOk);
  EXPECT_EQ(config_check_name("a|b", 3), kBadCharacter);
  EXPECT_EQ(config_check_name("0123456789012345678901234", 25), kValueOutOfRange);
  // A name the line cannot carry becomes one it can, and the checksum is of that.
  Robot r = load("robots/mk2plus.json");
  r.name = "  Bob's arm #2!  ";
  const NanoConfig c = nano_config(r);
  EXPECT_STREQ(c.arm.name, "Bob's arm -2-");
  EXPECT_EQ(c.lines[c.lines.size() - 2], "N Bob's arm -2-");
}
