#include <noether/lie.hpp>

#include <cmath>

namespace noether {

RodriguesCoefficients rodrigues_coefficients(double x) {
  if (x < 1e-2) {
    // Taylor series (no sine or cosine for the small rotations of a step); the first omitted
    // terms are O(x⁸)/9! relative to 1, below 1e-21 here.
    const double x2 = x * x, x4 = x2 * x2;
    return {1.0 - x2 / 6.0 + x4 / 120.0 - x4 * x2 / 5040.0, 0.5 - x2 / 24.0 + x4 / 720.0 - x4 * x2 / 40320.0};
  }
  const double s = std::sin(0.5 * x);
  return {std::sin(x) / x, 2.0 * s * s / (x * x)};  // 1 − cos x = 2 sin²(x/2)
}

Mat3 exp_so3(const Vec3& f) {
  const auto [a, b] = rodrigues_coefficients(f.norm());
  const Mat3 S = hat(f);
  return Mat3::Identity() + a * S + b * S * S;
}

double orthogonality_error(const Mat3& R) {
  return (Mat3::Identity() - R.transpose() * R).norm();
}

Vec4 quaternion_from_rotation(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  Vec4 v(q.w(), q.x(), q.y(), q.z());
  if (v[0] < 0) v = -v;
  return v;
}

Mat3 rotation_from_quaternion(const Vec4& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

}  // namespace noether

#include <Eigen/SVD>

namespace noether {
Mat3 nearest_rotation(const Mat3& M) {
  Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  const Mat3 V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;
  return U * V.transpose();
}
}  // namespace noether

namespace noether {
Vec3 log_so3(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Vec3 v = q.vec();
  const double n = v.norm();
  const double theta = 2.0 * std::atan2(n, q.w());
  return n > 0 ? Vec3((theta / n) * v) : Vec3((2.0 / q.w()) * v);
}
}  // namespace noether
