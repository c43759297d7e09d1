// firmware/test/pio_main.h - the main() PlatformIO's googletest runner needs: it builds each
// test folder as a program of its own (`pio test -e native`). CMake links gtest_main instead,
// so this is compiled only under PlatformIO (PIO_UNIT_TESTING). Included once per test folder.
#ifndef ARTICULA_FIRMWARE_TEST_PIO_MAIN_H
#define ARTICULA_FIRMWARE_TEST_PIO_MAIN_H
#ifdef PIO_UNIT_TESTING
#include <gtest/gtest.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int failed = RUN_ALL_TESTS();
  (void)failed;
  return 0;  // PlatformIO reads the results from the output
}
#endif
#endif
