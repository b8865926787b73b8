// Osculating elements ↔ relative state (docs/equations.md §17).
#include <noether/orbital_elements.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;

namespace {
constexpr double deg = M_PI / 180.0;
double angle_difference(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }
}  // namespace

// state → elements inverts elements → state over eccentricities up to 0.99 and all
// orientations away from the singular cases (e = 0, i = 0 or 180°).
TEST(OrbitalElements, RoundTrip) {
  const double mu = 3.7;
  for (double e : {0.01, 0.3, 0.7, 0.99})
    for (double i : {5.0, 60.0, 120.0, 175.0})
      for (double angle : {10.0, 100.0, 200.0, 330.0}) {
        const OrbitalElements el{2.5, e, i * deg, angle * deg, (angle + 77.0) * deg, (360.0 - angle) * deg};
        const OrbitalElements back = elements_from_state(state_from_elements(el, mu), mu);
        EXPECT_NEAR(back.a / el.a, 1.0, 1e-12) << e << " " << i << " " << angle;
        EXPECT_NEAR(back.e, el.e, 1e-12);
        EXPECT_NEAR(back.i, el.i, 1e-12);
        EXPECT_LT(angle_difference(back.Omega, el.Omega), 1e-11);
        EXPECT_LT(angle_difference(back.omega, el.omega), 1e-9 / e);
        EXPECT_LT(angle_difference(back.nu, el.nu), 1e-9 / e);
      }
}

// Energy and angular momentum of the state are those of the conic: vis-viva
// v² = μ (2/r − 1/a) and |h| = √(μ a (1 − e²)).
TEST(OrbitalElements, VisVivaAndAngularMomentum) {
  const double mu = 1.0;
  for (double nu : {0.0, 1.0, 2.0, 3.0, 4.0}) {
    const OrbitalElements el{1.3, 0.6, 0.4, 1.1, 2.2, nu};
    const RelativeState s = state_from_elements(el, mu);
    const double r = s.r.norm();
    EXPECT_NEAR(s.v.squaredNorm(), mu * (2.0 / r - 1.0 / el.a), 1e-14);
    EXPECT_NEAR(s.r.cross(s.v).norm(), std::sqrt(mu * el.a * (1.0 - el.e * el.e)), 1e-14);
    EXPECT_NEAR(r, el.a * (1.0 - el.e * el.e) / (1.0 + el.e * std::cos(nu)), 1e-14);
  }
}

// Kepler's equation (17.2) is solved to round-off up to e = 0.999, and the true anomaly maps
// back to the same mean anomaly.
TEST(OrbitalElements, KeplerEquation) {
  for (double e : {0.0, 0.1, 0.5, 0.9, 0.99, 0.999})
    for (double M = 0.0; M < 2.0 * M_PI; M += 0.37) {
      const double nu = true_from_mean_anomaly(M, e);
      EXPECT_LT(angle_difference(mean_from_true_anomaly(nu, e), M), 1e-12) << e << " " << M;
    }
}

TEST(OrbitalElements, UnboundStateRefused) {
  EXPECT_THROW(elements_from_state({Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 2, 0)}, 1.0), std::domain_error);
}
