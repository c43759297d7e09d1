// host/lib/legacy.h - the original system's robot text file (thesis appendix C) turned
// into a robot file (robots/README.md): what maps is kept, what does not is listed.
#ifndef ARTICULA_HOST_LEGACY_H
#define ARTICULA_HOST_LEGACY_H

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace articula::host {

struct LegacyImport {
  nlohmann::json robot;               // the robot file, ready to write
  std::vector<std::string> dropped;   // each thing that does not map, with its place
};

// A legacy file that cannot be read: what() is "<file>:<line>: <problem>".
class LegacyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads the appendix C format (values only, in the order of its 20 sets; '#' comments and
// blank lines ignored). Lengths are multiplied by mm_per_unit (the original's Unity units
// had no fixed size: the thesis's MK2 model used 25.75 mm a unit). Throws LegacyError.
LegacyImport import_legacy(const std::string& text, const std::string& name, double mm_per_unit);

}  // namespace articula::host

#endif  // ARTICULA_HOST_LEGACY_H
