// host/lib/protocol_view.cpp - the arm's lines read by the core's parsers, for the bindings.
#include "protocol_view.h"

#include <articula/motion.h>
#include <articula/protocol.h>
#include <articula/status.h>

#include <algorithm>

namespace articula::host {

nlohmann::json arm_line_json(const std::string& text) {
  using json = nlohmann::json;
  const char* line = text.c_str();
  const uint16_t len = uint16_t(std::min<size_t>(text.size(), 1000));
  uint8_t code = 0;
  if (len < 256 && parse_reply(code, line, uint8_t(len))) return {{"kind", "reply"}, {"code", code}};
  StatusReport<8> st;
  if (parse_status(st, line, len)) {
    json steps = json::array(), angles = json::array(), millideg = json::array();
    for (int i = 0; i < st.num_joints; ++i) {
      steps.push_back(st.steps[i]);
      millideg.push_back(st.millideg[i]);
      angles.push_back(st.millideg[i] / 1000.0);
    }
    return {{"kind", "status"}, {"state", kStateWords[st.state]}, {"at_rest", state_at_rest(st.state)}, {"steps", steps}, {"angles", angles},
            {"millideg", millideg}, {"gripper", st.gripper}, {"free", st.free_slots}, {"coils", st.coils},
            {"io", st.io >= 0 ? json(st.io) : json(nullptr)}, {"warning", st.warning}};
  }
  InfoReport info;
  if (parse_info(info, line, len))
    return {{"kind", "info"},
            {"version", std::to_string(info.version[0]) + "." + std::to_string(info.version[1]) + "." +
                            std::to_string(info.version[2])},
            {"protocol", info.protocol},
            {"joints", info.num_joints},
            {"robot", std::string(info.name)},
            {"checksum", info.checksum >= 0 ? json(info.checksum) : json(nullptr)},
            {"warning", info.warning}};
  // A setting as the firmware lists it is the line that sets it: `$3=200.000`.
  Command cmd;
  if (len > 0 && len < 256 && line[0] == '$' && parse_line(cmd, line, uint8_t(len), 0) == kOk &&
      cmd.type == kCmdSetSetting)
    return {{"kind", "setting"}, {"number", cmd.arg[0]}, {"value", cmd.arg[1] / 1000.0}};
  return {{"kind", "other"}};
}

nlohmann::json status_table_json() {
  nlohmann::json out = nlohmann::json::object();
  for (uint8_t c = 0; c < kStatusCount; ++c) out[std::to_string(c)] = {status_name(c), status_text(c)};
  return out;
}

double first_interval_s(double max_rate, double accel) {
  if (!(max_rate >= 1 && accel >= 1 && max_rate < 4.3e9 && accel < 4.3e9)) return -1;
  ProfileConstants k;
  const MotionSettings s{kStepTickHz, uint32_t(max_rate), uint32_t(accel)};
  if (profile_constants(k, s) != kMotionOk) return -1;
  return double(k.first) / kStepTickHz;
}

}  // namespace articula::host
