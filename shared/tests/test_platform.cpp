// Tests shared/articula/platform.h: scalar math dispatch, finiteness, unit conversion.
#include <articula/platform.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
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

// ---- Math<S>::sincos: the library for float (and on AVR), the fast path for double on the
// host (platform.h, detail::sincos_kernel), checked against the library.
namespace {

// The error of got in units of the last place of ref, counted in the finer spacing where
// ref is a power of two (the spacing towards zero): strict.
double ulps(double got, double ref) {
  if (got == ref) return 0;
  if (std::isnan(got) || std::isnan(ref)) return std::isnan(got) && std::isnan(ref) ? 0 : 1e300;
  const double spacing = ref == 0 ? std::numeric_limits<double>::denorm_min() : std::fabs(ref - std::nextafter(ref, 0.0));
  return std::fabs(got - ref) / spacing;
}

struct SinCosErrors {
  double sin_ulps = 0, cos_ulps = 0, pythagoras = 0;
  double worst_sin_x = 0, worst_cos_x = 0;
  long count = 0;
  void add(double x) {
    double s, c;
    Math<double>::sincos(x, s, c);
    const double es = ulps(s, std::sin(x)), ec = ulps(c, std::cos(x));
    if (es > sin_ulps) sin_ulps = es, worst_sin_x = x;
    if (ec > cos_ulps) cos_ulps = ec, worst_cos_x = x;
    if (std::isfinite(x)) pythagoras = std::max(pythagoras, std::fabs(s * s + c * c - 1));
    ++count;
  }
  void print(const char* what) const {
    std::printf("%s: %ld arguments, max error sin %.3f ulp (x = %.17g), cos %.3f ulp (x = %.17g), "
                "max |sin^2 + cos^2 - 1| = %.3g\n",
                what, count, sin_ulps, worst_sin_x, cos_ulps, worst_cos_x, pythagoras);
  }
};

}  // namespace

TEST(PlatformSinCos, FloatIsTheLibrary) {
  for (float x : {0.0f, 0.7f, -2.5f, 1e4f, 3.1415927f}) {
    float s, c;
    Math<float>::sincos(x, s, c);
    EXPECT_EQ(s, ::sinf(x));
    EXPECT_EQ(c, ::cosf(x));
  }
}

TEST(PlatformSinCos, TenMillionRandomArgumentsWithin2UlpOfTheLibrary) {
  // Uniform in [-1000, 1000] rad (fixed seed): against glibc's sin and cos, which are
  // within 1 ulp of the true values. Measured here: at most 1 ulp.
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<double> u(-1000, 1000);
  SinCosErrors e;
  for (int i = 0; i < 10000000; ++i) e.add(u(rng));
  e.print("random in [-1000, 1000]");
  EXPECT_LE(e.sin_ulps, 2.0);
  EXPECT_LE(e.cos_ulps, 2.0);
  EXPECT_LE(e.pythagoras, 4e-16);
}

TEST(PlatformSinCos, SpecialPointsWithin2UlpOfTheLibrary) {
  SinCosErrors e;
  // Multiples of pi/4 and pi/2 as the code computes them (k * pi/4 and deg_to_rad of whole
  // multiples of 45 and 90 deg), and their neighbours, up to the fallback bound 1e5.
  for (int k = -127323; k <= 127323; ++k) {
    const double xs[3] = {k * (M_PI / 4), deg_to_rad(45.0 * k), deg_to_rad(90.0 * (k / 2))};
    for (double x : xs) {
      if (std::fabs(x) > 1e5) continue;
      e.add(x);
      e.add(std::nextafter(x, 1e6));
      e.add(std::nextafter(x, -1e6));
    }
  }
  // Tiny arguments, zero, subnormals.
  for (double x = 1e-300; x < 1; x *= 3.7) e.add(x), e.add(-x);
  for (double x : {0.0, -0.0, 4.9e-324, -4.9e-324, 2.2250738585072014e-308, 1e-8, 1.4901161193847656e-8}) e.add(x);
  // At the fallback bound 1e5 (|k| < 2^16 inside) and beyond it (the library).
  for (double x : {1e5, -1e5, std::nextafter(1e5, 0.0), std::nextafter(1e5, 2e5), 65535 * M_PI_2, 65536 * M_PI_2,
                   1e6, -3e7, 1e22, 1e300, -1e300, std::numeric_limits<double>::max()})
    e.add(x);
  for (double x = 99000; x <= 101000; x += 0.37) e.add(x), e.add(-x);
  e.print("special points");
  EXPECT_LE(e.sin_ulps, 2.0);
  EXPECT_LE(e.cos_ulps, 2.0);
  EXPECT_LE(e.pythagoras, 4e-16);
}

TEST(PlatformSinCos, ExactWhereTheLibraryIsExactAndNanStaysNan) {
  double s, c;
  Math<double>::sincos(0.0, s, c);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(c, 1.0);
  Math<double>::sincos(deg_to_rad(90.0), s, c);  // exactly the double nearest pi/2
  EXPECT_EQ(s, 1.0);
  EXPECT_EQ(c, std::cos(deg_to_rad(90.0)));  // 6.1e-17, as the library
  Math<double>::sincos(deg_to_rad(180.0), s, c);
  EXPECT_EQ(c, -1.0);
  EXPECT_EQ(s, std::sin(deg_to_rad(180.0)));
  for (double x : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()}) {
    Math<double>::sincos(x, s, c);
    EXPECT_TRUE(std::isnan(s));
    EXPECT_TRUE(std::isnan(c));
  }
}

TEST(PlatformSinCos, ManyAtOnceEqualsOneAtATime) {
  // sincos_n and sincos2 (two at a time in SIMD lanes) give sincos's bits, for odd and even
  // counts and with arguments for the library mixed in.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int n = 0; n <= 9; ++n) {
    for (int trial = 0; trial < 2000; ++trial) {
      double x[9], s[9], c[9];
      for (int i = 0; i < n; ++i) x[i] = trial % 7 == 3 && i == n / 2 ? 2e5 * u(rng) : u(rng) * (trial % 3 == 0 ? 250 : 1);
      if (n > 2 && trial == 5) x[1] = std::numeric_limits<double>::quiet_NaN();
      Math<double>::sincos_n(x, s, c, n);
      for (int i = 0; i < n; ++i) {
        double s1, c1;
        Math<double>::sincos(x[i], s1, c1);
        ASSERT_EQ(std::memcmp(&s1, &s[i], sizeof s1), 0) << "x = " << x[i];
        ASSERT_EQ(std::memcmp(&c1, &c[i], sizeof c1), 0) << "x = " << x[i];
      }
    }
  }
  for (int trial = 0; trial < 20000; ++trial) {  // and sincos2, two at once
    const double x0 = u(rng) * (trial % 5 == 0 ? 3e4 : 1), x1 = trial % 11 == 0 ? 3e5 : u(rng);
    double s0, c0, s1, c1, s0r, c0r, s1r, c1r;
    Math<double>::sincos2(x0, x1, s0, c0, s1, c1);
    Math<double>::sincos(x0, s0r, c0r);
    Math<double>::sincos(x1, s1r, c1r);
    ASSERT_EQ(std::memcmp(&s0, &s0r, sizeof s0), 0) << x0;
    ASSERT_EQ(std::memcmp(&c0, &c0r, sizeof c0), 0) << x0;
    ASSERT_EQ(std::memcmp(&s1, &s1r, sizeof s1), 0) << x1;
    ASSERT_EQ(std::memcmp(&c1, &c1r, sizeof c1), 0) << x1;
  }
  float xf[3] = {0.5f, -1.0f, 2.0f}, sf[3], cf[3];
  Math<float>::sincos_n(xf, sf, cf, 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(sf[i], ::sinf(xf[i]));
    EXPECT_EQ(cf[i], ::cosf(xf[i]));
  }
}
