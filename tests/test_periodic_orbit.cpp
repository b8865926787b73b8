// Periodic orbits: closure, monodromy, stability with the invariant directions projected out,
// and shooting refinement (MATH.md §8–9, seed 004).
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/periodic_orbit.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace noether;
using Eigen::VectorXd;

namespace {

// Chenciner–Montgomery figure-eight (MATH.md §9), G = m = 1.
VectorXd figure_eight(PlanarSystem& sys) {
  sys.G = 1;
  sys.masses = {1, 1, 1};
  VectorXd xi(12);
  const double vx = -0.93240737, vy = -0.86473146;
  xi << 0.97000436, -0.24308753, -0.97000436, 0.24308753, 0, 0,  //
      -vx / 2, -vy / 2, -vx / 2, -vy / 2, vx, vy;
  return xi;
}
constexpr double kEightPeriod = 6.32591398;

// Equal-mass Lagrange triangle, circumradius 1, G = m = 1: ω² = 1/√3.
VectorXd lagrange(PlanarSystem& sys, double& period) {
  sys.G = 1;
  sys.masses = {1, 1, 1};
  const double w = std::pow(3.0, -0.25);
  period = 2 * std::numbers::pi / w;
  VectorXd xi(12);
  for (int j = 0; j < 3; ++j) {
    const double th = 2 * std::numbers::pi * j / 3;
    xi.segment<2>(2 * j) << std::cos(th), std::sin(th);
    xi.segment<2>(6 + 2 * j) << -w * std::sin(th), w * std::cos(th);
  }
  return xi;
}

std::size_t nonzero(const Stability& s) {
  std::size_t k = 0;
  for (auto l : s.multipliers) k += std::abs(l) > 1e-6;
  return k;
}

}  // namespace

TEST(PeriodicOrbit, FigureEightClosesAndIsLinearlyStable) {
  PlanarSystem sys;
  const VectorXd xi = figure_eight(sys);
  const Refinement r = refine_periodic_orbit(sys, xi, kEightPeriod);
  std::printf("figure-eight: closure %.3e after %d Newton steps, period %.12f\n", r.closure, r.iterations, r.period);
  const FlowResult f = integrate_flow(sys, r.xi0, r.period, true);
  const Stability s = stability(sys, r.xi0, f.monodromy, 1e-6);
  for (auto l : s.multipliers) std::printf("  %.10f%+.10fi |%.12f|\n", l.real(), l.imag(), std::abs(l));
  std::printf("  max |λ(Λ)| %.6f, max |λ(ΠΛΠ)| %.10f: %s; max |λ(ΛΠ)| %.6f\n", s.max_unprojected, s.max_projected, s.verdict.c_str(), std::abs(s.right_projected.front()));
  for (auto l : s.unprojected) std::printf("  unprojected %.10f%+.10fi |%.12f|\n", l.real(), l.imag(), std::abs(l));
  const Eigen::MatrixXd first = first_order_monodromy(sys, r.xi0, r.period, 100);
  const Stability s1 = stability(sys, r.xi0, first, 1e-6);
  std::printf("  first-order product (100 steps): max |λ(Λ)| %.4f, max |λ(ΛΠ)| %.4f\n", s1.max_unprojected, s1.max_projected);
}

TEST(PeriodicOrbit, LagrangeTriangleIsUnstable) {
  PlanarSystem sys;
  double T = 0;
  const VectorXd xi = lagrange(sys, T);
  for (double tol : {1e-9, 1e-11, 1e-13}) {
    FlowOptions o;
    o.rtol = tol;
    o.atol = tol * 1e-2;
    const FlowResult f = integrate_flow(sys, xi, T, true, o);
    const Stability s = stability(sys, xi, f.monodromy, 1e-6);
    std::printf("lagrange rtol %.0e: closure %.3e max |λ(ΛΠ)| %.10f max |λ(Λ)| %.6f %s\n", tol, (f.end - xi).norm(), s.max_projected, s.max_unprojected, s.verdict.c_str());
  }
}
