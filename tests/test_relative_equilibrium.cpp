// Relative equilibria of rigid binaries and their linear stability (docs/equations.md §18,
// docs/relative-equilibria.md): the generic solver and linearisation (3-D, any potential plugin,
// differenced forces and moments) against the planar sphere–ellipsoid problem written out by hand
// (18.6–18.8), against ω_lib = n √(3(B − A)/C), and on KW4.
#include "test_support.hpp"

#include <noether/relative_equilibrium.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <sstream>

using namespace noether;

namespace {

// A point mass and a homogeneous ellipsoid (G = 1) on a circle of radius r, the ellipsoid's
// long axis `angle` from the line of centres; order-2 series (the second-degree potential).
Scene point_and_ellipsoid(double m_point, double m_ellipsoid, double r, const Vec3& axes, double angle,
                          int order = 2) {
  std::ostringstream scene;
  scene.precision(17);
  const double half = 0.5 * (M_PI + angle);
  scene << "G: 1\nbarycentric: true\nbodies:\n"
        << "  - {name: point, mass: " << m_point << ", position: [0, 0, 0]}\n"
        << "  - name: ellipsoid\n    mass: " << m_ellipsoid << "\n    shape: {ellipsoid: {semi_axes: [" << axes.x()
        << ", " << axes.y() << ", " << axes.z() << "]}}\n    orbit: {around: point, a: " << r << ", nu: 0}\n"
        << "    attitude: {quaternion: [" << std::cos(half) << ", 0, 0, " << std::sin(half) << "]}\n"
        << "potential: {plugin: mutual-series, order: " << order << "}\nintegrator: {plugin: lgvi, step: 0.2}\n"
        << "run: {t_end: 1, output_every: 1}\n";
  return parse_scene(scene.str(), "point-ellipsoid.yaml");
}

// The planar problem of a point mass M and an ellipsoid m (moments A < B < C) in its
// second-degree potential, reduced by the angular momentum K (docs/equations.md (18.6–18.8)):
// the relative equilibrium at separation r with the long axis at φ0 (0 or π/2), and the
// in-plane characteristic polynomial ν C' s⁴ + (ν k_φ + C' k_r + g²) s² + k_r k_φ = 0.
struct PlanarSphereEllipsoid {
  double rate, k_r, k_phi;
  std::complex<double> s[2];  // the two roots s with Im s ≥ 0 (or Re s > 0)
  bool linearly_stable() const { return std::abs(s[0].real()) < 1e-12 && std::abs(s[1].real()) < 1e-12; }
  bool energetically_stable() const { return k_r > 0 && k_phi > 0; }
};

PlanarSphereEllipsoid planar(double M, double m, const Vec3& axes, double r, double phi0) {
  const double a2 = axes.x() * axes.x(), b2 = axes.y() * axes.y(), c2 = axes.z() * axes.z();
  const double A = m * (b2 + c2) / 5, B = m * (a2 + c2) / 5, C = m * (a2 + b2) / 5;
  const double nu = M * m / (M + m), sin2 = std::pow(std::sin(phi0), 2);
  const double Q = (B + C - 2 * A) - 3 * (B - A) * sin2;
  const double U_r = M * m / (r * r) + 1.5 * M * Q / std::pow(r, 4);
  const double U_rr = -2 * M * m / std::pow(r, 3) - 6 * M * Q / std::pow(r, 5);
  const double w2 = U_r / (nu * r), I = nu * r * r + C;
  PlanarSphereEllipsoid p;
  p.rate = std::sqrt(w2);
  p.k_r = U_rr + w2 * (4 * nu * nu * r * r / I - nu);
  p.k_phi = 3 * M * (B - A) * std::cos(2 * phi0) / std::pow(r, 3);
  const double Ce = C * nu * r * r / I, g = 2 * p.rate * C * nu * r / I;
  const double a = nu * Ce, b = nu * p.k_phi + Ce * p.k_r + g * g, c = p.k_r * p.k_phi;
  const std::complex<double> disc = std::sqrt(std::complex<double>(b * b - 4 * a * c));
  for (int i = 0; i < 2; ++i) {
    std::complex<double> s = std::sqrt((-b + (i == 0 ? 1.0 : -1.0) * disc) / (2 * a));
    if (s.imag() < 0 || (s.imag() == 0 && s.real() < 0)) s = -s;
    p.s[i] = s;
  }
  return p;
}

// In-plane modes of the generic linearisation, one λ per ± pair.
std::vector<std::complex<double>> in_plane(const EquilibriumStability& st) {
  std::vector<std::complex<double>> out;
  for (const auto& m : st.modes)
    if (m.in_plane) out.push_back(m.eigenvalue);
  return out;
}

double nearest(const std::vector<std::complex<double>>& list, std::complex<double> z) {
  double best = INFINITY;
  for (auto l : list) best = std::min({best, std::abs(l - z), std::abs(std::conj(l) - z), std::abs(l + z), std::abs(std::conj(l) + z)});
  return best;
}

}  // namespace

// What the issue asks first: a synchronous ellipsoidal secondary about a sphere librates at
// ω_lib = n √(3(B − A)/C) up to the mass ratio and (a/r)²; the linearisation reproduces the
// hand-written planar model to the differencing's precision and the formula to that order.
TEST(RelativeEquilibrium, LibrationFrequencyMatchesTheSpinOrbitFormulaToTheExpectedOrder) {
  auto registry = test::bundled_plugins();
  const Vec3 axes(0.2, 0.18, 0.15);
  const double a2 = axes.x() * axes.x(), b2 = axes.y() * axes.y(), c2 = axes.z() * axes.z();
  double previous = INFINITY;
  for (auto [q, r] : {std::pair{1e-2, 4.0}, std::pair{1e-3, 8.0}, std::pair{1e-4, 16.0}, std::pair{1e-6, 32.0}}) {
    const Scene s = point_and_ellipsoid(1.0, q, r, axes, 0.3);
    const auto model = FullBodyModel::from_scene(s, registry);
    const auto eq = find_relative_equilibrium(model, s.initial);
    ASSERT_TRUE(eq.converged) << "residual " << eq.residual;
    EXPECT_NEAR(eq.separation, r, 1e-12 * r);
    const auto st = linear_stability(model, eq);
    EXPECT_LT(st.invariance_defect, 1e-8);
    EXPECT_EQ(st.verdict, "linearly stable");
    EXPECT_EQ(st.energetic_verdict, "energetically stable");
    EXPECT_TRUE(st.planar);
    double lib = 0;
    for (const auto& m : st.modes)
      if (m.kind == "libration of ellipsoid" && m.in_plane) lib = m.frequency;
    const double n = std::sqrt((1.0 + q) / (r * r * r));
    const double formula = n * std::sqrt(3 * (a2 - b2) / (a2 + b2));  // 3(B − A)/C for the ellipsoid
    const auto hand = planar(1.0, q, axes, r, 0.0);
    const double order = q + a2 / (r * r);
    std::printf("m/M %.0e, r %4.0f: omega_lib %.10f, formula %.10f (difference %+.2e, expected order %.1e), "
                "hand-written planar model %.10f, %.10f\n",
                q, r, lib, formula, lib / formula - 1, order, hand.s[0].imag(), hand.s[1].imag());
    EXPECT_LT(std::min(std::abs(lib - hand.s[0].imag()), std::abs(lib - hand.s[1].imag())), 1e-7 * lib);  // one model, two formulations
    EXPECT_NEAR(eq.rate, hand.rate, 1e-10 * eq.rate);
    EXPECT_LT(std::abs(lib / formula - 1), 2 * order);
    EXPECT_LT(std::abs(lib / formula - 1), previous);  // and it shrinks with that order
    previous = std::abs(lib / formula - 1);
  }
}

// Sphere–ellipsoid relative equilibria (Scheeres 2009; Bellerose & Scheeres 2008): a small
// sphere about a large ellipsoid locked to it. The long-axis equilibrium is stable above the
// separation r* where the family's angular momentum is least (k_r = 0); the short-axis one is
// never a minimum of the energy (k_φ < 0), although gyroscopic coupling makes it linearly
// stable on a band of separations. Across a sweep, the generic solver finds both, and its
// verdicts and frequencies match the planar model's.
TEST(RelativeEquilibrium, SphereEllipsoidVerdictsMatchScheeresConditionsAcrossSeparations) {
  auto registry = test::bundled_plugins();
  const Vec3 axes(1.0, 0.7, 0.5);
  const double M = 0.05, m = 1.0;  // the sphere, the ellipsoid
  // r*: the root of k_r on the long-axis branch, by bisection on the planar model.
  double lo = 1.6, hi = 8;
  ASSERT_LT(planar(M, m, axes, lo, 0).k_r, 0);
  ASSERT_GT(planar(M, m, axes, hi, 0).k_r, 0);
  for (int i = 0; i < 60; ++i) (planar(M, m, axes, 0.5 * (lo + hi), 0).k_r > 0 ? hi : lo) = 0.5 * (lo + hi);
  const double r_star = 0.5 * (lo + hi);
  std::printf("r* = %.8f (contact at %.2f)\n", r_star, axes.x());
  int long_stable = 0, short_linear = 0;
  for (double r : {1.5, 2.0, 3.0, 4.0, 0.999 * r_star, 1.001 * r_star, 6.0, 8.0, 12.0}) {
    for (double phi0 : {0.0, M_PI / 2}) {
      const Scene s = point_and_ellipsoid(M, m, r, axes, phi0 + 0.2);  // a guess 0.2 rad off
      const auto model = FullBodyModel::from_scene(s, registry);
      const auto eq = find_relative_equilibrium(model, s.initial);
      ASSERT_TRUE(eq.converged) << "r " << r;
      // The equilibrium found is the symmetric one sought: long (short) axis on the line of centres.
      const Vec3 line = (eq.state.x.col(0) - eq.state.x.col(1)).normalized();
      const double along = std::abs(line.dot(eq.state.R[0].col(0)));
      EXPECT_NEAR(along, phi0 == 0 ? 1.0 : 0.0, 1e-9) << "r " << r;
      const auto st = linear_stability(model, eq);
      const auto hand = planar(M, m, axes, r, phi0);
      EXPECT_NEAR(eq.rate, hand.rate, 1e-10 * hand.rate);
      const auto modes = in_plane(st);
      // a complex quartet ±a ± ib is one mode; else one mode per root
      ASSERT_EQ(modes.size(), hand.s[0].real() != 0 && hand.s[0].imag() != 0 ? 1u : 2u) << "r " << r;
      for (auto z : hand.s) EXPECT_LT(nearest(modes, z), 1e-6 * eq.rate) << "r " << r << " s " << z;
      for (auto l : modes) EXPECT_LT(nearest({hand.s[0], hand.s[1]}, l), 1e-6 * eq.rate) << "r " << r << " l " << l;
      EXPECT_EQ(st.in_plane_verdict, hand.linearly_stable() ? "linearly stable" : "unstable") << "r " << r;
      EXPECT_EQ(st.energetic_verdict == "energetically stable", hand.energetically_stable()) << "r " << r;
      EXPECT_EQ(st.out_of_plane_verdict, "linearly stable") << "r " << r;
      std::printf("r %7.4f %s: in-plane %-15s energetic %-25s (planar model: k_r %+.2e, k_phi %+.2e)\n", r,
                  phi0 == 0 ? "long axis " : "short axis", st.in_plane_verdict.c_str(), st.energetic_verdict.c_str(),
                  hand.k_r, hand.k_phi);
      if (phi0 == 0) {
        EXPECT_EQ(st.energetic_verdict == "energetically stable", r > r_star) << "r " << r;
        long_stable += r > r_star;
      } else {
        EXPECT_NE(st.energetic_verdict, "energetically stable") << "r " << r;
        short_linear += st.in_plane_verdict == "linearly stable";
      }
    }
  }
  EXPECT_EQ(long_stable, 4);     // 1.001 r*, 6, 8, 12
  EXPECT_GE(short_linear, 1);    // the gyroscopic band exists for these parameters
}

// KW4 as ellipsoids: the locked equilibrium at the published separation. Both bodies locked
// at 2.547 km is Darwin-unstable — the orbit's angular momentum ν r² ω is less than 3× the
// bodies' spin C ω (Hut 1980), so one real pair — while Beta's libration and the tilts are
// oscillations; and the energy-momentum test agrees (one negative direction).
TEST(RelativeEquilibrium, KW4NearestEquilibriumIsDarwinUnstableWithBetaLibrating) {
  auto registry = test::bundled_plugins();
  const Scene s = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"));
  const auto model = FullBodyModel::from_scene(s, registry);
  const auto eq = find_relative_equilibrium(model, s.initial);
  ASSERT_TRUE(eq.converged);
  const double r0 = (s.initial.x.col(0) - s.initial.x.col(1)).norm();
  EXPECT_NEAR(eq.separation, r0, 1e-9 * r0);
  const auto st = linear_stability(model, eq);
  EXPECT_LT(st.invariance_defect, 1e-8);
  const double ma = s.system.body(0).mass, mb = s.system.body(1).mass, nu = ma * mb / (ma + mb);
  const double C = s.system.body(0).inertia(2, 2) + s.system.body(1).inertia(2, 2);
  EXPECT_LT(nu * r0 * r0, 3 * C);  // Hut's criterion says unstable
  int real_pairs = 0;
  for (const auto& m : st.modes) real_pairs += m.frequency == 0 && m.eigenvalue.real() > 0;
  EXPECT_EQ(real_pairs, 1);
  EXPECT_EQ(st.in_plane_verdict, "unstable");
  EXPECT_EQ(st.out_of_plane_verdict, "linearly stable");
  EXPECT_EQ(st.energetic_index, 1);
  // Beta's libration: of the order of n √(3(B − A)/C) for Beta, pulled by the coupling to the orbit.
  const Mat3& J = s.system.body(1).inertia;
  const double formula = eq.rate * std::sqrt(3 * (J(1, 1) - J(0, 0)) / J(2, 2));
  double lib = 0;
  for (const auto& m : st.modes)
    if (m.kind == "libration of beta" && m.frequency > 0 && lib == 0) lib = m.frequency;
  std::printf("KW4: rate %.6e rad/s, Beta libration %.6e rad/s (period %.2f h), n sqrt(3(B-A)/C) %.6e\n", eq.rate, lib,
              2 * M_PI / lib / 3600, formula);
  EXPECT_NEAR(lib / formula, 1.0, 0.1);
}

TEST(RelativeEquilibrium, RefusesWhatHasNoRelativeEquilibrium) {
  auto registry = test::bundled_plugins();
  const Scene kepler = load_scene(test::source_path("examples/orbits/kepler-central.yaml"));
  const auto field = FullBodyModel::from_scene(kepler, registry);
  EXPECT_THROW(find_relative_equilibrium(field, kepler.initial), SceneError);  // one body, external field
  Scene s = point_and_ellipsoid(1.0, 1e-3, 8.0, Vec3(0.2, 0.18, 0.15), 0.0);
  const auto model = FullBodyModel::from_scene(s, registry);
  State rest = s.initial;
  rest.p.setZero();
  rest.Pi.setZero();
  try {
    find_relative_equilibrium(model, rest);
    ADD_FAILURE() << "no angular momentum accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("angular momentum"), std::string::npos) << e.what();
  }
  EquilibriumOptions same;
  same.body_b = 0;
  EXPECT_THROW(find_relative_equilibrium(model, s.initial, same), SceneError);
}

// Three point masses at the corners of an equilateral triangle turning at ω (Lagrange 1772): an
// equilibrium for any masses. With β = (m1 m2 + m2 m3 + m3 m1)/M², its in-plane eigenvalues are
// λ² = x ω² with x² + x + 27β/4 = 0, plus ±iω, and out of the plane ±iω; linearly stable exactly
// when 27β < 1 (Gascheau 1843, Routh 1875). The generic solver and linearisation, point masses in
// 3-D, against that, on both sides of the threshold.
TEST(RelativeEquilibrium, LagrangeTriangleMatchesRouthsCriterion) {
  auto registry = test::bundled_plugins();
  const double m3 = 1e-3;
  // The m2 at which 27β = 1 (m1 = 1): 27(m2 + m2 m3 + m3) = (1 + m2 + m3)², the smaller root.
  const double b = 2 * (1 + m3) - 27 * (1 + m3), c = (1 + m3) * (1 + m3) - 27 * m3;
  const double m2_critical = (-b - std::sqrt(b * b - 4 * c)) / 2;
  for (const double m2 : {1.0, 0.01, 0.97 * m2_critical, 1.03 * m2_critical}) {
    const double M = 1 + m2 + m3, beta = (m2 + m2 * m3 + m3) / (M * M);
    std::ostringstream scene;
    scene.precision(17);
    scene << "G: 1\nbodies:\n";
    const double masses[3] = {1, m2, m3};
    for (int k = 0; k < 3; ++k) {  // unit triangle; velocities a guess (the solver sets them)
      const double angle = 2 * M_PI * k / 3;
      scene << "  - {name: b" << k << ", mass: " << masses[k] << ", position: [" << std::cos(angle) << ", "
            << std::sin(angle) << ", 0], velocity: [" << -std::sin(angle) << ", " << std::cos(angle) << ", 0]}\n";
    }
    scene << "potential: {plugin: point-mass}\nintegrator: {plugin: rk}\nrun: {t_end: 1, output_every: 1}\n";
    const Scene s = parse_scene(scene.str(), "lagrange.yaml");
    const auto model = FullBodyModel::from_scene(s, registry);
    const auto eq = find_relative_equilibrium(model, s.initial);
    ASSERT_TRUE(eq.converged) << "m2 = " << m2;
    const auto st = linear_stability(model, eq);
    const double w = eq.rate;
    // The predicted spectrum, each matched to a computed eigenvalue.
    std::vector<std::complex<double>> expected{{0, w}, {0, -w}, {0, w}, {0, -w}};
    const std::complex<double> disc = std::sqrt(std::complex<double>(1 - 27 * beta));
    for (const auto x : {(-1.0 + disc) / 2.0, (-1.0 - disc) / 2.0})
      for (const double sign : {1.0, -1.0}) expected.push_back(sign * std::sqrt(x) * w);
    ASSERT_EQ(st.eigenvalues.size(), expected.size()) << "m2 = " << m2;
    std::vector<std::complex<double>> left = st.eigenvalues;
    for (const auto& e : expected) {
      auto nearest = std::min_element(left.begin(), left.end(), [&](auto p, auto q) { return std::abs(p - e) < std::abs(q - e); });
      EXPECT_NEAR(std::abs(*nearest - e), 0.0, 1e-6 * w) << "m2 = " << m2 << ", expected " << e << ", nearest " << *nearest;
      left.erase(nearest);
    }
    EXPECT_EQ(st.verdict, 27 * beta < 1 ? "linearly stable" : "unstable") << "m2 = " << m2 << ", 27 beta = " << 27 * beta;
    std::printf("Lagrange m = (1, %.6g, %g): 27 beta = %.4f, verdict %s, max |Re lambda| / omega = %.3g\n", m2, m3,
                27 * beta, st.verdict.c_str(), st.max_real / w);
  }
}
