#pragma once
// Two unit vectors completing a unit vector to a right-handed orthonormal basis (the occlusion
// map's projection plane, eq. 29.3; an ejecta cone's azimuths, eq. 39.2).
#include <noether/lie.hpp>

#include <cmath>

namespace noether {

inline void complete_basis(const Vec3& w, Vec3& e1, Vec3& e2) {
  const Vec3 seed = std::abs(w.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = (seed - seed.dot(w) * w).normalized();
  e2 = w.cross(e1);
}

}  // namespace noether
