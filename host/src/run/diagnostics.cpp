#include <noether/diagnostics.hpp>

#include <algorithm>

namespace noether {

Diagnostics diagnose(const System& system, const State& state, double U) {
  Diagnostics d;
  d.potential = U;
  for (std::size_t i = 0; i < system.size(); ++i) {
    const auto idx = static_cast<Eigen::Index>(i);
    const Vec3 p = state.p.col(idx);
    const Vec3 x = state.x.col(idx);
    d.kinetic_translational += p.squaredNorm() / (2.0 * system.body(i).mass);
    d.linear_momentum += p;
    d.angular_momentum += x.cross(p);
  }
  for (std::size_t k = 0; k < system.rigid_count(); ++k) {
    const Body& b = system.body(system.body_of_rigid(k));
    const Vec3 Pi = state.Pi.col(static_cast<Eigen::Index>(k));
    d.kinetic_rotational += 0.5 * Pi.dot(b.inertia_inverse * Pi);
    d.angular_momentum += state.R[k] * Pi;
    d.orthogonality_error = std::max(d.orthogonality_error, orthogonality_error(state.R[k]));
  }
  d.energy = d.kinetic_translational + d.kinetic_rotational + U;
  return d;
}

}  // namespace noether
