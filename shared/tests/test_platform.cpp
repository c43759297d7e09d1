// Tests shared/articula/platform.h: scalar math dispatch, finiteness, unit conversion.
#include <articula/platform.h>
#include <gtest/gtest.h>

#include <limits>
#include <type_traits>

using namespace articula;

TEST(Platform, MathDispatchesOnTheScalarType) {
  static_assert(std::is_same<decltype(Math<float>::sin(1.0f)), float>::value, "float in, float out");
  static_assert(std::is_same<decltype(Math<double>::sin(1.0)), double>::value, "double in, double out");
  // sinf and sin differ in the last bits for most arguments; the float path must be float.
  EXPECT_EQ(Math<float>::sin(0.7f), ::sinf(0.7f));
  EXPECT_EQ(Math<double>::sin(0.7), ::sin(0.7));
  EXPECT_EQ(Math<double>::epsilon(), std::numeric_limits<double>::epsilon());
  EXPECT_EQ(Math<float>::epsilon(), std::numeric_limits<float>::epsilon());
}

TEST(Platform, IsFiniteRejectsNanAndInfinityOnly) {
  EXPECT_TRUE(is_finite(0.0));
  EXPECT_TRUE(is_finite(-1e300));
  EXPECT_TRUE(is_finite(std::numeric_limits<double>::denorm_min()));
  EXPECT_TRUE(is_finite(std::numeric_limits<float>::max()));
  EXPECT_FALSE(is_finite(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(is_finite(std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(is_finite(-std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(is_finite(std::numeric_limits<float>::quiet_NaN()));
}

TEST(Platform, DegreesAndRadians) {
  EXPECT_DOUBLE_EQ(deg_to_rad(180.0), M_PI);
  EXPECT_DOUBLE_EQ(rad_to_deg(M_PI / 2), 90.0);
  EXPECT_FLOAT_EQ(deg_to_rad(90.0f), float(M_PI / 2));
  EXPECT_DOUBLE_EQ(rad_to_deg(deg_to_rad(-37.25)), -37.25);
}

TEST(Platform, ClampMinMax) {
  EXPECT_EQ(clamp(5, 0, 3), 3);
  EXPECT_EQ(clamp(-5, 0, 3), 0);
  EXPECT_EQ(clamp(2, 0, 3), 2);
  EXPECT_EQ(min_of(2.0, -1.0), -1.0);
  EXPECT_EQ(max_of(2.0, -1.0), 2.0);
  EXPECT_EQ(square(-3), 9);
}
