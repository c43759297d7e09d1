// python/src/protocol.cpp - the arm's protocol from the core (host/lib/protocol_view.h): the
// status table, a line from the arm read by the firmware's own parsers, and the motion
// profile's first step. articula.link and the harness (hil/harness) read the arm with these,
// as the studio's page does through the web engine.
#include <articula/motion.h>
#include <articula/settings.h>
#include <nanobind/stl/string.h>

#include <articula/status.h>

#include "bindings.h"
#include "draw.h"
#include "program.h"
#include "protocol_view.h"

namespace articula::python {

using namespace nb::literals;

void bind_protocol(nb::module_& m) {
  // The status table: shared/articula/status.h, the one table the firmware and every tool use.
  nb::dict status;
  for (uint8_t c = 0; c < kStatusCount; ++c) status[nb::int_(c)] = nb::make_tuple(status_name(c), status_text(c));
  m.attr("_status_table") = status;
  // The firmware's step timer, ticks a second (shared/articula/motion.h): every time in a
  // prediction's records counts in them.
  m.attr("STEP_TICK_HZ") = kStepTickHz;
  // The settings table: shared/articula/settings.h, for a three-motor arm.
  nb::dict settings;
  for (uint8_t n = 0; n < kSettingCount; ++n) {
    const SettingRange r = setting_range(n, 3);
    settings[nb::int_(n)] = nb::make_tuple(r.min, r.max, r.fallback);
  }
  m.attr("_settings_table") = settings;
  // The pen's settings (host/lib/draw.h kPenFields), for a drawing's defaults and ranges.
  m.attr("_pen_fields") = json_to_python(host::pen_fields_json());

  m.def("parse_arm_line", [](const std::string& line) { return json_to_python(host::arm_line_json(line)); }, "line"_a,
        "A line from the arm, read by the firmware's own parsers (shared/articula/protocol.h): a dict with kind "
        "'reply' (code), 'status' (state, steps, angles in deg, millideg, gripper, free, coils, warning), 'info' "
        "(version, protocol, joints, robot, warning), 'setting' (number, value) or 'other'.");
  m.def("line_command", &host::line_command, "line"_a,
        "A protocol line as the arm acts on it: what comes before its comment ('#'), without blanks around it; "
        "'' for a blank line or a comment alone (host/lib/program.h, the core's comment_start).");
  m.def("first_interval_s", &host::first_interval_s, "max_rate"_a, "accel"_a,
        "The first step interval of a move from rest at $0 = max_rate steps/s and $1 = accel steps/s^2, in "
        "seconds (shared/articula/motion.h's profile); -1 for settings the firmware refuses.");
}

}  // namespace articula::python
