// Tests shared/articula/transform.h: rotations, roll/pitch/yaw, rigid transforms.
#include <articula/transform.h>
#include <gtest/gtest.h>

#include <random>

using namespace articula;

namespace {
void expect_mat_near(const Mat3<double>& a, const Mat3<double>& b, double tol) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << "at (" << i << "," << j << ")";
}
}  // namespace

TEST(Transform, ElementaryRotationsByHand) {
  // Rot_z(90 deg) takes x to y and y to -x (right-handed).
  const Vec3<double> y = rot_z(M_PI / 2) * make_vec3(1.0, 0.0, 0.0);
  EXPECT_NEAR(y.x, 0, 1e-15);
  EXPECT_NEAR(y.y, 1, 1e-15);
  const Vec3<double> z = rot_x(M_PI / 2) * make_vec3(0.0, 1.0, 0.0);
  EXPECT_NEAR(z.z, 1, 1e-15);
  const Vec3<double> x = rot_y(M_PI / 2) * make_vec3(0.0, 0.0, 1.0);
  EXPECT_NEAR(x.x, 1, 1e-15);
}

TEST(Transform, RpyIsFixedXyz) {
  // R = Rz(yaw) Ry(pitch) Rx(roll): roll is applied first about the fixed x axis.
  const Mat3<double> r = rpy_to_matrix(0.1, 0.2, 0.3);
  expect_mat_near(r, rot_z(0.3) * rot_y(0.2) * rot_x(0.1), 1e-15);
}

TEST(Transform, RpyRoundTripIncludingGimbalLock) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> a(-M_PI, M_PI), p(-M_PI / 2 + 1e-3, M_PI / 2 - 1e-3);
  for (int i = 0; i < 1000; ++i) {
    const double roll = a(rng), pitch = p(rng), yaw = a(rng);
    const Vec3<double> rpy = matrix_to_rpy(rpy_to_matrix(roll, pitch, yaw));
    EXPECT_NEAR(rpy.x, roll, 1e-9);
    EXPECT_NEAR(rpy.y, pitch, 1e-9);
    EXPECT_NEAR(rpy.z, yaw, 1e-9);
  }
  // At pitch = +-90 deg only roll -+ yaw is defined; the matrix must come back all the same.
  for (double pitch : {M_PI / 2, -M_PI / 2}) {
    const Mat3<double> r = rpy_to_matrix(0.4, pitch, -1.1);
    const Vec3<double> rpy = matrix_to_rpy(r);
    EXPECT_NEAR(rpy.y, pitch, 1e-9);
    expect_mat_near(rpy_to_matrix(rpy.x, rpy.y, rpy.z), r, 1e-9);
  }
}

TEST(Transform, ComposeAndInverse) {
  const Transform<double> T_a_b = make_transform(rpy_to_matrix(0.3, -0.5, 1.2), make_vec3(10.0, -4.0, 2.5));
  const Transform<double> T_b_c = make_transform(rot_x(0.7), make_vec3(0.0, 3.0, -1.0));
  const Vec3<double> p_c = make_vec3(1.0, 2.0, 3.0);
  // Composition is the same as applying one after the other.
  const Vec3<double> p1 = (T_a_b * T_b_c) * p_c;
  const Vec3<double> p2 = T_a_b * (T_b_c * p_c);
  EXPECT_NEAR(norm(p1 - p2), 0, 1e-12);
  // The inverse undoes it.
  const Transform<double> I = inverse(T_a_b) * T_a_b;
  expect_mat_near(I.R, identity3<double>(), 1e-12);
  EXPECT_NEAR(norm(I.p), 0, 1e-12);
}

TEST(Transform, VectorAlgebra) {
  const Vec3<double> x = make_vec3(1.0, 0.0, 0.0), y = make_vec3(0.0, 1.0, 0.0);
  const Vec3<double> z = cross(x, y);
  EXPECT_EQ(z.z, 1.0);
  EXPECT_EQ(dot(x, y), 0.0);
  EXPECT_DOUBLE_EQ(norm(make_vec3(3.0, 4.0, 12.0)), 13.0);
  const Vec3<float> f = cast<float>(make_vec3(1.5, 2.5, -3.5));
  EXPECT_EQ(f.z, -3.5f);
}
