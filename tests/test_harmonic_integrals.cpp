// Inertia integrals modulo traces (docs/equations.md (13.9)–(13.11)): a ball's class is its mass
// alone; the class turns as the mesh does; the Stokes coefficients (an independent use of the
// same integrals, §31) and the series (against the full integrals turned by (12.6)) do not see
// the difference between the integrals and their class.
#include "shapes.hpp"

#include <noether/error.hpp>
#include <noether/gravity_field.hpp>
#include <noether/harmonic_integrals.hpp>
#include <noether/inertia_integrals.hpp>
#include <noether/mutual_series.hpp>
#include <noether/stokes_coefficients.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;
using namespace noether::test;
using multi_index::count;
using multi_index::exponents;

namespace {

InertiaIntegrals reduced(InertiaIntegrals T) {
  TraceReduction(T.order).apply(T.T.data(), T.order);
  return T;
}

// max over degree d of |a − b| / (M r^d)
double worst_by_degree(const InertiaIntegrals& a, const InertiaIntegrals& b, double mass, double r) {
  double worst = 0.0;
  for (int i = 0; i < count(std::min(a.order, b.order)); ++i)
    worst = std::max(worst, std::abs(a.T[static_cast<std::size_t>(i)] - b.T[static_cast<std::size_t>(i)]) /
                                (mass * std::pow(r, multi_index::degree(i))));
  return worst;
}

const Mat3 kTurn = (Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized()) *
                    Eigen::AngleAxisd(-1.1, Vec3::UnitY())).toRotationMatrix();

}  // namespace

TEST(HarmonicIntegrals, ABallsClassIsItsMassAlone) {
  // A homogeneous ball's exterior field is a point mass's: every degree ≥ 1 reduces to zero, while
  // the integrals themselves (∫ x²ᵏ dm, …) do not vanish.
  const double a = 1.7, M = 3.2;
  const InertiaIntegrals T = ellipsoid_integrals(M, Vec3(a, a, a), 14);
  const InertiaIntegrals R = reduced(T);
  EXPECT_DOUBLE_EQ(R.T[0], M);
  double worst = 0.0, largest = 0.0;
  for (int i = 1; i < count(14); ++i) {
    const double s = M * std::pow(a, multi_index::degree(i));
    worst = std::max(worst, std::abs(R.T[static_cast<std::size_t>(i)]) / s);
    largest = std::max(largest, std::abs(T.T[static_cast<std::size_t>(i)]) / s);
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_GT(largest, 0.1);
  // An ellipsoid's class is not its mass alone, and is zero above z¹ by construction.
  const InertiaIntegrals E = reduced(ellipsoid_integrals(M, Vec3(a, 1.2, 0.8), 14));
  EXPECT_GT(std::abs(E(2, 0, 0)), 0.1 * M);
  for (int i = 0; i < count(14); ++i)
    if (exponents(i)[2] > 1) EXPECT_EQ(E.T[static_cast<std::size_t>(i)], 0.0);
}

TEST(HarmonicIntegrals, TheClassTurnsAsTheMeshDoes) {
  // (13.10) against the class of the integrals of the mesh whose vertices were turned by C.
  const Mesh mesh = shipped_mesh("hou2017_B.obj");
  Mesh turned = mesh;
  for (Eigen::Index i = 0; i < turned.vertices.cols(); ++i) turned.vertices.col(i) = kTurn * mesh.vertices.col(i);
  for (const int N : {1, 2, 5, 12}) {
    const auto T = polyhedron_integrals(mesh, 2000, N);
    InertiaIntegrals rotated;
    HarmonicRotation rotation(N);
    rotation.apply(kTurn, T, rotated);
    ASSERT_EQ(rotated.order, N);
    EXPECT_LT(worst_by_degree(rotated, reduced(polyhedron_integrals(turned, 2000, N)), T.mass(), 2.0), 1e-13) << "N " << N;
    // and against (12.6)'s full turn, reduced
    InertiaIntegrals full;
    IntegralRotation(N).apply(kTurn, T, full);
    EXPECT_LT(worst_by_degree(rotated, reduced(full), T.mass(), 2.0), 1e-14) << "N " << N;
  }
  // Only the degrees asked for: max_degree caps the output.
  InertiaIntegrals capped;
  HarmonicRotation(12).apply(kTurn, polyhedron_integrals(mesh, 2000, 12), capped, 6);
  EXPECT_EQ(capped.order, 6);
  EXPECT_EQ(capped.T.size(), static_cast<std::size_t>(count(6)));
  EXPECT_THROW(HarmonicRotation(4).apply(kTurn, polyhedron_integrals(mesh, 2000, 6), capped), Error);
}

TEST(HarmonicIntegrals, TheStokesCoefficientsSeeOnlyTheClass) {
  // (31.1) pairs each degree's integrals with a harmonic polynomial: the class gives the same field.
  const auto beta = make_polyhedron(shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true);
  const InertiaIntegrals T = beta->integrals(12);
  const StokesCoefficients a = stokes_from_integrals(T, beta->radius, 12, true);
  const StokesCoefficients b = stokes_from_integrals(reduced(T), beta->radius, 12, true);
  double worst = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < a.C.size(); ++i) {
    worst = std::max({worst, std::abs(a.C[i] - b.C[i]), std::abs(a.S[i] - b.S[i])});
    largest = std::max(largest, std::abs(a.C[i]));
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_GT(largest, 1e-2);  // C̄20
}

TEST(HarmonicIntegrals, TheSeriesOfTheClassIsTheSeriesOfTheIntegrals) {
  // MutualSeries::evaluate turns B's class (13.10) and sums over the reduced multi-indices (13.11);
  // the same series from the full integrals turned by (12.6) and given to evaluate_rotated —
  // which reduces them itself — and, independently, the terms' identities (13.7) hold.
  const auto alpha = make_polyhedron(shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, true);
  const auto beta = make_polyhedron(shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true);
  const double G = 6.674e-11;
  const Vec3 R(1300, 450, -200);
  for (const int N : {3, 8, 12}) {
    const InertiaIntegrals TA = alpha->integrals(N), TB = beta->integrals(N);
    InertiaIntegrals full;
    IntegralRotation(N).apply(kTurn, TB, full);
    MutualSeries series(N);
    const MutualTerms a = series.evaluate(G, TA, TB, R, kTurn);
    const MutualTerms b = series.evaluate_rotated(G, TA, full, R);
    EXPECT_NEAR(a.U, b.U, 1e-14 * std::abs(b.U)) << N;
    EXPECT_LT((a.dU_dR - b.dU_dR).norm(), 1e-13 * b.dU_dR.norm()) << N;
    EXPECT_LT((a.torque_A - b.torque_A).norm(), 1e-12 * b.torque_A.norm()) << N;
    EXPECT_LT((a.torque_B - b.torque_B).norm(), 1e-12 * b.torque_B.norm()) << N;
    EXPECT_LT((R.cross(a.dU_dR) - a.torque_A - a.torque_B).norm(), 1e-12 * a.torque_B.norm()) << N;
  }
}
