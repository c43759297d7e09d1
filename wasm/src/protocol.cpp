// wasm/src/protocol.cpp - the arm's protocol for JavaScript (the twin of python/src/protocol.cpp),
// from the core through host/lib/protocol_view.h: the status table, a line from the arm read
// by the firmware's own parsers, the motion profile's first step.
#include <articula/motion.h>
#include <articula/settings.h>
#include <emscripten/bind.h>

#include <articula/status.h>

#include <string>

#include "program.h"
#include "protocol_view.h"

EMSCRIPTEN_BINDINGS(articula_protocol) {
  using namespace emscripten;
  // The firmware's step timer, ticks a second (shared/articula/motion.h).
  constant("stepTickHz", articula::kStepTickHz);
  function("statusText", +[](int code) { return std::string(articula::status_text(uint8_t(code))); });
  function("statusTable", +[] { return articula::host::status_table_json().dump(); });
  // The settings table (shared/articula/settings.h) for a three-motor arm: [[min, max, default], ...].
  function("settingsTable", +[] {
    std::string out = "[";
    for (uint8_t n = 0; n < articula::kSettingCount; ++n) {
      const articula::SettingRange r = articula::setting_range(n, 3);
      out += (n ? ",[" : "[") + std::to_string(r.min) + "," + std::to_string(r.max) + "," + std::to_string(r.fallback) + "]";
    }
    return out + "]";
  });
  function("lineCommand", &articula::host::line_command);
  function("parseArmLine", +[](const std::string& line) { return articula::host::arm_line_json(line).dump(); });
  function("firstIntervalS", &articula::host::first_interval_s);
}
