// articula/transform.h - fixed-size 3D vectors, rotations and rigid transforms.
//
// Plain structs, no heap, templated on the scalar. Names follow the monogram habit:
// T_a_b maps coordinates in frame b to frame a, so T_a_c = T_a_b * T_b_c reads by eye.
#ifndef ARTICULA_TRANSFORM_H
#define ARTICULA_TRANSFORM_H

#include "platform.h"

namespace articula {

template <typename Scalar>
struct Vec3 {
  Scalar x, y, z;

  Scalar operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Scalar& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

template <typename Scalar>
inline Vec3<Scalar> make_vec3(Scalar x, Scalar y, Scalar z) {
  Vec3<Scalar> v = {x, y, z};
  return v;
}

template <typename S>
inline Vec3<S> operator+(const Vec3<S>& a, const Vec3<S>& b) {
  return make_vec3(a.x + b.x, a.y + b.y, a.z + b.z);
}

template <typename S>
inline Vec3<S> operator-(const Vec3<S>& a, const Vec3<S>& b) {
  return make_vec3(a.x - b.x, a.y - b.y, a.z - b.z);
}

template <typename S>
inline Vec3<S> operator*(S k, const Vec3<S>& a) {
  return make_vec3(k * a.x, k * a.y, k * a.z);
}

template <typename S>
inline S dot(const Vec3<S>& a, const Vec3<S>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <typename S>
inline Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return make_vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

template <typename S>
inline S norm(const Vec3<S>& a) {
  return Math<S>::sqrt(dot(a, a));
}

// Row-major 3x3 matrix: m[row][col].
template <typename Scalar>
struct Mat3 {
  Scalar m[3][3];

  Vec3<Scalar> col(int c) const { return make_vec3(m[0][c], m[1][c], m[2][c]); }
};

template <typename S>
inline Mat3<S> identity3() {
  Mat3<S> r = {{{S(1), S(0), S(0)}, {S(0), S(1), S(0)}, {S(0), S(0), S(1)}}};
  return r;
}

template <typename S>
inline Mat3<S> operator*(const Mat3<S>& a, const Mat3<S>& b) {
  Mat3<S> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}

template <typename S>
inline Vec3<S> operator*(const Mat3<S>& a, const Vec3<S>& v) {
  return make_vec3(a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
                   a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
                   a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z);
}

template <typename S>
inline Mat3<S> transpose(const Mat3<S>& a) {
  Mat3<S> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

template <typename S>
inline Mat3<S> rot_x(S angle) {
  const S c = Math<S>::cos(angle), s = Math<S>::sin(angle);
  Mat3<S> r = {{{S(1), S(0), S(0)}, {S(0), c, -s}, {S(0), s, c}}};
  return r;
}

template <typename S>
inline Mat3<S> rot_y(S angle) {
  const S c = Math<S>::cos(angle), s = Math<S>::sin(angle);
  Mat3<S> r = {{{c, S(0), s}, {S(0), S(1), S(0)}, {-s, S(0), c}}};
  return r;
}

template <typename S>
inline Mat3<S> rot_z(S angle) {
  const S c = Math<S>::cos(angle), s = Math<S>::sin(angle);
  Mat3<S> r = {{{c, -s, S(0)}, {s, c, S(0)}, {S(0), S(0), S(1)}}};
  return r;
}

// Roll/pitch/yaw as fixed X-Y-Z angles (Craig 2.8): R = Rz(yaw) * Ry(pitch) * Rx(roll).
template <typename S>
inline Mat3<S> rpy_to_matrix(S roll, S pitch, S yaw) {
  return rot_z(yaw) * rot_y(pitch) * rot_x(roll);
}

// Inverse of rpy_to_matrix (Craig eq. 2.66). At pitch = +-90 deg (gimbal lock) roll is
// set to 0 and the whole rotation about the vertical goes into yaw.
template <typename S>
inline Vec3<S> matrix_to_rpy(const Mat3<S>& r) {
  const S pitch = Math<S>::atan2(-r.m[2][0], Math<S>::sqrt(r.m[0][0] * r.m[0][0] + r.m[1][0] * r.m[1][0]));
  const S cp = Math<S>::cos(pitch);
  if (Math<S>::fabs(cp) < S(1e-6)) {
    // Gimbal lock: only roll - yaw (pitch +90) or roll + yaw (pitch -90) is defined.
    // With roll = 0 both cases give m[0][1] = -sin(yaw), m[1][1] = cos(yaw).
    return make_vec3(S(0), pitch, Math<S>::atan2(-r.m[0][1], r.m[1][1]));
  }
  return make_vec3(Math<S>::atan2(r.m[2][1], r.m[2][2]), pitch, Math<S>::atan2(r.m[1][0], r.m[0][0]));
}

template <typename Scalar>
struct Transform {
  Mat3<Scalar> R;
  Vec3<Scalar> p;

  static Transform identity() {
    Transform t;
    t.R = identity3<Scalar>();
    t.p = make_vec3(Scalar(0), Scalar(0), Scalar(0));
    return t;
  }
};

template <typename S>
inline Transform<S> make_transform(const Mat3<S>& R, const Vec3<S>& p) {
  Transform<S> t;
  t.R = R;
  t.p = p;
  return t;
}

template <typename S>
inline Transform<S> operator*(const Transform<S>& a, const Transform<S>& b) {
  return make_transform(a.R * b.R, a.R * b.p + a.p);
}

template <typename S>
inline Vec3<S> operator*(const Transform<S>& a, const Vec3<S>& v) {
  return a.R * v + a.p;
}

template <typename S>
inline Transform<S> inverse(const Transform<S>& a) {
  const Mat3<S> Rt = transpose(a.R);
  return make_transform(Rt, S(-1) * (Rt * a.p));
}

// Scalar conversion, for comparing the float computation with the double one.
template <typename To, typename From>
inline Vec3<To> cast(const Vec3<From>& v) {
  return make_vec3(To(v.x), To(v.y), To(v.z));
}

template <typename To, typename From>
inline Mat3<To> cast(const Mat3<From>& a) {
  Mat3<To> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = To(a.m[i][j]);
  return r;
}

template <typename To, typename From>
inline Transform<To> cast(const Transform<From>& t) {
  return make_transform(cast<To>(t.R), cast<To>(t.p));
}

}  // namespace articula

#endif  // ARTICULA_TRANSFORM_H
