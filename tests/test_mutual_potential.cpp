// The mutual potential of real shapes (docs/equations.md §13–13): exact fields against
// independent formulas, the exact reference against a second exact formula, and the
// inertia-integral series converging to the exact reference with its order.
#include "mutual_configurations.hpp"

#include <noether/exact_mutual.hpp>
#include <noether/gravity_field.hpp>
#include <noether/mutual_series.hpp>

#include <gtest/gtest.h>

#include <cstdio>

using namespace noether;
using namespace noether::test;

namespace {

constexpr double G = 6.674e-11;

struct Errors {
  double U, F, M;  // relative: |ΔU|/|U|, |ΔF|/|F|, max |ΔM| / (|R| |F|)
};

Errors compare(const MutualTerms& a, const MutualTerms& b, const Vec3& R) {
  const double F = b.dU_dR.norm();
  return {std::abs(a.U - b.U) / std::abs(b.U), (a.dU_dR - b.dU_dR).norm() / F,
          std::max((a.torque_A - b.torque_A).norm(), (a.torque_B - b.torque_B).norm()) / (F * R.norm())};
}

MutualTerms series(const Configuration& c, int N) {
  MutualSeries s(N);
  return s.evaluate(G, c.A->integrals(N), c.B->integrals(N), c.R, c.C);
}

MutualTerms exact(const Configuration& c, double tolerance = 1e-13,
                  ExactMutualOptions::Surface surface = ExactMutualOptions::Surface::Automatic) {
  ExactMutualOptions o;
  o.tolerance = tolerance;
  o.max_level = 9;
  o.surface = surface;
  ExactMutual e(G, c.A, c.A->mass, c.B, c.B->mass, o);
  return e.evaluate(c.R, c.C);
}

// Werner & Scheeres 2005 Eq. 1 (Liebenthal): U = (Gρ_Aρ_B/2) ∮∮ (n_a·n_b) |x − y| dS dS,
// a double surface integral independent of either body's exterior field.
double double_surface_U(const Configuration& c, int n) {
  const SurfaceRule a = polyhedron_surface_rule(c.A->mesh, n), b = polyhedron_surface_rule(c.B->mesh, n);
  long double sum = 0.0L;
  for (std::size_t l = 0; l < b.points.size(); ++l) {
    const Vec3 y = c.R + c.C * b.points[l], wb = c.C * b.areas[l];
    for (std::size_t k = 0; k < a.points.size(); ++k) sum += a.areas[k].dot(wb) * (a.points[k] - y).norm();
  }
  return 0.5 * G * c.A->density * c.B->density * static_cast<double>(sum);
}

}  // namespace

TEST(GravityField, PolyhedronFieldAgreesWithItsMultipoleSeriesAndItsGradient) {
  // A box seen from 4 half-widths: Werner–Scheeres against the box's own series to degree 16
  // (a unit point mass paired with the box), and g against −∇Φ by central differences.
  const auto box = make_polyhedron(box_mesh(Vec3(1.0, 0.6, 0.4)), 3.0, false);
  const PolyhedronField field(box->mesh, G * box->density);
  const auto T = box->integrals(16);
  MutualSeries s(16);
  const InertiaIntegrals unit = point_integrals({1.0}, {Vec3::Zero()}, 0);
  for (const Vec3& p : {Vec3(4.0, 0.3, -0.2), Vec3(-1.0, 3.2, 2.1), Vec3(0.5, -0.7, -4.5)}) {
    const FieldValue v = field(p);
    const MutualTerms m = s.evaluate(G, T, unit, p, Mat3::Identity());  // U of a unit mass at p
    EXPECT_NEAR(v.phi, m.U, 1e-11 * std::abs(m.U));
    EXPECT_LT((v.g + m.dU_dR).norm(), 1e-10 * v.g.norm());  // force on the unit mass = −∂U/∂R
    EXPECT_FALSE(v.inside);
    for (int i = 0; i < 3; ++i) {
      const double h = 1e-5;
      const double d = (field(p + h * Vec3::Unit(i)).phi - field(p - h * Vec3::Unit(i)).phi) / (2 * h);
      EXPECT_NEAR(-d, v.g[i], 1e-7 * v.g.norm());
    }
  }
  EXPECT_TRUE(field(Vec3(0.1, 0.1, 0.1)).inside);
}

TEST(GravityField, EllipsoidFieldAgreesWithItsSeriesAndASphereIsAPointMass) {
  const auto ell = make_ellipsoid(Vec3(2.0, 1.3, 0.9), 2.0);
  const EllipsoidField field(ell->semi_axes, G * ell->density);
  MutualSeries s(20);
  const auto T = ell->integrals(20);
  const InertiaIntegrals unit = point_integrals({1.0}, {Vec3::Zero()}, 0);
  for (const Vec3& p : {Vec3(6.0, 1.0, -0.5), Vec3(-2.0, 5.5, 3.0)}) {
    const FieldValue v = field(p);
    const MutualTerms m = s.evaluate(G, T, unit, p, Mat3::Identity());
    EXPECT_NEAR(v.phi, m.U, 1e-11 * std::abs(m.U));
    EXPECT_LT((v.g + m.dU_dR).norm(), 1e-10 * v.g.norm());
  }
  const auto sphere = make_ellipsoid(Vec3(1.5, 1.5, 1.5), 2.0);
  const EllipsoidField sf(sphere->semi_axes, G * sphere->density);
  const Vec3 p(1.0, 2.0, -2.5);
  EXPECT_NEAR(sf(p).phi, -G * sphere->mass / p.norm(), 1e-14 * G * sphere->mass / p.norm());
}

TEST(ExactMutual, TwoSpheresAreExactlyTwoPointMasses) {
  const Configuration c{"spheres", make_ellipsoid(Vec3(1, 1, 1), 3.0), make_ellipsoid(Vec3(0.5, 0.5, 0.5), 1.0),
                        Vec3(1.2, -2.0, 0.7),
                        Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix()};
  const MutualTerms t = exact(c);
  const double U = -G * c.A->mass * c.B->mass / c.R.norm();
  EXPECT_NEAR(t.U, U, 1e-13 * std::abs(U));
  EXPECT_LT((t.dU_dR - (-U / c.R.norm()) * c.R.normalized()).norm(), 1e-12 * std::abs(U) / c.R.norm());  // ∂U/∂R = −U/R ê
  EXPECT_LT(t.torque_A.norm() + t.torque_B.norm(), 1e-11 * std::abs(U));
  // And the series of two spheres is exact at every order.
  for (int N : {0, 2, 5, 8}) EXPECT_NEAR(series(c, N).U, U, 1e-14 * std::abs(U)) << N;
}

TEST(ExactMutual, AgreesWithTheDoubleSurfaceIntegralOnTheOctahedra) {
  std::vector<Configuration> cases = fahnestock_octahedra();
  cases.insert(cases.begin(), hou_octahedra());
  for (const auto& c : cases) {
    const double U = exact(c).U;
    const double Ud = double_surface_U(c, 20);
    EXPECT_LT(std::abs(U - Ud) / std::abs(U), 1e-12) << c.name << " U " << U << " double-surface " << Ud;
  }
}

TEST(ExactMutual, EitherBodysSurfaceGivesTheSameAnswer) {
  for (const auto& c : {hou_octahedra(), fahnestock_octahedra()[2], didymos_gubas()}) {
    const MutualTerms a = exact(c, 1e-13, ExactMutualOptions::Surface::A);
    const MutualTerms b = exact(c, 1e-13, ExactMutualOptions::Surface::B);
    const Errors e = compare(a, b, c.R);
    EXPECT_LT(e.U, 1e-12) << c.name;
    EXPECT_LT(e.F, 1e-11) << c.name;
    EXPECT_LT(e.M, 1e-9) << c.name;
  }
}

TEST(MutualSeries, OrderZeroIsThePointMassPotential) {
  const Configuration c = hou_octahedra();
  const MutualTerms t = series(c, 0);
  const double U = -G * c.A->mass * c.B->mass / c.R.norm();
  EXPECT_NEAR(t.U, U, 1e-15 * std::abs(U));
  EXPECT_LT((t.dU_dR + U / c.R.norm() * c.R.normalized()).norm(), 1e-15 * std::abs(U) / c.R.norm());
  EXPECT_EQ(series(c, 1).U, t.U);  // first moments vanish about the centres of mass
}

TEST(MutualSeries, ConvergesToTheExactReferenceOnTheOctahedra) {
  std::vector<Configuration> cases = fahnestock_octahedra();
  cases.insert(cases.begin(), hou_octahedra());
  for (const auto& c : cases) {
    const MutualTerms ref = exact(c);
    std::printf("%-12s  N   rel U      rel F      torque\n", c.name.c_str());
    // The error is not monotone from one order to the next (not even every second order:
    // fahn_oct_1 has 2.5e-6 at N = 6 and 5.1e-6 at N = 8), so the assertion is that it falls
    // across N = 2, 4, 8, 12 — for U, the force and the torques.
    Errors previous{1, 1, 1};
    for (int N = 0; N <= 12; ++N) {
      const Errors e = compare(series(c, N), ref, c.R);
      std::printf("%-12s %2d  %.3e  %.3e  %.3e\n", "", N, e.U, e.F, e.M);
      if (N == 2 || N == 4 || N == 8 || N == 12) {
        EXPECT_LT(e.U, previous.U) << c.name << " N=" << N;
        EXPECT_LT(e.F, previous.F) << c.name << " N=" << N;
        if (c.name != "fahn_oct_2") EXPECT_LT(e.M, previous.M) << c.name << " N=" << N;  // its torques vanish
        previous = e;
      }
      if (c.name == "hou_oct" && N == 12) {
        EXPECT_LT(e.U, 1e-8);
        EXPECT_LT(e.F, 1e-6);
        EXPECT_LT(e.M, 1e-6);
      }
    }
  }
}

TEST(MutualSeries, ConvergesToTheExactReferenceOnEllipsoidsAndDidymos) {
  for (const auto& c : {kw4_ellipsoids(), didymos_gubas()}) {
    const MutualTerms ref = exact(c);
    std::printf("%-12s  N   rel U      rel F      torque\n", c.name.c_str());
    double last_U = 1, last_F = 1;
    for (int N = 2; N <= 12; N += 2) {
      const Errors e = compare(series(c, N), ref, c.R);
      std::printf("%-12s %2d  %.3e  %.3e  %.3e\n", "", N, e.U, e.F, e.M);
      EXPECT_LT(e.U, last_U) << c.name << " N=" << N;
      EXPECT_LT(e.F, last_F) << c.name << " N=" << N;
      last_U = std::max(e.U, 1e-15), last_F = std::max(e.F, 1e-14);
    }
    const Errors e12 = compare(series(c, 12), ref, c.R);
    EXPECT_LT(e12.U, 1e-10) << c.name;
    EXPECT_LT(e12.F, 1e-8) << c.name;
  }
}
