// articula/platform.h - the few things the core needs from the platform.
//
// The core compiles unchanged with avr-g++ 5.4 (-std=gnu++11, no C++ standard library,
// sizeof(double) == 4, sizeof(int) == 2) and with g++ 12 (-std=c++17). So it includes C
// headers only and names nothing from std::. Feature differences are detected here, once.
#ifndef ARTICULA_PLATFORM_H
#define ARTICULA_PLATFORM_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

namespace articula {

// Scalar math, dispatched on the scalar type so float code calls the float functions
// (sinf, not sin) on the host. On AVR both map to the same 32-bit routines.
template <typename Scalar>
struct Math;

template <>
struct Math<float> {
  static float sin(float x) { return ::sinf(x); }
  static float cos(float x) { return ::cosf(x); }
  static float sqrt(float x) { return ::sqrtf(x); }
  static float atan2(float y, float x) { return ::atan2f(y, x); }
  static float acos(float x) { return ::acosf(x); }
  static float fabs(float x) { return ::fabsf(x); }
  static float epsilon() { return 1.1920929e-7f; }
};

template <>
struct Math<double> {
  static double sin(double x) { return ::sin(x); }
  static double cos(double x) { return ::cos(x); }
  static double sqrt(double x) { return ::sqrt(x); }
  static double atan2(double y, double x) { return ::atan2(y, x); }
  static double acos(double x) { return ::acos(x); }
  static double fabs(double x) { return ::fabs(x); }
  // On AVR double is float; the epsilon follows the real width.
  static double epsilon() { return sizeof(double) == 4 ? 1.1920929e-7 : 2.220446049250313e-16; }
};

template <typename Scalar>
inline Scalar pi() {
  return Scalar(3.14159265358979323846);
}

template <typename Scalar>
inline Scalar deg_to_rad(Scalar deg) {
  return deg * (pi<Scalar>() / Scalar(180));
}

template <typename Scalar>
inline Scalar rad_to_deg(Scalar rad) {
  return rad * (Scalar(180) / pi<Scalar>());
}

// True for every value but NaN and +-inf. Written without isfinite(), which is a macro in
// C, a function in avr-libc and std::isfinite in C++: x - x is 0 for finite x and NaN
// otherwise, and NaN never equals itself. (Valid without -ffast-math, which we never use.)
template <typename Scalar>
inline bool is_finite(Scalar x) {
  volatile Scalar d = x - x;  // volatile: keep the comparison honest under optimisation
  return d == d;
}

template <typename T>
inline T min_of(T a, T b) {
  return b < a ? b : a;
}

template <typename T>
inline T max_of(T a, T b) {
  return a < b ? b : a;
}

template <typename T>
inline T clamp(T x, T lo, T hi) {
  return x < lo ? lo : (hi < x ? hi : x);
}

template <typename T>
inline T square(T x) {
  return x * x;
}

}  // namespace articula

#endif  // ARTICULA_PLATFORM_H
