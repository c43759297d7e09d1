// The gripper's servo scale (articula/servo.h): aperture to pulse, pulse back to angle and
// aperture, in float as on the Nano and in double as in the emulators.
#include <articula/servo.h>
#include <gtest/gtest.h>

using namespace articula;

TEST(Servo, EndsOfTheScaleAreTheServoLibrarys) {
  EXPECT_EQ(servo_pulse_us<float>(0.0f, 180.0f, 0), 544);
  EXPECT_EQ(servo_pulse_us<float>(0.0f, 180.0f, 100000), 2400);
  EXPECT_EQ(servo_pulse_us<float>(0.0f, 180.0f, 50000), 1472);  // 90 degrees
}

TEST(Servo, ApertureRunsFromClosedToOpen) {
  // the MK2's gripper closes at 150 degrees and opens at 60: a reversed servo
  EXPECT_EQ(servo_pulse_us<float>(150.0f, 60.0f, 0), servo_pulse_us<float>(0.0f, 180.0f, 83333));
  EXPECT_EQ(servo_pulse_us<float>(150.0f, 60.0f, 100000), 1163);  // 60 degrees: 544 + 618.67 us, rounded
}

TEST(Servo, AnglesBeyondTheServosRangeAreHeldAtItsEnds) {
  EXPECT_EQ(servo_pulse_us<float>(-40.0f, 0.0f, 0), 544);
  EXPECT_EQ(servo_pulse_us<float>(170.0f, 220.0f, 100000), 2400);
}

TEST(Servo, APulseReadsBackAsTheApertureAskedFor) {
  for (int32_t aperture = 0; aperture <= 100000; aperture += 2500) {
    const double us = servo_pulse_us<float>(150.0f, 60.0f, aperture);
    const double angle = servo_angle_deg(us);
    // a whole microsecond is 0.097 degrees, 0.11 % of this 90-degree range
    EXPECT_NEAR(servo_aperture_percent(angle, 150.0, 60.0), aperture / 1000.0, 0.11) << aperture;
  }
  EXPECT_DOUBLE_EQ(servo_angle_deg(544.0), 0.0);
  EXPECT_DOUBLE_EQ(servo_angle_deg(2400.0), 180.0);
}
