#pragma once
// SO(3) essentials (docs/equations.md §1, §4): the hat map S(·), the exponential map by Rodrigues'
// formula with small-angle series, and the orthogonality error ‖I − RᵀR‖.
#include <Eigen/Core>
#include <Eigen/Geometry>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec4 = Eigen::Vector4d;

// S(a) b = a × b.
inline Mat3 hat(const Vec3& a) {
  Mat3 S;
  S << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),   //
      -a.y(), a.x(), 0.0;
  return S;
}

// Inverse of hat() for a skew-symmetric matrix (uses the antisymmetric part).
inline Vec3 vee(const Mat3& S) {
  return 0.5 * Vec3(S(2, 1) - S(1, 2), S(0, 2) - S(2, 0), S(1, 0) - S(0, 1));
}

// The two coefficients of Rodrigues' formula, F = I + a S(f) + b S(f)², at x = ‖f‖:
//   a = sin x / x,   b = (1 − cos x)/x² = 2 sin²(x/2)/x²   (series below x = 1e-4).
struct RodriguesCoefficients {
  double a;
  double b;
};
RodriguesCoefficients rodrigues_coefficients(double x);

// exp(S(f)) ∈ SO(3).
Mat3 exp_so3(const Vec3& f);

// ‖I − RᵀR‖ in the Frobenius norm: how far R has drifted off SO(3).
double orthogonality_error(const Mat3& R);

// Unit quaternion (w, x, y, z), scalar first, w ≥ 0, of a rotation matrix; and back.
Vec4 quaternion_from_rotation(const Mat3& R);
Mat3 rotation_from_quaternion(const Vec4& q);

}  // namespace noether

namespace noether {
// The rotation nearest to M in the Frobenius norm (polar factor U Vᵀ of M = U Σ Vᵀ): used
// only where a user asks for re-orthonormalisation (rk's `renormalize`), never silently.
Mat3 nearest_rotation(const Mat3& M);
}  // namespace noether

namespace noether {
// The rotation vector f of R = exp(S(f)), ‖f‖ ≤ π (via the unit quaternion, accurate for
// small angles).
Vec3 log_so3(const Mat3& R);
}  // namespace noether

#pragma GCC visibility pop
