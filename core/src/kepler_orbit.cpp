#include <noether/error.hpp>
#include <noether/kepler_orbit.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <string>

namespace noether {

double stumpff_c(double z) {  // (35.2)
  if (std::abs(z) < 1e-3) return 0.5 - z / 24.0 + z * z / 720.0 - z * z * z / 40320.0;
  if (z > 0) return (1.0 - std::cos(std::sqrt(z))) / z;
  return (std::cosh(std::sqrt(-z)) - 1.0) / (-z);
}

double stumpff_s(double z) {
  if (std::abs(z) < 1e-3) return 1.0 / 6.0 - z / 120.0 + z * z / 5040.0 - z * z * z / 362880.0;
  if (z > 0) {
    const double s = std::sqrt(z);
    return (s - std::sin(s)) / (s * s * s);
  }
  const double s = std::sqrt(-z);
  return (std::sinh(s) - s) / (s * s * s);
}

KeplerOrbit::KeplerOrbit(const Eigen::Vector3d& r0, const Eigen::Vector3d& v0, double mu, double t0)
    : r0_(r0), v0_(v0), mu_(mu), t0_(t0) {
  r0n_ = r0.norm();
  if (!(mu > 0) || !std::isfinite(mu)) throw Error("KeplerOrbit: the gravitational parameter must be positive");
  if (!(r0n_ > 0) || !r0.allFinite() || !v0.allFinite()) throw Error("KeplerOrbit: the relative state must be finite, r0 ≠ 0");
  alpha_ = 2.0 / r0n_ - v0.squaredNorm() / mu;
  sigma0_ = r0.dot(v0) / std::sqrt(mu);
}

double KeplerOrbit::periapsis() const {
  const double h2 = r0_.cross(v0_).squaredNorm();
  if (!(h2 > 0)) return 0.0;  // radial: it reaches the focus
  const Eigen::Vector3d e = ((v0_.squaredNorm() - mu_ / r0n_) * r0_ - r0_.dot(v0_) * v0_) / mu_;
  return h2 / (mu_ * (1.0 + e.norm()));
}

void KeplerOrbit::state(double t, Eigen::Vector3d& r, Eigen::Vector3d& v) const {
  const double dt = t - t0_, sqmu = std::sqrt(mu_);
  // Kepler's equation in χ (35.1): F(χ) = σ0 χ² C + (1 − α r0) χ³ S + r0 χ − √μ Δt = 0, whose
  // derivative is the radius r(χ) > 0: F increases, so a bracket and safeguarded Newton find χ.
  auto F = [&](double x, double& dF) {
    const double z = alpha_ * x * x, C = stumpff_c(z), S = stumpff_s(z);
    dF = sigma0_ * x * (1.0 - z * S) + (1.0 - alpha_ * r0n_) * x * x * C + r0n_;
    return sigma0_ * x * x * C + (1.0 - alpha_ * r0n_) * x * x * x * S + r0n_ * x - sqmu * dt;
  };
  if (dt == 0.0) {
    r = r0_;
    v = v0_;
    return;
  }
  double d = 0.0;
  double x = sqmu * dt / r0n_;  // χ ≈ √μ Δt / r0 for short times
  double lo = dt > 0 ? 0.0 : x, hi = dt > 0 ? x : 0.0;
  for (int k = 0; k < 200; ++k) {  // a bracket [lo, hi] with F(lo) ≤ 0 ≤ F(hi)
    if (dt > 0 ? F(hi, d) >= 0 : F(lo, d) <= 0) break;
    if (dt > 0) {
      lo = hi;
      hi *= 2;
    } else {
      hi = lo;
      lo *= 2;
    }
  }
  x = 0.5 * (lo + hi);
  for (int k = 0; k < 200; ++k) {
    const double f = F(x, d);
    (f < 0 ? lo : hi) = x;
    double next = x - f / d;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // bisection when Newton leaves the bracket
    if (std::abs(next - x) <= 4e-16 * std::max(1.0, std::abs(x)) || hi - lo <= 4e-16 * std::abs(x)) {
      x = next;
      break;
    }
    x = next;
  }
  // Lagrange's coefficients (35.3).
  const double z = alpha_ * x * x, C = stumpff_c(z), S = stumpff_s(z);
  const double f = 1.0 - x * x / r0n_ * C, g = dt - x * x * x / sqmu * S;
  r = f * r0_ + g * v0_;
  const double rn = r.norm();
  const double fdot = sqmu / (rn * r0n_) * (z * x * S - x), gdot = 1.0 - x * x / rn * C;
  v = fdot * r0_ + gdot * v0_;
  if (!r.allFinite() || !v.allFinite())
    throw Error("KeplerOrbit: the conic overflowed at t = " + std::to_string(t) + " (a hyperbola far from its pericentre)");
}

}  // namespace noether
