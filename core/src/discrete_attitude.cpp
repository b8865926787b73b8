#include <noether/discrete_attitude.hpp>
#include <noether/error.hpp>

#include <cmath>
#include <numbers>
#include <sstream>

namespace noether {

namespace {

// The derivative coefficients of (130) at x = ‖f‖:
//   c1 = (x cos x − sin x)/x³,   c3 = (x sin x − 2(1 − cos x))/x⁴,
// by their Taylor series for small x, where the closed forms cancel catastrophically.
struct JacobianCoefficients {
  double c1, c3;
};
JacobianCoefficients jacobian_coefficients(double x) {
  if (x < 1e-2) {
    const double x2 = x * x;
    return {-1.0 / 3.0 + x2 / 30.0 - x2 * x2 / 840.0, -1.0 / 12.0 + x2 / 180.0 - x2 * x2 / 6720.0};
  }
  const double s = std::sin(x), c = std::cos(x), h = std::sin(0.5 * x);
  return {(x * c - s) / (x * x * x), (x * s - 4.0 * h * h) / (x * x * x * x)};
}

}  // namespace

Vec3 discrete_attitude_residual_map(const Vec3& f, const Mat3& J) {
  const auto [a, b] = rodrigues_coefficients(f.norm());
  const Vec3 Jf = J * f;
  return a * Jf + b * f.cross(Jf);  // (128)
}

Mat3 discrete_attitude_jacobian(const Vec3& f, const Mat3& J) {
  const double x = f.norm();
  const auto [a, b] = rodrigues_coefficients(x);
  const auto [c1, c3] = jacobian_coefficients(x);
  const Vec3 Jf = J * f;
  // (130)
  return c1 * Jf * f.transpose() + a * J + c3 * f.cross(Jf) * f.transpose() +
         b * (-hat(Jf) + hat(f) * J);
}

DiscreteAttitude solve_discrete_attitude(const Vec3& g, const Mat3& J,
                                         const DiscreteAttitudeOptions& options) {
  Vec3 f = J.ldlt().solve(g);  // first guess: G(f) ≈ J f for small f
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 1; it <= options.max_iterations; ++it) {
    const Vec3 residual = discrete_attitude_residual_map(f, J) - g;
    const Vec3 delta = discrete_attitude_jacobian(f, J).partialPivLu().solve(residual);
    f -= delta;
    const double step = delta.norm(), size = f.norm();
    if (!std::isfinite(size) || size >= std::numbers::pi) break;
    // Converged, or stalled at the round-off floor after quadratic convergence.
    if (step <= options.tolerance * size || (step <= 1e-10 * size && step >= 0.5 * previous) ||
        size == 0.0)
      return {exp_so3(f), f, it};
    previous = step;
  }
  std::ostringstream msg;
  msg << "the discrete attitude equation (128) has no solution near the identity: Newton "
      << "did not converge (‖g‖ = " << g.norm() << ", last ‖f‖ = " << f.norm()
      << ", needs ‖f‖ < π)";
  throw Error(msg.str());
}

}  // namespace noether
