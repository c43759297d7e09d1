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
#include <string.h>

// ARTICULA_UNROLL3 before a loop of 3 (x, y, z) asks for it to be unrolled, and
// ARTICULA_INLINE for a function to be inlined, on host compilers that honour it (g++ -O2
// unrolls such loops rarely by itself). Elsewhere they are nothing (avr-g++ 5.4 does not
// know the pragma, and the Nano prefers the smaller code anyway).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 8 && !defined(__AVR__)
#define ARTICULA_UNROLL3 _Pragma("GCC unroll 3")
#else
#define ARTICULA_UNROLL3
#endif
#if defined(__GNUC__) && !defined(__AVR__)
#define ARTICULA_INLINE inline __attribute__((always_inline))
#else
#define ARTICULA_INLINE inline
#endif

// ARTICULA_IN_FLASH on a constant table keeps it in flash on the Nano (PROGMEM: its RAM is
// short), read with from_flash(); elsewhere both are nothing.
#if defined(__AVR__)
#include <avr/pgmspace.h>
#define ARTICULA_IN_FLASH PROGMEM
#else
#define ARTICULA_IN_FLASH
#endif

namespace articula {

// A copy of a constant marked ARTICULA_IN_FLASH.
template <class T>
inline T from_flash(const T& x) {
#if defined(__AVR__)
  T t;
  memcpy_P(&t, &x, sizeof t);
  return t;
#else
  return x;
#endif
}

// Whether to take the faster, larger code paths (dh.h): not on the Nano, where flash is
// short.
#if defined(__AVR__)
static const bool kFastHost = false;
#else
static const bool kFastHost = true;
#endif

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
  // sin and cos of one angle (the library's, one call each), so templates can ask for both.
  static void sincos(float x, float& s, float& c) { s = ::sinf(x), c = ::cosf(x); }
  static void sincos2(float x0, float x1, float& s0, float& c0, float& s1, float& c1) {
    sincos(x0, s0, c0), sincos(x1, s1, c1);
  }
  static void sincos_n(const float* x, float* s, float* c, int n) {
    for (int i = 0; i < n; ++i) sincos(x[i], s[i], c[i]);
  }
};

namespace detail {
// The bits of one value as another type of the same size (memcpy: defined behaviour, and
// compiled to a register move).
template <typename To, typename From>
inline To bit_copy(const From& from) {
  To to;
  memcpy(&to, &from, sizeof(To));
  return to;
}

// The constants of the fast sin and cos below (sincos_kernel), in the order of the list
// ARTICULA_SINCOS_CONSTANTS: 2/pi, 1.5 * 2^52, P1, P2, P3, s1..s8, c2..c8, 1/2, 1.
enum SinCosConstant {
  kScTwoOverPi, kScShift, kScP1, kScP2, kScP3,
  kScS1, kScS2, kScS3, kScS4, kScS5, kScS6, kScS7, kScS8,
  kScC2, kScC3, kScC4, kScC5, kScC6, kScC7, kScC8,
  kScHalf, kScOne, kScCount
};
// Their values, written once as an X macro (a list that expands at each use).
#define ARTICULA_SINCOS_CONSTANTS(X)                                                        \
  X(0.63661977236758134)     /* 2/pi, the nearest double */                                \
  X(6755399441055744.0)      /* 1.5 * 2^52 */                                              \
  X(1.5707963267923333)      /* P1 = 0x1.921fb5444p+0 (37 bits) */                         \
  X(2.5633441515839558e-12)  /* P2 = 0x1.68c234c4cp-39 (37 bits) */                        \
  X(1.0562999066987428e-23)  /* P3 = 0x1.98a2e03707345p-77 */                              \
  /* sin r = r + r z (s1 + s2 z + ... + s8 z^7), s_n = (-1)^n / (2n+1)! */                 \
  X(-1.0 / 6.0) X(1.0 / 120.0) X(-1.0 / 5040.0) X(1.0 / 362880.0) X(-1.0 / 39916800.0)     \
  X(1.0 / 6227020800.0) X(-1.0 / 1307674368000.0) X(1.0 / 355687428096000.0)               \
  /* cos r = 1 - z/2 + z^2 (c2 + c3 z + ... + c8 z^6), c_n = (-1)^n / (2n)! */             \
  X(1.0 / 24.0) X(-1.0 / 720.0) X(1.0 / 40320.0) X(-1.0 / 3628800.0) X(1.0 / 479001600.0) \
  X(-1.0 / 87178291200.0) X(1.0 / 20922789888000.0)                                        \
  X(0.5) X(1.0)

// The constants as lanes of V: a plain array for double.
template <typename V>
struct SinCosTable {
  static const double* get() {
#define ARTICULA_SC_SCALAR(k) k,
    static const double table[kScCount] = {ARTICULA_SINCOS_CONSTANTS(ARTICULA_SC_SCALAR)};
#undef ARTICULA_SC_SCALAR
    return table;
  }
};
// k in every lane of U, an unsigned integer or a vector of them.
template <typename U>
inline U splat_u(uint64_t k) {
  return U(k);
}

// Two doubles at a time in SIMD lanes, with the GCC vector extension (g++ and clang++ on
// x86-64, SSE2, AArch64, and WebAssembly with its SIMD, emscripten -msimd128).
#if defined(__GNUC__) && (defined(__SSE2__) || defined(__aarch64__) || defined(__wasm_simd128__))
#define ARTICULA_SIMD2 1
typedef double DoubleX2 __attribute__((vector_size(16)));
typedef uint64_t Uint64X2 __attribute__((vector_size(16)));
// For two lanes, an array of vector constants whose address the compiler is made to
// forget (the empty asm): otherwise g++ rebuilds each one at each use from a scalar
// (a load and a shuffle, -march=x86-64) instead of using it as a memory operand.
template <>
struct SinCosTable<DoubleX2> {
  static const DoubleX2* get() {
#define ARTICULA_SC_VECTOR(k) {k, k},
    static const DoubleX2 table[kScCount] = {ARTICULA_SINCOS_CONSTANTS(ARTICULA_SC_VECTOR)};
#undef ARTICULA_SC_VECTOR
    const DoubleX2* p = table;
    __asm__("" : "+r"(p));
    return p;
  }
};
template <>
inline Uint64X2 splat_u<Uint64X2>(uint64_t k) {
  const Uint64X2 v = {k, k};
  return v;
}
#endif

// Fast sin and cos of binary64 doubles, for the host: within 1 ulp of glibc's over the
// tests' 10 million arguments and special points (tests/test_platform.cpp). Written for
// Articula from first principles, no library's source or coefficient table:
//
//  1. Range reduction by pi/2 (Cody and Waite): k = the integer nearest x * 2/pi, and
//     r = x - k * pi/2 with pi/2 split in three, P1 + P2 + P3, so that the reduction
//     stays exact where it matters. P1 is pi/2 rounded to 37 significant bits and P2 the
//     rest rounded to 37 bits: |k| < 2^16 (|x| <= 1e5), so k*P1 and k*P2 are exact
//     products, and x - k*P1 is exact (both are multiples of 2^-53 and the difference is
//     below 1). P3 is the remainder rounded to 53 bits; P1 + P2 + P3 is pi/2 to 5e-40.
//     The one rounded subtraction, (x - k*P1) - k*P2, has its error recovered exactly
//     (Knuth's TwoSum) and kept with -k*P3 as a tail t, so the reduced angle is r + t
//     to about 2^-110 absolute, enough even for x next to a multiple of pi/2.
//     (A two-part split with P1 the double nearest pi/2 needs a fused multiply-add to
//     make k*P1 exact; the x86-64 baseline has none, hence three parts.) The constants
//     were computed with exact rational arithmetic from pi to 400 bits by Machin's
//     formula, pi/4 = 4 atan(1/5) - atan(1/239): bench/sincos_constants.py recomputes
//     them and checks the values here. k is rounded by adding and subtracting 1.5 * 2^52,
//     which also leaves k mod 4 in the low bits of the sum.
//  2. Taylor polynomials on |r| <= pi/4 (a hair more where x * 2/pi rounds the other way):
//     sin r = sum (-1)^n r^(2n+1) / (2n+1)!, n = 0..8 (the first term left out,
//     r^19/19!, is below 8.4e-20 at pi/4); cos r = sum (-1)^n r^(2n) / (2n)!, n = 0..8
//     (left out: r^18/18! < 2.1e-18). The coefficients are the reciprocals of the
//     factorials (all exact below 2^53), rounded once by the compiler. Each polynomial in
//     z = r^2 is evaluated by Estrin's scheme (shorter dependency chains than Horner's,
//     which measured slower in the forward kinematics despite fewer instructions), the
//     large terms last: r for sin, and for cos 1 - z/2 with the error of that
//     subtraction recovered (Fast2Sum). The tail enters to first order:
//     sin(r + t) = sin r + t cos r, cos(r + t) = cos r - t sin r.
//  3. The quadrant k mod 4 picks (sin, cos) = (S, C), (C, -S), (-S, -C), (-C, S) with bit
//     operations (select and sign flip: exact, no unpredictable branch).
// The callers send |x| > 1e5, NaN and +-inf to the library. sin(-0) comes out +0. V is
// double, or two doubles in a vector with U the unsigned integer vector of the same
// layout: the same operations in each lane, so both give identical results. Needs IEEE
// round-to-nearest arithmetic without excess precision or reassociation (x86-64 SSE2,
// AArch64; never -ffast-math), as the rest of the core does. (Fused multiply-adds, where
// a compiler contracts them, keep every step above exact or better.)
template <typename V, typename U>
ARTICULA_INLINE void sincos_kernel(V x, V& s, V& c) {
  const auto* K = SinCosTable<V>::get();
  const V shifted = x * K[kScTwoOverPi] + K[kScShift];  // 1.5 * 2^52 + k: k mod 4 in the low bits
  const V kd = shifted - K[kScShift];
  const U q = bit_copy<U>(shifted);
  const V r1 = x - kd * K[kScP1];  // exact
  const V t2 = kd * K[kScP2];      // exact
  const V r = r1 - t2;
  const V v = r - r1;  // TwoSum: r1 - t2 = r + e exactly
  const V e = (r1 - (r - v)) - (t2 + v);
  const V t = e - kd * K[kScP3];

  const V z = r * r, z2 = z * z, z4 = z2 * z2;
  const V ps = ((K[kScS1] + K[kScS2] * z) + (K[kScS3] + K[kScS4] * z) * z2) +
               ((K[kScS5] + K[kScS6] * z) + (K[kScS7] + K[kScS8] * z) * z2) * z4;
  const V pc = ((K[kScC2] + K[kScC3] * z) + (K[kScC4] + K[kScC5] * z) * z2) +
               ((K[kScC6] + K[kScC7] * z) + K[kScC8] * z2) * z4;
  // sin: r last; the tail as t cos r with cos r ~ 1 - z/2 (the rest is below 0.02 ulp).
  const V h = K[kScHalf] * z;
  const V S = r + (r * z * ps + (t - t * h));
  // cos: 1 - h rounds (up to 0.5 ulp, the largest error there would be); its error
  // (1 - w) - h is exact (Fast2Sum, 1 > h) and joins the small terms; the tail as
  // -t sin r ~ -t r.
  const V w = K[kScOne] - h;
  const V C = w + (((K[kScOne] - w) - h) + (z2 * pc - t * r));

  // Quadrant: odd k swaps S and C; sin is negated for k mod 4 in {2, 3}, cos for {1, 2}.
  const U one_u = splat_u<U>(1), two_u = splat_u<U>(2);
  const U swap = -(q & one_u);  // all ones for odd k
  const U neg_s = (q & two_u) << 62;
  const U neg_c = ((q + one_u) & two_u) << 62;
  const U Sb = bit_copy<U>(S), Cb = bit_copy<U>(C);
  s = bit_copy<V>(((Cb & swap) | (Sb & ~swap)) ^ neg_s);
  c = bit_copy<V>(((Sb & swap) | (Cb & ~swap)) ^ neg_c);
}

// Where the fast path runs: |x| <= 1e5 (so |k| < 2^16), not NaN or inf.
inline bool sincos_fast_range(double x) { return x <= 1e5 && x >= -1e5; }

// sin and cos of doubles: the primary template is the library (AVR, where double is 32
// bits); binary64 doubles take the fast path above.
template <typename D, bool Binary64 = sizeof(D) == 8>
struct SinCos {
  static void eval(D x, D& s, D& c) { s = ::sin(x), c = ::cos(x); }
  static void eval2(D x0, D x1, D& s0, D& c0, D& s1, D& c1) { eval(x0, s0, c0), eval(x1, s1, c1); }
  static void eval_n(const D* x, D* s, D* c, int n) {
    for (int i = 0; i < n; ++i) eval(x[i], s[i], c[i]);
  }
};

template <typename D>
struct SinCos<D, true> {
  static void eval(D x, D& s, D& c) {
    if (sincos_fast_range(x)) {
      sincos_kernel<D, uint64_t>(x, s, c);
    } else {
      s = ::sin(x), c = ::cos(x);
    }
  }
  // Two at a time in SIMD lanes where there are (ARTICULA_SIMD2): the same results as
  // eval, one at a time.
  static ARTICULA_INLINE void eval2(D x0, D x1, D& s0, D& c0, D& s1, D& c1) {
#ifdef ARTICULA_SIMD2
    if (sincos_fast_range(x0) && sincos_fast_range(x1)) {
      const DoubleX2 x = {x0, x1};
      DoubleX2 s, c;
      sincos_kernel<DoubleX2, Uint64X2>(x, s, c);
      s0 = s[0], s1 = s[1], c0 = c[0], c1 = c[1];
      return;
    }
#endif
    eval(x0, s0, c0);
    eval(x1, s1, c1);
  }
  static void eval_n(const D* x, D* s, D* c, int n) {
    int i = 0;
    for (; i + 1 < n; i += 2) eval2(x[i], x[i + 1], s[i], c[i], s[i + 1], c[i + 1]);
    if (i < n) eval(x[i], s[i], c[i]);
  }
};
}  // namespace detail

template <>
struct Math<double> {
  static double sin(double x) { return ::sin(x); }
  static double cos(double x) { return ::cos(x); }
  static double sqrt(double x) { return ::sqrt(x); }
  static double atan2(double y, double x) { return ::atan2(y, x); }
  static double acos(double x) { return ::acos(x); }
  static double fabs(double x) { return ::fabs(x); }
  // sin and cos of one angle: on the host the fast path above (detail::sincos_kernel,
  // within 1 ulp of glibc's in the tests), on AVR the library's two calls.
  static void sincos(double x, double& s, double& c) { detail::SinCos<double>::eval(x, s, c); }
  // sincos of two angles (x0, x1): what two calls of sincos give, but at once, in the two
  // lanes of SIMD registers on the host.
  static ARTICULA_INLINE void sincos2(double x0, double x1, double& s0, double& c0, double& s1, double& c1) {
    detail::SinCos<double>::eval2(x0, x1, s0, c0, s1, c1);
  }
  // sincos of n angles: s[i], c[i] exactly as sincos(x[i], s[i], c[i]) gives them, but
  // two at a time in SIMD lanes on the host (x, s and c must not overlap).
  static void sincos_n(const double* x, double* s, double* c, int n) { detail::SinCos<double>::eval_n(x, s, c, n); }
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
