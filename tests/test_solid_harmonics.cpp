// Regular solid harmonics and the sphere projection behind the exact model's expansion
// (docs/equations.md §37): closed forms, one recursion against the other, harmonicity, exact
// projection, a point mass's local expansion, and the moments from the inertia integrals
// against surface quadratures of the same integrands.
#include "mutual_configurations.hpp"

#include <noether/gravity_field.hpp>
#include <noether/solid_harmonics.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

using namespace noether;
using namespace noether::test;

namespace {

double evaluate_polynomial(const std::vector<double>& c, int n, const Vec3& x) {
  double v = 0.0;
  const int first = multi_index::first_of_degree(n);
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto& [l, m, k] = multi_index::exponents(first + static_cast<int>(i));
    v += c[i] * std::pow(x.x(), l) * std::pow(x.y(), m) * std::pow(x.z(), k);
  }
  return v;
}

std::vector<double> values(const Vec3& x, int N) {
  std::vector<double> v(static_cast<std::size_t>(harmonic::count(N)));
  solid_harmonic_values(x, N, v.data());
  return v;
}

}  // namespace

TEST(SolidHarmonics, LowDegreesAreTheClosedForms) {
  const Vec3 x(0.3, -0.7, 0.45);
  const std::vector<double> v = values(x, 2);
  const double r2 = x.squaredNorm();
  using harmonic::index;
  EXPECT_DOUBLE_EQ(v[index(0, 0, false)], 1.0);
  EXPECT_DOUBLE_EQ(v[index(1, 0, false)], x.z());
  // Schmidt semi-normalised, Condon–Shortley phase: r P_1^1 cos φ = −x, r P_1^1 sin φ = −y.
  EXPECT_NEAR(v[index(1, 1, false)], -x.x(), 1e-15);
  EXPECT_NEAR(v[index(1, 1, true)], -x.y(), 1e-15);
  EXPECT_NEAR(v[index(2, 0, false)], 0.5 * (3 * x.z() * x.z() - r2), 1e-15);
  EXPECT_NEAR(v[index(2, 1, false)], -std::sqrt(3.0) * x.x() * x.z(), 1e-15);
  EXPECT_NEAR(v[index(2, 2, true)], std::sqrt(3.0) * x.x() * x.y(), 1e-15);
  EXPECT_NEAR(v[index(2, 2, false)], 0.5 * std::sqrt(3.0) * (x.x() * x.x() - x.y() * x.y()), 1e-15);
  EXPECT_EQ(harmonic::degree(index(7, 7, true)), 7);
  EXPECT_EQ(harmonic::degree(index(8, 0, false)), 8);
}

TEST(SolidHarmonics, PolynomialsAreTheValuesAndAreHarmonic) {
  constexpr int N = 24;
  const SolidHarmonicPolynomials p = solid_harmonic_polynomials(N);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0, bound = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 x = Vec3(u(rng), u(rng), u(rng)).normalized() * (0.2 + 0.8 * std::abs(u(rng)));
    const std::vector<double> v = values(x, N);
    for (int j = 0; j < harmonic::count(N); ++j) {
      const int n = harmonic::degree(j);
      worst = std::max(worst, std::abs(evaluate_polynomial(p.coefficients[static_cast<std::size_t>(j)], n, x) -
                                       v[static_cast<std::size_t>(j)]));
      // Schmidt semi-normalised: |R_j(x)| ≤ |x|ⁿ.
      bound = std::max(bound, std::abs(v[static_cast<std::size_t>(j)]) / std::pow(x.norm(), n));
    }
  }
  EXPECT_LT(worst, 1e-9);  // monomial sums cancel: coefficients reach ~1e6 at degree 24
  EXPECT_LE(bound, 1.0 + 1e-12);
  // ∇² of each polynomial, coefficient by coefficient: ∂²x^l = l(l−1) x^{l−2}, …
  double laplacian = 0.0, scale = 0.0;
  for (int j = 0; j < harmonic::count(N); ++j) {
    const int n = harmonic::degree(j);
    if (n < 2) continue;
    const auto& c = p.coefficients[static_cast<std::size_t>(j)];
    std::vector<double> lap(static_cast<std::size_t>(multi_index::count_of_degree(n - 2)), 0.0);
    const int first = multi_index::first_of_degree(n), first2 = multi_index::first_of_degree(n - 2);
    for (std::size_t i = 0; i < c.size(); ++i) {
      const auto& [l, m, k] = multi_index::exponents(first + static_cast<int>(i));
      scale = std::max(scale, std::abs(c[i]) * std::max({l, m, k}) * std::max({l, m, k}));
      if (l >= 2) lap[static_cast<std::size_t>(multi_index::index(l - 2, m, k) - first2)] += l * (l - 1) * c[i];
      if (m >= 2) lap[static_cast<std::size_t>(multi_index::index(l, m - 2, k) - first2)] += m * (m - 1) * c[i];
      if (k >= 2) lap[static_cast<std::size_t>(multi_index::index(l, m, k - 2) - first2)] += k * (k - 1) * c[i];
    }
    for (double v : lap) laplacian = std::max(laplacian, std::abs(v));
  }
  std::printf("degree %d: values against polynomials %.1e, largest |∇² coefficient| %.1e of %.1e\n", N, worst,
              laplacian, scale);
  EXPECT_LT(laplacian, 1e-14 * scale);
}

TEST(SolidHarmonics, TheSphereProjectsEachHarmonicOntoItself) {
  for (int N : {4, 17, 40}) {
    const SphereProjection sphere(N);
    const auto K = static_cast<Eigen::Index>(sphere.nodes().size());
    EXPECT_EQ(K, (N + 2) * (2 * N + 2));
    // Every third harmonic (all of them cost seconds at degree 40), the last one included.
    const int J = harmonic::count(N);
    std::vector<int> chosen;
    for (int j = J - 1; j >= 0; j -= 3) chosen.push_back(j);
    Eigen::MatrixXd samples(K, static_cast<Eigen::Index>(chosen.size())), expected = Eigen::MatrixXd::Zero(J, samples.cols());
    for (Eigen::Index k = 0; k < K; ++k) {
      const std::vector<double> v = values(sphere.nodes()[static_cast<std::size_t>(k)], N);
      for (std::size_t i = 0; i < chosen.size(); ++i)
        samples(k, static_cast<Eigen::Index>(i)) = v[static_cast<std::size_t>(chosen[i])];
    }
    for (std::size_t i = 0; i < chosen.size(); ++i) expected(chosen[i], static_cast<Eigen::Index>(i)) = 1.0;
    const double error = (sphere.project(samples) - expected).cwiseAbs().maxCoeff();
    std::printf("degree %d: projection of the harmonics off the identity by %.1e\n", N, error);
    EXPECT_LT(error, 1e-12) << N;
  }
}

TEST(SolidHarmonics, APointMassExpandsAboutAPointWithItsGeometricRate) {
  // 1/|x − s| about the origin, sampled on the unit sphere, |s| = 3: the error at |x| ≤ 1 falls
  // as (1/3)^{N+1}.
  const Vec3 s(1.2, -2.1, 1.8);
  const Vec3 x = Vec3(0.3, 0.8, -0.5).normalized();
  double last = 1.0;
  for (int N : {8, 16, 24, 32}) {
    const SphereProjection sphere(N);
    Eigen::MatrixXd f(static_cast<Eigen::Index>(sphere.nodes().size()), 1);
    for (std::size_t k = 0; k < sphere.nodes().size(); ++k) f(static_cast<Eigen::Index>(k), 0) = 1.0 / (sphere.nodes()[k] - s).norm();
    const Eigen::MatrixXd c = sphere.project(f);
    const std::vector<double> v = values(x, N);
    double sum = 0.0;
    for (int j = 0; j < harmonic::count(N); ++j) sum += c(j, 0) * v[static_cast<std::size_t>(j)];
    const double error = std::abs(sum - 1.0 / (x - s).norm()) * s.norm();
    const double expected = std::pow(1.0 / s.norm(), N + 1) / (1.0 - 1.0 / s.norm());
    std::printf("point mass at 3: degree %d, error %.2e (bound (1/3)^(N+1)/(1 − 1/3) = %.2e)\n", N, error, expected);
    EXPECT_LT(error, expected + 5e-14) << N;  // round-off: ~1e-14 of 1/|s|
    if (N <= 24) EXPECT_LT(error, last / 1000) << N;
    last = error;
  }
}

TEST(SolidHarmonics, MomentsFromInertiaIntegralsAreTheSurfaceIntegrals) {
  // ∫ R_j dm = ρ/(n+3) ∮ R_j (x·n) dS, ∫ ∇R_j dm = ρ ∮ R_j n dS, ∫ x × ∇R_j dm = ρ ∮ R_j (x × n) dS,
  // by a Duffy rule exact for these degrees: the octahedron and the KW4 secondary's mesh.
  constexpr int N = 14;
#ifdef NOETHER_TEST_SANITIZED
  const std::vector<Configuration> bodies = {hou_octahedra()};  // the KW4 mesh took 17 s there
#else
  const std::vector<Configuration> bodies = {hou_octahedra(), kw4_polyhedra()};
#endif
  for (const Configuration& c : bodies) {
    const Solid& body = *c.B;
    const double a = body.radius;
    const SolidHarmonicMoments m = solid_harmonic_moments(body.integrals(N), a, solid_harmonic_polynomials(N));
    const SurfaceRule rule = polyhedron_surface_rule(body.mesh, N / 2 + 2);
    const int J = harmonic::count(N);
    Eigen::VectorXd mass = Eigen::VectorXd::Zero(J);
    Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, J), moment = Eigen::Matrix3Xd::Zero(3, J);
    for (std::size_t k = 0; k < rule.points.size(); ++k) {
      const Vec3& x = rule.points[k];
      const std::vector<double> v = values(x / a, N);
      for (int j = 0; j < J; ++j) {
        const double r = v[static_cast<std::size_t>(j)] * body.density;
        mass[j] += r * x.dot(rule.areas[k]) / (harmonic::degree(j) + 3);
        gradient.col(j) += r * rule.areas[k];
        moment.col(j) += r * x.cross(rule.areas[k]);
      }
    }
    const double M = body.mass;
    const double e_mass = (m.mass - mass).cwiseAbs().maxCoeff() / M;
    const double e_gradient = (m.gradient - gradient).cwiseAbs().maxCoeff() * a / M;
    const double e_moment = (m.moment - moment).cwiseAbs().maxCoeff() / M;
    std::printf("%s secondary: moments to degree %d against the surface rule: %.1e, %.1e, %.1e (of the mass)\n",
                c.name.c_str(), N, e_mass, e_gradient, e_moment);
    EXPECT_NEAR(m.mass[0], M, 1e-12 * M);
    EXPECT_LT(e_mass, 1e-12) << c.name;
    EXPECT_LT(e_gradient, 1e-12) << c.name;
    EXPECT_LT(e_moment, 1e-12) << c.name;
  }
}
