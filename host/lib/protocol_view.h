// host/lib/protocol_view.h - the arm's protocol for the bindings (python/src, wasm/src), from
// the core's own code (shared/articula/protocol.h, status.h, motion.h): a line from the arm
// read by the firmware's parsers, the status table, the motion profile's first step. So the
// harness (hil/), articula.link and the studio read the arm with the firmware's parsers and
// time it with the firmware's profile, and keep no copy of either.
#ifndef ARTICULA_HOST_PROTOCOL_VIEW_H
#define ARTICULA_HOST_PROTOCOL_VIEW_H

#include <nlohmann/json.hpp>

#include <string>

namespace articula::host {

// A line from the arm: {"kind": "reply", "code"}, a status report {"kind": "status", "state",
// "steps", "angles" (deg), "gripper", "free", "coils", "warning", "fields" (every field as
// text, by its letter)}, the banner {"kind": "info", "version", "protocol", "joints", "robot",
// "warning"}, or {"kind": "other"}.
nlohmann::json arm_line_json(const std::string& line);

// The protocol's status table: {"0": ["ok", "..."], "9": ["limit", "target beyond ..."], ...}.
nlohmann::json status_table_json();

// The first step interval of a move from rest at these settings ($0 steps/s, $1 steps/s^2),
// s (motion.h's profile): no pin shows when a move starts, so an emulated Nano's measured
// duration is this plus the span of the move's steps. -1 for settings the profile refuses.
double first_interval_s(double max_rate, double accel);

}  // namespace articula::host

#endif  // ARTICULA_HOST_PROTOCOL_VIEW_H
