#include <noether/continuous_equations.hpp>
#include <noether/error.hpp>

#include <cmath>

namespace noether {

InertialEquations::InertialEquations(const System& system, std::shared_ptr<const Potential> potential)
    : system_(system), potential_(std::move(potential)),
      size_(6 * system.size() + 12 * system.rigid_count()),
      scratch_(State::zeros(system)) {
  forces_.resize(system_);
}

void InertialEquations::pack(const State& s, double* y) const {
  const std::size_t n = system_.size(), nr = system_.rigid_count();
  std::copy(s.x.data(), s.x.data() + 3 * n, y);
  std::copy(s.p.data(), s.p.data() + 3 * n, y + 3 * n);
  double* R = y + 6 * n;
  for (std::size_t k = 0; k < nr; ++k) std::copy(s.R[k].data(), s.R[k].data() + 9, R + 9 * k);
  std::copy(s.Pi.data(), s.Pi.data() + 3 * nr, R + 9 * nr);
}

void InertialEquations::unpack(const double* y, double t, State& s) const {
  const std::size_t n = system_.size(), nr = system_.rigid_count();
  s.t = t;
  s.x = Eigen::Map<const Eigen::Matrix3Xd>(y, 3, static_cast<Eigen::Index>(n));
  s.p = Eigen::Map<const Eigen::Matrix3Xd>(y + 3 * n, 3, static_cast<Eigen::Index>(n));
  const double* R = y + 6 * n;
  s.R.resize(nr);
  for (std::size_t k = 0; k < nr; ++k) s.R[k] = Eigen::Map<const Mat3>(R + 9 * k);
  s.Pi = Eigen::Map<const Eigen::Matrix3Xd>(R + 9 * nr, 3, static_cast<Eigen::Index>(nr));
}

void InertialEquations::rhs(double t, const double* y, double* dydt) {
  unpack(y, t, scratch_);
  potential_->evaluate(scratch_, forces_);
  ++evaluations_;
  const std::size_t n = system_.size(), nr = system_.rigid_count();
  for (std::size_t i = 0; i < n; ++i) {
    const double inv_m = 1.0 / system_.body(i).mass;
    for (int a = 0; a < 3; ++a) {
      dydt[3 * i + a] = y[3 * n + 3 * i + a] * inv_m;                        // ẋ = γ/m
      dydt[3 * n + 3 * i + a] = forces_.f(a, static_cast<Eigen::Index>(i));  // γ̇ = −∂U/∂x
    }
  }
  double* dR = dydt + 6 * n;
  double* dPi = dR + 9 * nr;
  for (std::size_t k = 0; k < nr; ++k) {
    const Body& b = system_.body(system_.body_of_rigid(k));
    const auto c = static_cast<Eigen::Index>(k);
    const Vec3 Pi = scratch_.Pi.col(c);
    const Vec3 Omega = b.inertia_inverse * Pi;
    Eigen::Map<Mat3>(dR + 9 * k) = scratch_.R[k] * hat(Omega);                // Ṙ = R S(Ω)
    Eigen::Map<Vec3>(dPi + 3 * k) = Pi.cross(Omega) + Vec3(forces_.M.col(c));  // Π̇ = Π×Ω + M
  }
}

}  // namespace noether
