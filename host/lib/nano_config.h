// host/lib/nano_config.h - a robot file as the robot configuration of a Nano
// (articula/config.h): the image, its checksum, and the protocol lines that write it. The
// CLI (`articula configure`), Python, the page and the harness all get it from here.
#ifndef ARTICULA_HOST_NANO_CONFIG_H
#define ARTICULA_HOST_NANO_CONFIG_H

#include <articula/config.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

// Why a robot cannot be a Nano's configuration; the message names the robot and the reason.
class NanoConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct NanoConfig {
  std::vector<uint8_t> image;        // kConfigImageSize bytes
  uint16_t checksum = 0;             // config_checksum(image): the I banner's K, $199's value
  std::vector<std::string> lines;    // $100=... to $161=..., N <name>, $199=<checksum>
  ConfiguredArm<kMaxConfigMotors> arm;  // the image as the firmware reads it (config_read): its
                                        // name as the banner shows it, has_point when P works
};

// Throws NanoConfigError for a robot the firmware cannot drive: no motors, more than three,
// microsteps other than 1 or 2, a coupling entry not a multiple of 0.001, a number beyond
// what the protocol carries.
NanoConfig nano_config(const Robot& robot);

// The motors the host's build of the firmware drives (host/CMakeLists.txt: the prediction runs
// it, firmware/sitl): the same source as the Nano's three.
inline constexpr int kFirmwareMotors = 8;

// The arm as the firmware holds it (robot::config()): for a robot the Nano takes, the image of
// nano_config() read back as the firmware reads it; for one it does not (more motors, finer
// microsteps, a coupling beyond three decimals), the same rules in float: the home pose u =
// C^-1 q within the limits, P's closed form when the model is of its family, the servo.
// Throws NanoConfigError for a robot without motors or with more than kFirmwareMotors.
ConfiguredArm<kFirmwareMotors> firmware_arm(const Robot& robot);

// P's arm for a robot, from its model and motors in float as the Nano holds them: false when
// the closed form does not apply (not a yaw-pitch-pitch arm with the identity or the MK2's
// parallelogram coupling). For robots the Nano cannot take, which the prediction still runs.
bool float_ypp_arm(const Robot& robot, YppArm<float>& arm);


}  // namespace articula::host

#endif  // ARTICULA_HOST_NANO_CONFIG_H
