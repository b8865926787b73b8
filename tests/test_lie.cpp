// SO(3) essentials: hat map identities, Rodrigues' formula on and off its series branch.
#include <noether/lie.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;

TEST(Lie, HatIsTheCrossProductAndVeeInvertsIt) {
  const Vec3 a(0.3, -1.2, 2.5), b(-0.7, 0.4, 1.1);
  EXPECT_LT((hat(a) * b - a.cross(b)).norm(), 1e-15);
  EXPECT_LT((vee(hat(a)) - a).norm(), 1e-15);
  // S(Ra) = R S(a) Rᵀ (docs/equations.md §1).
  const Mat3 R = exp_so3(Vec3(0.2, 0.9, -0.4));
  EXPECT_LT((hat(R * a) - R * hat(a) * R.transpose()).norm(), 1e-14);
}

// exp(S(f)) is orthogonal to round-off over the whole range the LGVI meets, 1e-12 ≤ ‖f‖ ≤ 3.
TEST(Lie, RodriguesIsOrthogonalFrom1em12To3) {
  const Vec3 axis = Vec3(1.0, -2.0, 0.5).normalized();
  double worst = 0.0;
  for (double x = 1e-12; x <= 3.0; x *= 1.5) {
    const Mat3 F = exp_so3(x * axis);
    worst = std::max(worst, orthogonality_error(F));
    EXPECT_NEAR(F.determinant(), 1.0, 1e-15);
  }
  EXPECT_LE(worst, 1e-15);
}

// The small-angle series and the closed form agree where they meet, and exp agrees with the
// quaternion rotation about the same axis.
TEST(Lie, RodriguesAgreesWithAngleAxis) {
  const Vec3 axis = Vec3(0.3, 0.4, -0.2).normalized();
  for (double x : {1e-9, 9.9e-5, 1.01e-4, 0.3, 2.9}) {
    const Mat3 expected = Eigen::AngleAxisd(x, axis).toRotationMatrix();
    EXPECT_LT((exp_so3(x * axis) - expected).norm(), 2e-16 * 8) << "x = " << x;
  }
}

TEST(Lie, QuaternionRoundTrip) {
  const Mat3 R = exp_so3(Vec3(-1.1, 0.5, 2.0));
  const Vec4 q = quaternion_from_rotation(R);
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  EXPECT_GE(q[0], 0.0);
  EXPECT_LT((rotation_from_quaternion(q) - R).norm(), 1e-15);
}
