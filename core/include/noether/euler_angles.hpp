#pragma once
// 3-2-1 (yaw, pitch, roll) Euler angles of an attitude, and back (docs/equations.md, eq. 17.9):
// R = Rz(ψ) Ry(θ) Rx(φ), the body turned by ψ about z, then θ about the new y, then φ about the
// new x. Output files give them in degrees (euler_angles, secondary_euler_angles).
#include <noether/lie.hpp>

#include <algorithm>
#include <cmath>

namespace noether {

// (ψ, θ, φ) in radians, ψ and φ in (−π, π], θ in [−π/2, π/2]. At θ = ±π/2 (gimbal lock) only
// ψ ∓ φ is defined: φ = 0 is taken.
inline Vec3 euler_angles_321(const Mat3& R) {
  const double s = std::clamp(-R(2, 0), -1.0, 1.0);
  const double theta = std::asin(s);
  if (std::hypot(R(2, 1), R(2, 2)) < 1e-12) return Vec3(std::atan2(-R(0, 1), R(1, 1)), theta, 0.0);
  return Vec3(std::atan2(R(1, 0), R(0, 0)), theta, std::atan2(R(2, 1), R(2, 2)));
}

inline Mat3 rotation_from_euler_321(const Vec3& angles) {
  return (Eigen::AngleAxisd(angles.x(), Vec3::UnitZ()) * Eigen::AngleAxisd(angles.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(angles.z(), Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace noether
