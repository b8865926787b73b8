// Osculating elements ↔ relative state (docs/equations.md §17; Vallado 2013, algorithms 9–10).
#include <noether/orbital_elements.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace noether {

namespace {

constexpr double two_pi = 6.283185307179586476925286766559;

double wrap(double angle) {  // into [0, 2π)
  angle = std::fmod(angle, two_pi);
  return angle < 0.0 ? angle + two_pi : angle;
}

Eigen::Matrix3d perifocal_to_inertial(double Omega, double i, double omega) {  // Rz(Ω) Rx(i) Rz(ω)
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  return (AngleAxisd(Omega, Vector3d::UnitZ()) * AngleAxisd(i, Vector3d::UnitX()) *
          AngleAxisd(omega, Vector3d::UnitZ()))
      .toRotationMatrix();
}

}  // namespace

double true_from_mean_anomaly(double M, double e) {
  M = wrap(M);
  double E = e < 0.8 ? M : M_PI;  // Newton on E − e sin E − M (eq. 17.2), monotone for e < 1
  for (int k = 0; k < 60; ++k) {
    const double dE = (E - e * std::sin(E) - M) / (1.0 - e * std::cos(E));
    E -= dE;
    if (std::abs(dE) < 1e-15) break;
  }
  return wrap(2.0 * std::atan2(std::sqrt(1.0 + e) * std::sin(0.5 * E), std::sqrt(1.0 - e) * std::cos(0.5 * E)));
}

double mean_from_true_anomaly(double nu, double e) {
  const double E = 2.0 * std::atan2(std::sqrt(1.0 - e) * std::sin(0.5 * nu), std::sqrt(1.0 + e) * std::cos(0.5 * nu));
  return wrap(E - e * std::sin(E));
}

RelativeState state_from_elements(const OrbitalElements& el, double mu) {
  const double p = el.a * (1.0 - el.e * el.e);  // semi-latus rectum
  const double c = std::cos(el.nu), s = std::sin(el.nu);
  const double r = p / (1.0 + el.e * c);
  const Eigen::Vector3d r_pf(r * c, r * s, 0.0);                                     // eq. (17.3)
  const Eigen::Vector3d v_pf(-std::sqrt(mu / p) * s, std::sqrt(mu / p) * (el.e + c), 0.0);
  const Eigen::Matrix3d Q = perifocal_to_inertial(el.Omega, el.i, el.omega);       // eq. (17.4)
  return {Q * r_pf, Q * v_pf};
}

OrbitalElements elements_from_state(const RelativeState& s, double mu) {
  const Eigen::Vector3d& r = s.r;
  const Eigen::Vector3d& v = s.v;
  const double rn = r.norm();
  const double energy = 0.5 * v.squaredNorm() - mu / rn;
  if (!(energy < 0.0)) throw std::domain_error("the relative orbit is not bound (specific energy ≥ 0)");
  OrbitalElements el;
  el.a = -mu / (2.0 * energy);                                                           // eq. (17.5)
  const Eigen::Vector3d h = r.cross(v);
  const Eigen::Vector3d e_vec = v.cross(h) / mu - r / rn;                                // eq. (17.6)
  el.e = e_vec.norm();
  el.i = std::acos(std::clamp(h.z() / h.norm(), -1.0, 1.0));                             // eq. (17.7)
  const Eigen::Vector3d node = Eigen::Vector3d::UnitZ().cross(h);
  const double tiny = 1e-12;
  const bool equatorial = node.norm() < tiny * h.norm(), circular = el.e < tiny;
  el.Omega = equatorial ? 0.0 : wrap(std::atan2(node.y(), node.x()));
  // The reference direction in the orbit plane: the node line (x for equatorial orbits).
  const Eigen::Vector3d n_hat = equatorial ? Eigen::Vector3d::UnitX() : Eigen::Vector3d(node.normalized());
  const Eigen::Vector3d m_hat = h.normalized().cross(n_hat);
  const auto angle_from_node = [&](const Eigen::Vector3d& x) { return wrap(std::atan2(x.dot(m_hat), x.dot(n_hat))); };
  el.omega = circular ? 0.0 : angle_from_node(e_vec);                                    // eq. (17.8)
  el.nu = wrap(angle_from_node(r) - el.omega);
  return el;
}

}  // namespace noether
