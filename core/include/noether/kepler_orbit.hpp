#pragma once
// KeplerOrbit: a two-body conic — ellipse, parabola or hyperbola — propagated exactly by the
// universal anomaly χ (Battin 1987, §4.5; Vallado 2013, Algorithm 8; docs/equations.md §35):
// the prescribed path of a body the scene does not integrate (a planet's flyby, the Sun).
#include <Eigen/Core>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class KeplerOrbit {
 public:
  // The relative state (r0, v0) at t0 under the gravitational parameter mu > 0.
  KeplerOrbit(const Eigen::Vector3d& r0, const Eigen::Vector3d& v0, double mu, double t0);
  // The relative position and velocity at t, by Lagrange's f and g in χ (35.1)–(35.3).
  void state(double t, Eigen::Vector3d& r, Eigen::Vector3d& v) const;
  double mu() const { return mu_; }
  // 1/a = 2/r0 − v0²/μ: > 0 bound, < 0 hyperbolic.
  double inverse_semi_major_axis() const { return alpha_; }
  // The closest the conic comes to its focus, q = h² / (μ (1 + e)) (h = |r0 × v0|; for a
  // radial orbit: 0) — whether or not the motion between t0 and a given time passes it.
  double periapsis() const;

 private:
  Eigen::Vector3d r0_, v0_;
  double mu_, t0_, alpha_, r0n_, sigma0_;  // σ0 = r0·v0/√μ
};

// Stumpff's functions C(z) = (1 − cos √z)/z and S(z) = (√z − sin √z)/√z³, continued to z ≤ 0
// (by cosh and sinh) and by their series near 0 (35.2).
double stumpff_c(double z);
double stumpff_s(double z);

}  // namespace noether

#pragma GCC visibility pop
