// host/tests/test_robots.h - the robots the host tests share, loaded once a program.
#ifndef ARTICULA_HOST_TESTS_TEST_ROBOTS_H
#define ARTICULA_HOST_TESTS_TEST_ROBOTS_H

#include <string>

#include "robot_file.h"

// The shipped MK2 Plus (robots/mk2plus.json).
inline const articula::host::Robot& mk2() {
  static const articula::host::Robot r =
      articula::host::load_robot_file(std::string(ARTICULA_SOURCE_DIR) + "/robots/mk2plus.json");
  return r;
}

#endif  // ARTICULA_HOST_TESTS_TEST_ROBOTS_H
