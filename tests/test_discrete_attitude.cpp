// The implicit attitude solve of the LGVI, (128)–(130).
#include <noether/discrete_attitude.hpp>
#include <noether/error.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;

namespace {
const Mat3 J1 = Vec3(0.0004, 0.0238, 0.0238).asDiagonal();  // dumbbell alpha, docs/equations.md §6
const Mat3 Jfull = [] {
  Mat3 J;
  J << 2.0, 0.3, -0.1,  //
      0.3, 3.0, 0.2,    //
      -0.1, 0.2, 4.0;
  return J;
}();
Mat3 nonstandard(const Mat3& J) { return 0.5 * J.trace() * Mat3::Identity() - J; }
}  // namespace

// ∇G of (130) against central differences of G, on both sides of the series switch.
TEST(DiscreteAttitude, JacobianMatchesFiniteDifferences) {
  const Vec3 dir = Vec3(0.7, -0.3, 0.5).normalized();
  for (double x : {1e-3, 2e-2, 0.5, 2.5}) {
    const Vec3 f = x * dir;
    const Mat3 analytic = discrete_attitude_jacobian(f, Jfull);
    Mat3 numeric;
    const double eps = 1e-6 * std::max(x, 1e-2);
    for (int c = 0; c < 3; ++c) {
      Vec3 e = Vec3::Zero();
      e[c] = eps;
      numeric.col(c) = (discrete_attitude_residual_map(f + e, Jfull) -
                        discrete_attitude_residual_map(f - e, Jfull)) / (2 * eps);
    }
    EXPECT_LT((analytic - numeric).norm() / analytic.norm(), 1e-8) << "‖f‖ = " << x;
  }
}

// For ‖f‖ from 1e-12 to 3: Newton recovers f from g = G(f), F is orthogonal to 1e-15, and F
// solves the defining equation S(g) = F Jd − Jd Fᵀ (93).
TEST(DiscreteAttitude, NewtonSolvesTheDefiningEquation) {
  const Vec3 dir = Vec3(0.2, 0.9, -0.4).normalized();
  int max_iterations = 0;
  for (const Mat3* J : {&J1, &Jfull}) {
    for (double x = 1e-12; x <= 3.0; x *= 3.0) {
      const Vec3 f = x * dir;
      const Vec3 g = discrete_attitude_residual_map(f, *J);
      const auto s = solve_discrete_attitude(g, *J);
      max_iterations = std::max(max_iterations, s.iterations);
      EXPECT_LE(orthogonality_error(s.F), 1e-15) << "‖f‖ = " << x;
      // G is one-to-one near 0 only; beyond, Newton may find another branch that solves (93)
      // too (see docs/numerical-results.md).
      if (x < 1.5) EXPECT_LT((s.f - f).norm(), 1e-11 * x) << "‖f‖ = " << x;
      const Mat3 Jd = nonstandard(*J);
      const Mat3 lhs = hat(g), rhs = s.F * Jd - Jd * s.F.transpose();
      // Evaluating F Jd − Jd Fᵀ has a round-off floor of a few ε ‖J‖.
      EXPECT_LT((lhs - rhs).norm(), 1e-14 * J->norm() * x + 1e-15 * J->norm())
          << "‖f‖ = " << x;
    }
  }
  EXPECT_LE(max_iterations, 8);
}

// At the dumbbell's spin (|Ω| = 9, h = 2e-4) Lee et al. (2007) report 3–4 iterations.
TEST(DiscreteAttitude, FewIterationsAtTheDumbbellSpin) {
  const Vec3 Pi = J1 * Vec3(0, 0, 9);
  const auto s = solve_discrete_attitude(2e-4 * Pi, J1);
  EXPECT_LE(s.iterations, 4);
  EXPECT_GE(s.iterations, 1);
}

// No F near the identity exists when ‖g‖ exceeds what G can reach: a clear error.
TEST(DiscreteAttitude, TooLargeAStepIsAnError) {
  const Vec3 g = 10.0 * J1 * Vec3(0, 0, 9);  // h ≈ 10 at |Ω| = 9
  try {
    solve_discrete_attitude(g, J1);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no solution near the identity"), std::string::npos);
  }
}

// The solver has two kernels, for J = diag(j) (scalars) and for any symmetric J; (128) is
// equivariant, F(Q J Qᵀ, Q g) = Q F(J, g) Qᵀ, so solving the same body in a rotated frame runs
// the other kernel and must give the rotated solution.
TEST(DiscreteAttitude, DiagonalAndGeneralKernelsAgree) {
  const Mat3 J = Vec3(0.0004, 0.0238, 0.0241).asDiagonal();
  const Mat3 Q = exp_so3(Vec3(0.3, -1.1, 0.7));
  for (double scale : {1.0, 30.0, 300.0}) {
    const Vec3 g = 2e-4 * scale * J * Vec3(0.3, -0.2, 9.0);
    const auto diagonal = solve_discrete_attitude(g, J);
    const auto general = solve_discrete_attitude(Q * g, Mat3(Q * J * Q.transpose()));
    EXPECT_LT((general.f - Q * diagonal.f).norm(), 1e-13 * diagonal.f.norm()) << scale;
    EXPECT_LT((general.F - Q * diagonal.F * Q.transpose()).norm(), 1e-13) << scale;
    // κ∞ in (4.2) depends on the frame, so the early stop may come one iteration apart.
    EXPECT_LE(std::abs(general.iterations - diagonal.iterations), 1) << scale;
  }
}
