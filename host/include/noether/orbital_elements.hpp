#pragma once
// Osculating Keplerian elements of a two-body relative orbit and the relative state they
// describe (docs/equations.md §17): bound orbits, angles in radians, μ = G (m_a + m_b).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace noether {

struct OrbitalElements {
  double a = 0.0;      // semi-major axis (> 0)
  double e = 0.0;      // eccentricity, 0 ≤ e < 1
  double i = 0.0;      // inclination
  double Omega = 0.0;  // longitude of the ascending node
  double omega = 0.0;  // argument of pericentre
  double nu = 0.0;     // true anomaly
};

struct RelativeState {
  Eigen::Vector3d r, v;
};

// Eq. (17.3)–(17.4): the perifocal state rotated by Rz(Ω) Rx(i) Rz(ω).
RelativeState state_from_elements(const OrbitalElements& el, double mu);

// Eq. (17.5)–(17.8): the inverse for a bound orbit (throws std::domain_error when unbound);
// Ω = 0 for equatorial and ω measured from the node line (or from x for equatorial) for
// circular orbits.
OrbitalElements elements_from_state(const RelativeState& s, double mu);

// Kepler's equation M = E − e sin E for the eccentric anomaly E (eq. 17.2), then ν.
double true_from_mean_anomaly(double M, double e);
double mean_from_true_anomaly(double nu, double e);

}  // namespace noether
