// host/lib/robot_file.h - reads a robot file (robots/README.md) into a Robot.
#ifndef ARTICULA_HOST_ROBOT_FILE_H
#define ARTICULA_HOST_ROBOT_FILE_H

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "robot.h"

namespace articula::host {

// A robot file that cannot be used. what() names the file, the JSON path and the
// problem: "robots/arm.json: /dh/2/theta/min: limits inverted (min 130 > max 36)".
// The path is a JSON pointer (RFC 6901); when the problem is the file as a whole (not found,
// not JSON) it is empty and left out: "robots/arm.json: file not found".
class RobotFileError : public std::runtime_error {
 public:
  RobotFileError(const std::string& file, const std::string& json_path, const std::string& problem);
  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, json_path_, problem_;
};

// Loads and checks a robot file. Throws RobotFileError.
Robot load_robot_file(const std::string& path);

// The same from text already in memory; `name` stands for the file in messages.
Robot parse_robot(const std::string& json_text, const std::string& name);

// A robot given by name ("mk2plus") is looked up in the shipped robots/ folder; a path
// ("robots/mk2plus.json", "./my.json") is used as it is.
std::string resolve_robot_path(const std::string& name_or_path);

// The fields the loader accepts in each kind of object of a robot file, keyed by the name
// robots/robot.schema.json gives that object under "$defs"; "robot" is the top level. The
// schema test checks the schema against this list, so the two cannot drift apart.
const std::map<std::string, std::vector<std::string>>& robot_file_fields();

// A number from a robot or scene file, in a message about it, as a person would write it and
// close to how the file wrote it (10 significant digits: 130, -0.7, 1e+20). Not a protocol
// number (protocol_number, blocks.h: thousandths) nor a note's (number_text, 6 digits).
std::string file_number(double v);

}  // namespace articula::host

#endif  // ARTICULA_HOST_ROBOT_FILE_H
