// The spherical-harmonic field (docs/equations.md §32): Cunningham's recursion against the
// inertia-integral series for a point mass (two independent formulations of the same truncated
// field), and the truncated field of a polyhedron against its exact field outside the
// Brillouin sphere: the error at degree N is the series' own tail beyond N.
#include "shapes.hpp"

#include <noether/gravity_field.hpp>
#include <noether/mutual_series.hpp>
#include <noether/solid.hpp>
#include <noether/spherical_harmonic_field.hpp>
#include <noether/stokes_coefficients.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace noether;

namespace {

std::shared_ptr<const Solid> kw4_beta() {
  return make_polyhedron(test::shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true);
}

// Points on a sphere of radius `r`, fixed seed.
std::vector<Vec3> sphere_points(double r, int count) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> gauss;
  std::vector<Vec3> out;
  for (int k = 0; k < count; ++k) out.push_back(r * Vec3(gauss(random), gauss(random), gauss(random)).normalized());
  return out;
}

}  // namespace

// For a point mass m at r about KW4 Beta's radar shape, the series of order N (docs/equations.md §13: the
// body's integrals contracted with derivatives of 1/R) is the body's exterior field to degree N:
// U = −m V, the force on the mass −∂U/∂R = m ∇V and the torque on Alpha −m r × ∇V (32.3), from
// Cunningham's recursion on the coefficients (31.1) — to 1e-12.
TEST(SphericalHarmonicField, IsTheSeriesOfAPointMass) {
  const auto beta = kw4_beta();
  const double G = 6.674e-11, m = 3.0;
  const InertiaIntegrals point = point_integrals({m}, {Vec3::Zero()}, 0);
  const InertiaIntegrals T = beta->integrals(16);
  double worst = 0;
  for (int N : {2, 5, 8, 16}) {
    SphericalHarmonicField field(stokes_from_integrals(T, beta->radius, N, true), G);
    MutualSeries series(N);
    for (const Vec3& r : sphere_points(1.3 * beta->radius, 20)) {
      const auto v = field(r);
      const MutualTerms t = series.evaluate(G, T, point, r, Mat3::Identity());
      const double scale_U = std::abs(t.U), scale_f = t.dU_dR.norm();
      worst = std::max({worst, std::abs(-m * v.potential - t.U) / scale_U,
                        (m * v.acceleration + t.dU_dR).norm() / scale_f,
                        (-m * r.cross(v.acceleration) - t.torque_A).norm() / (scale_f * r.norm())});
    }
  }
  RecordProperty("worst_relative_difference", ::testing::PrintToString(worst));
  EXPECT_LT(worst, 1e-12);
}

// At twice the Brillouin radius, against the exact polyhedron field (Werner & Scheeres 1997), for
// the octahedron A of Hou et al. 2017 (sharp corners: a slowly decaying field, and integrals to
// degree 36 in milliseconds where KW4's radar mesh takes minutes): the acceleration error of
// degree N (4..16) is the tail of the series beyond N, measured as the difference between degrees
// N and 36 (whose own tail is ~2^-37 of the field), to 1 % of itself; it falls by more than 2^-6
// every 8 degrees.
TEST(SphericalHarmonicField, TruncationErrorIsTheSeriesTail) {
  const auto octahedron = make_polyhedron(test::shipped_mesh("hou2017_A.obj"), 2000, true);
  const double G = 6.674e-11;
  const int top = 36;
  const StokesCoefficients all = stokes_from_integrals(octahedron->integrals(top), octahedron->radius, top, true);
  SphericalHarmonicField full(all, G);
  PolyhedronField exact(octahedron->mesh, G * octahedron->density);
  const auto points = sphere_points(2.0 * octahedron->radius, 60);
  std::vector<double> error(17, 0.0);
  double g_scale = 0, full_error = 0;
  for (int N = 4; N <= 16; ++N) {
    SphericalHarmonicField field(truncated(all, N, true), G);
    double worst_measured = 0, worst_mismatch = 0;
    for (const Vec3& r : points) {
      const Vec3 g_exact = exact(r).g, g_full = full(r).acceleration, g_N = field(r).acceleration;
      g_scale = std::max(g_scale, g_exact.norm());
      full_error = std::max(full_error, (g_full - g_exact).norm());
      const double measured = (g_N - g_exact).norm(), predicted = (g_N - g_full).norm();
      worst_measured = std::max(worst_measured, measured);
      worst_mismatch = std::max(worst_mismatch, std::abs(measured - predicted) / predicted);
    }
    error[static_cast<std::size_t>(N)] = worst_measured / g_scale;
    EXPECT_LT(worst_mismatch, 0.01) << "degree " << N;
    RecordProperty("relative_error_degree_" + std::to_string(N), ::testing::PrintToString(error[static_cast<std::size_t>(N)]));
  }
  RecordProperty("degree_36_against_exact", ::testing::PrintToString(full_error / g_scale));
  EXPECT_LT(full_error / g_scale, 1e-9);
  EXPECT_LT(error[12], error[4] / 64);
  EXPECT_LT(error[16], error[8] / 64);
}

// The Hessian from the harmonics two degrees up (32.2) against central differences of the
// gradient, and traceless as the field is harmonic outside the body (∇²V = 0): KW4 Beta to degree
// 16 at 1.3 times its Brillouin radius.
TEST(SphericalHarmonicField, HessianIsTheGradientsDerivativeAndTraceless) {
  const auto beta = kw4_beta();
  SphericalHarmonicField field(stokes_from_integrals(beta->integrals(16), beta->radius, 16, true), 6.674e-11);
  double worst_difference = 0, worst_trace = 0;
  for (const Vec3& r : sphere_points(1.3 * beta->radius, 10)) {
    const auto v = field(r, true);
    const double h = 1e-4 * r.norm();
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = Vec3::Unit(j) * h;
      const Vec3 column = (field(r + e).acceleration - field(r - e).acceleration) / (2 * h);
      worst_difference = std::max(worst_difference, (column - v.hessian.col(j)).norm() / v.hessian.norm());
    }
    worst_trace = std::max(worst_trace, std::abs(v.hessian.trace()) / v.hessian.norm());
    EXPECT_EQ(field(r).acceleration, v.acceleration);  // the gradient does not depend on asking for H
  }
  RecordProperty("worst_against_differences", ::testing::PrintToString(worst_difference));
  RecordProperty("worst_trace", ::testing::PrintToString(worst_trace));
  EXPECT_LT(worst_difference, 1e-7);
  EXPECT_LT(worst_trace, 1e-13);
}
