// Stokes coefficients ↔ inertia integrals (docs/equations.md §31): an ellipsoid's against its
// closed forms, a cluster's exterior field against the sum of its point masses, the round trip
// T → (C, S) → T on KW4 Alpha and an ellipsoid, and a polyhedron's coefficients against a
// quadrature of its exact field over a sphere.
#include "mutual_configurations.hpp"

#include <noether/gravity_field.hpp>
#include <noether/inertia_integrals.hpp>
#include <noether/mutual_series.hpp>
#include <noether/solid.hpp>
#include <noether/stokes_coefficients.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace noether;

namespace {

// P_nm(μ) without the Condon–Shortley phase, 0 ≤ m ≤ n ≤ N, by the standard recursions:
// P_mm = (2m − 1)!! (1 − μ²)^{m/2}, P_{m+1,m} = (2m + 1) μ P_mm,
// (n − m) P_nm = (2n − 1) μ P_{n−1,m} − (n + m − 1) P_{n−2,m}. [n][m]
std::vector<std::vector<double>> legendre(int N, double mu) {
  std::vector<std::vector<double>> P(static_cast<std::size_t>(N + 1), std::vector<double>(static_cast<std::size_t>(N + 1), 0.0));
  const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  P[0][0] = 1;
  for (int m = 1; m <= N; ++m) P[m][m] = (2 * m - 1) * s * P[m - 1][m - 1];
  for (int m = 0; m < N; ++m) P[m + 1][m] = (2 * m + 1) * mu * P[m][m];
  for (int m = 0; m <= N; ++m)
    for (int n = m + 2; n <= N; ++n)
      P[n][m] = ((2 * n - 1) * mu * P[n - 1][m] - (n + m - 1) * P[n - 2][m]) / (n - m);
  return P;
}

// U/G at r from unnormalised coefficients: (M/r) Σ (R/r)^n P_nm(sin φ)(C cos mλ + S sin mλ).
double exterior_potential(const StokesCoefficients& cs, const Vec3& r) {
  const double rho = r.norm(), sin_phi = r.z() / rho, lambda = std::atan2(r.y(), r.x());
  const auto P = legendre(cs.degree, sin_phi);
  double sum = 0;
  for (int n = 0; n <= cs.degree; ++n)
    for (int m = 0; m <= n; ++m)
      sum += std::pow(cs.reference_radius / rho, n) * P[n][m] *
             (cs.c(n, m) * std::cos(m * lambda) + cs.s(n, m) * std::sin(m * lambda));
  return cs.mass / rho * sum;
}

}  // namespace

// A homogeneous ellipsoid, from its moments E[x⁴] = 3a⁴/35, E[x²y²] = a²b²/35, …, and the
// Legendre polynomials written out (r⁴P40 = (35z⁴ − 30z²r² + 3r⁴)/8, r⁴P42 cos 2λ =
// (15/2)(7z² − r²)(x² − y²), r⁴P44 cos 4λ = 105(x⁴ − 6x²y² + y⁴)):
//   C20 = (2c² − a² − b²)/(10R²)          C22 = (a² − b²)/(20R²)
//   C40 = 3(3a⁴ + 3b⁴ + 8c⁴ + 2a²b² − 8a²c² − 8b²c²)/(280R⁴)
//   C42 = (a² − b²)(2c² − a² − b²)/(280R⁴)  C44 = (a² − b²)²/(2240R⁴)
// and every odd-degree, odd-order or sine coefficient zero.
TEST(StokesCoefficients, EllipsoidAgainstItsClosedForms) {
  const double a = 766, b = 747.5, c = 673.5, M = 2.353e12, R = 800;
  const InertiaIntegrals T = ellipsoid_integrals(M, Vec3(a, b, c), 8);
  const StokesCoefficients cs = stokes_from_integrals(T, R, 8, false);
  const double a2 = a * a, b2 = b * b, c2 = c * c, R2 = R * R, R4 = R2 * R2;
  EXPECT_NEAR(cs.c(0, 0), 1.0, 1e-15);
  EXPECT_NEAR(cs.c(2, 0), (2 * c2 - a2 - b2) / (10 * R2), 1e-15);
  EXPECT_NEAR(cs.c(2, 2), (a2 - b2) / (20 * R2), 1e-16);
  // Degree 4: the closed forms are differences of terms ~(a/R)⁴/100 that nearly cancel (C44 is
  // 1e-6); 1e-16 absolute is round-off in those terms.
  EXPECT_NEAR(cs.c(4, 0), 3 * (3 * a2 * a2 + 3 * b2 * b2 + 8 * c2 * c2 + 2 * a2 * b2 - 8 * a2 * c2 - 8 * b2 * c2) / (280 * R4), 1e-16);
  EXPECT_NEAR(cs.c(4, 2), (a2 - b2) * (2 * c2 - a2 - b2) / (280 * R4), 1e-16);
  EXPECT_NEAR(cs.c(4, 4), (a2 - b2) * (a2 - b2) / (2240 * R4), 1e-16);
  for (int n = 0; n <= 8; ++n)
    for (int m = 0; m <= n; ++m) {
      EXPECT_EQ(cs.s(n, m), 0.0) << n << m;
      if (n % 2 || m % 2) EXPECT_EQ(cs.c(n, m), 0.0) << n << m;
    }
  // Normalised: C̄ = C / N_nm, N_20 = √5, N_22 = √(5/12).
  const StokesCoefficients bar = stokes_from_integrals(T, R, 8, true);
  EXPECT_NEAR(bar.c(2, 0), cs.c(2, 0) / std::sqrt(5.0), 1e-16);
  EXPECT_NEAR(bar.c(2, 2), cs.c(2, 2) / std::sqrt(5.0 / 12), 1e-16);
}

// Eleven point masses: their field at 3× the reference radius (which holds them all) against the
// series to degree 24 — the truncation's (1/3)^25 relative, so the conventions (latitude, sign of
// the longitude, the factorials) are all tested at once.
TEST(StokesCoefficients, ExteriorFieldOfPointMassesAgreesWithTheirSum) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> m;
  std::vector<Vec3> x;
  for (int k = 0; k < 11; ++k) {
    m.push_back(1 + u(random) * 0.5);
    x.push_back(Vec3(u(random), 0.7 * u(random), 0.5 * u(random)));
  }
  const InertiaIntegrals T = point_integrals(m, x, 24);
  const StokesCoefficients cs = stokes_from_integrals(T, 1.5, 24, false);
  double worst = 0;
  for (int k = 0; k < 40; ++k) {
    const Vec3 r = 4.5 * Vec3(u(random), u(random), u(random)).normalized();
    double direct = 0;
    for (std::size_t p = 0; p < m.size(); ++p) direct += m[p] / (r - x[p]).norm();
    worst = std::max(worst, std::abs(exterior_potential(cs, r) / direct - 1));
  }
  RecordProperty("worst_relative_error", ::testing::PrintToString(worst));
  EXPECT_LT(worst, 1e-13);  // measured 1.6e-15
}

// T → (C, S) → T to degree 12 with the body's own traces (31.3): every integral back to 1e-13 of
// its degree's scale M R^n (measured 4.4e-17 and 1.5e-16), for KW4 Alpha's polyhedron and an
// ellipsoid, in both normalisations.
TEST(StokesCoefficients, RoundTripToDegreeTwelve) {
  const auto alpha = make_polyhedron(test::shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, true);
  const auto ellipsoid = make_ellipsoid(Vec3(766, 747.5, 673.5), 1970);
  for (const auto* solid : {alpha.get(), ellipsoid.get()})
    for (bool normalized : {false, true}) {
      const InertiaIntegrals T = solid->integrals(12);
      const double R = solid->radius;
      const InertiaIntegrals back = integrals_from_stokes(stokes_from_integrals(T, R, 12, normalized), T);
      double worst = 0;
      for (int i = 0; i < multi_index::count(12); ++i) {
        const double scale = T.mass() * std::pow(R, multi_index::degree(i));
        worst = std::max(worst, std::abs(back.T[static_cast<std::size_t>(i)] - T.T[static_cast<std::size_t>(i)]) / scale);
      }
      EXPECT_LT(worst, 1e-13) << solid->describe() << (normalized ? " normalised" : "");
      RecordProperty(std::string("worst_") + (solid == alpha.get() ? "alpha" : "ellipsoid") + (normalized ? "_normalised" : ""),
                     ::testing::PrintToString(worst));
    }
}

// KW4 Beta's polyhedron: its coefficients to degree 6 against a spherical-harmonic analysis of its
// exact field (Werner & Scheeres 1997) on a sphere of twice its radius — Gauss–Legendre in sin φ
// (24 nodes) and 48 longitudes, exact for the degrees that matter; the higher degrees, smaller by
// 2^-n, alias below 1e-12.
TEST(StokesCoefficients, PolyhedronAgainstAQuadratureOfItsExactField) {
  const auto beta = make_polyhedron(test::shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true);
  const double R = beta->radius, rho = 2 * R, M = beta->mass;
  const StokesCoefficients cs = stokes_from_integrals(beta->integrals(6), R, 6, false);
  const PolyhedronField field(beta->mesh, 2810.0);  // G = 1: Φ = −U
  // Gauss–Legendre nodes and weights on [−1, 1] (the core's rule on [0, 1], mapped).
  const int L = 24, K = 48;
  std::vector<double> mu, w;
  gauss_legendre01(L, mu, w);
  for (int i = 0; i < L; ++i) mu[i] = 2 * mu[i] - 1, w[i] *= 2;
  // C_nm = (2n+1)(2−δ)/(4π) (n−m)!/(n+m)! (ρ/R)^n ρ/M ∫ U P_nm cos mλ dΩ, S likewise.
  std::vector<double> U(static_cast<std::size_t>(L * K));
  for (int i = 0; i < L; ++i)
    for (int k = 0; k < K; ++k) {
      const double lambda = 2 * M_PI * k / K, cos_phi = std::sqrt(1 - mu[i] * mu[i]);
      U[static_cast<std::size_t>(i * K + k)] =
          -field(rho * Vec3(cos_phi * std::cos(lambda), cos_phi * std::sin(lambda), mu[i])).phi;
    }
  double worst = 0, scale = std::abs(cs.c(2, 0));
  for (int n = 2; n <= 6; ++n)
    for (int m = 0; m <= n; ++m) {
      double c = 0, s = 0;
      for (int i = 0; i < L; ++i) {
        const auto P = legendre(6, mu[i]);
        for (int k = 0; k < K; ++k) {
          const double lambda = 2 * M_PI * k / K, u = U[static_cast<std::size_t>(i * K + k)];
          c += w[i] * (2 * M_PI / K) * u * P[n][m] * std::cos(m * lambda);
          s += w[i] * (2 * M_PI / K) * u * P[n][m] * std::sin(m * lambda);
        }
      }
      const double f = (2 * n + 1) * (m == 0 ? 1.0 : 2.0) / (4 * M_PI) * multi_index::factorial(n - m) /
                       multi_index::factorial(n + m) * std::pow(rho / R, n) * rho / M;
      worst = std::max({worst, std::abs(f * c - cs.c(n, m)) / scale, std::abs(f * s - cs.s(n, m)) / scale});
    }
  RecordProperty("worst_error_over_C20", ::testing::PrintToString(worst));
  EXPECT_LT(worst, 1e-11);  // measured 1.3e-12
}

// The field does not fix the traces, and needs none beyond degree 2: KW4 Alpha rebuilt from its
// coefficients with only its inertia's trace (degree 2) and zero traces above gives the same
// mutual potential, force and torques with Beta in the series to order 8 — the series contracts
// the integrals with the harmonic derivatives of 1/R, which annihilate r² × anything (31.3).
TEST(StokesCoefficients, TheMutualSeriesSeesOnlyTheField) {
  const auto alpha = make_polyhedron(test::shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, true);
  const auto beta = make_polyhedron(test::shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true);
  const InertiaIntegrals TA = alpha->integrals(8), TB = beta->integrals(8);
  const InertiaIntegrals inertia_only = integrals_from_inertia(alpha->mass, alpha->inertia);
  const InertiaIntegrals rebuilt = integrals_from_stokes(stokes_from_integrals(TA, alpha->radius, 8, true), inertia_only);
  double differs = 0;  // the rebuilt integrals are not the body's: their traces above degree 2 are zero
  for (int i = multi_index::first_of_degree(4); i < multi_index::count(8); ++i)
    differs = std::max(differs, std::abs(rebuilt.T[static_cast<std::size_t>(i)] - TA.T[static_cast<std::size_t>(i)]) /
                                    (TA.mass() * std::pow(alpha->radius, multi_index::degree(i))));
  EXPECT_GT(differs, 1e-3);
  MutualSeries series(8);
  const Vec3 R(1300, 450, -200);
  const Mat3 C = Eigen::AngleAxisd(0.7, Vec3(0.3, -0.4, 1).normalized()).toRotationMatrix();
  const MutualTerms a = series.evaluate(6.674e-11, TA, TB, R, C), b = series.evaluate(6.674e-11, rebuilt, TB, R, C);
  EXPECT_NEAR(b.U, a.U, 1e-13 * std::abs(a.U));
  EXPECT_LT((b.dU_dR - a.dU_dR).norm(), 1e-12 * a.dU_dR.norm());
  EXPECT_LT((b.torque_A - a.torque_A).norm(), 1e-11 * a.torque_A.norm());
  EXPECT_LT((b.torque_B - a.torque_B).norm(), 1e-11 * a.torque_B.norm());
}
