#include <noether/discrete_attitude.hpp>
#include <noether/error.hpp>

#include <cmath>
#include <numbers>
#include <sstream>

namespace noether {

namespace {

// Everything (128) and (130) need at one iterate x = ‖f‖, from one sine and one cosine:
//   a = sin x / x,  b = (1 − cos x)/x²,  c1 = (x cos x − sin x)/x³,  c3 = (x sin x − 2(1 − cos x))/x⁴,
// by Taylor series below x = 1e-2 (where c1 and c3 cancel catastrophically; the first omitted
// terms are below 1e-19 relative there).
struct Coefficients {
  double a, b, c1, c3;
};

// From x² = ‖f‖²: the small rotations of a step need no square root, sine or cosine.
inline Coefficients coefficients_of_square(double x2) {
  if (x2 < 1e-4) {  // x < 1e-2: Estrin's scheme (short dependency chains: Newton is latency-bound)
    const double x4 = x2 * x2;
    return {(1.0 - x2 * (1.0 / 6.0)) + x4 * (1.0 / 120.0 - x2 * (1.0 / 5040.0)),
            (0.5 - x2 * (1.0 / 24.0)) + x4 * (1.0 / 720.0 - x2 * (1.0 / 40320.0)),
            (-1.0 / 3.0 + x2 * (1.0 / 30.0)) + x4 * (-1.0 / 840.0 + x2 * (1.0 / 45360.0)),
            (-1.0 / 12.0 + x2 * (1.0 / 180.0)) + x4 * (-1.0 / 6720.0 + x2 * (1.0 / 453600.0))};
  }
  const double x = std::sqrt(x2);
  const double s = std::sin(x), c = std::cos(x);
  const double one_minus_cos = c > 0.0 ? s * s / (1.0 + c) : 1.0 - c;  // no cancellation either side
  const double inv_x = 1.0 / x, inv_x2 = inv_x * inv_x;
  return {s * inv_x, one_minus_cos * inv_x2, (x * c - s) * inv_x2 * inv_x, (x * s - 2.0 * one_minus_cos) * inv_x2 * inv_x2};
}

// G(f) (128) and ∇G(f) (130) from the same coefficients.
Vec3 residual_map(const Vec3& f, const Vec3& Jf, const Coefficients& k) { return k.a * Jf + k.b * f.cross(Jf); }

Mat3 jacobian(const Vec3& f, const Vec3& Jf, const Mat3& J, const Coefficients& k) {
  return (k.c1 * Jf + k.c3 * f.cross(Jf)) * f.transpose() + k.a * J + k.b * (hat(f) * J - hat(Jf));
}

// A⁻¹ of a 3×3 A by its adjugate (the cross products of its rows), to solve A x = r at the
// cost of a matrix–vector product: A⁻¹ = [r1×r2, r2×r0, r0×r1] / det A (columns). No pivoting is
// needed where (130) is used: ∇G is a small perturbation of J near the identity.
struct Inverse3 {
  Mat3 inverse;
  explicit Inverse3(const Mat3& A) {
    const Vec3 r0 = A.row(0), r1 = A.row(1), r2 = A.row(2);
    const Vec3 c0 = r1.cross(r2);
    inverse.col(0) = c0;
    inverse.col(1) = r2.cross(r0);
    inverse.col(2) = r0.cross(r1);
    inverse *= 1.0 / r0.dot(c0);
  }
};

// F = exp(S(f)) = I + a S(f) + b S(f)² = (1 − b‖f‖²) I + a S(f) + b f fᵀ (Rodrigues): exp_so3
// in this file's form, because calling exp_so3 (another translation unit, no sqrt-free path)
// cost 30–40 ns per dumbbell step, 12 % of it (measured with BM_LgviDumbbellStep).
Mat3 rotation(const Vec3& f) {
  const double x2 = f.squaredNorm();
  const Coefficients k = coefficients_of_square(x2);
  Mat3 F = k.b * f * f.transpose() + k.a * hat(f);
  F.diagonal().array() += 1.0 - k.b * x2;
  return F;
}

// One Newton step δ = ∇G(f)⁻¹ (G(f) − g) of (128) with (130), refreshing ∇G⁻¹ or keeping the
// last one (simplified Newton). Two kernels: any symmetric J, and J = diag(j) — the inertial
// forms' case, written in scalars (a third of the arithmetic: S(f) J − S(J f) has the entries
// f_k (j_i − j_j) off the diagonal and zeros on it; and no packing of 3-vectors into SSE pairs,
// whose store-forwarding stalls cost more than the arithmetic).
class GeneralKernel {
 public:
  GeneralKernel(const Vec3& g, const Mat3& J) : g_(g), J_(J) {}
  Vec3 step(const Vec3& f, bool refresh) {
    const Coefficients k = coefficients_of_square(f.squaredNorm());
    const Vec3 Jf = J_ * f;
    if (refresh) jacobian_inverse_ = Inverse3(jacobian(f, Jf, J_, k)).inverse;
    return jacobian_inverse_ * (residual_map(f, Jf, k) - g_);
  }

 private:
  Vec3 g_;
  Mat3 J_, jacobian_inverse_;
};

class DiagonalKernel {
 public:
  DiagonalKernel(const Vec3& g, const Vec3& j) : g0_(g.x()), g1_(g.y()), g2_(g.z()), j0_(j.x()), j1_(j.y()), j2_(j.z()) {}
  Vec3 step(const Vec3& fv, bool refresh) {
    const double f0 = fv.x(), f1 = fv.y(), f2 = fv.z();
    const Coefficients k = coefficients_of_square(f0 * f0 + f1 * f1 + f2 * f2);
    const double q0 = j0_ * f0, q1 = j1_ * f1, q2 = j2_ * f2;                    // J f
    const double w0 = f1 * q2 - f2 * q1, w1 = f2 * q0 - f0 * q2, w2 = f0 * q1 - f1 * q0;  // f × J f
    const double r0 = k.a * q0 + k.b * w0 - g0_, r1 = k.a * q1 + k.b * w1 - g1_,
                 r2 = k.a * q2 + k.b * w2 - g2_;                                  // G(f) − g (128)
    if (refresh) {  // ∇G (130) and its adjugate
      const double u0 = k.c1 * q0 + k.c3 * w0, u1 = k.c1 * q1 + k.c3 * w1, u2 = k.c1 * q2 + k.c3 * w2;
      const double b = k.b;
      const double m00 = u0 * f0 + k.a * j0_, m01 = u0 * f1 + b * f2 * (j2_ - j1_), m02 = u0 * f2 + b * f1 * (j2_ - j1_);
      const double m10 = u1 * f0 + b * f2 * (j0_ - j2_), m11 = u1 * f1 + k.a * j1_, m12 = u1 * f2 + b * f0 * (j0_ - j2_);
      const double m20 = u2 * f0 + b * f1 * (j1_ - j0_), m21 = u2 * f1 + b * f0 * (j1_ - j0_), m22 = u2 * f2 + k.a * j2_;
      n_[0] = m11 * m22 - m12 * m21, n_[1] = m02 * m21 - m01 * m22, n_[2] = m01 * m12 - m02 * m11;
      n_[3] = m12 * m20 - m10 * m22, n_[4] = m00 * m22 - m02 * m20, n_[5] = m02 * m10 - m00 * m12;
      n_[6] = m10 * m21 - m11 * m20, n_[7] = m01 * m20 - m00 * m21, n_[8] = m00 * m11 - m01 * m10;
      inv_det_ = 1.0 / (m00 * n_[0] + m01 * n_[3] + m02 * n_[6]);  // in parallel with N r below
    }
    return inv_det_ * Vec3(n_[0] * r0 + n_[1] * r1 + n_[2] * r2, n_[3] * r0 + n_[4] * r1 + n_[5] * r2,
                           n_[6] * r0 + n_[7] * r1 + n_[8] * r2);
  }

 private:
  double g0_, g1_, g2_, j0_, j1_, j2_;
  double n_[9] = {};     // the adjugate of ∇G, row-major
  double inv_det_ = 0.0;  // 1 / det ∇G
};

// Newton from f₀ (4.1) until ‖δ‖ ≤ tol ‖f‖, the round-off floor, or the bound (4.2); once a
// step is below 1e-4 ‖f‖ the Jacobian is kept (then each iteration still gains a factor
// ~‖∇²G‖‖δ‖/σ(J) ≪ 1e-4). Norms are compared squared (no square root on the way).
template <class Kernel>
DiscreteAttitude newton(Kernel kernel, Vec3 f, const Vec3& g, double kappa, const DiscreteAttitudeOptions& options) {
  double previous = std::numeric_limits<double>::infinity();  // ‖δ‖² of the last iterate
  const double tolerance2 = options.tolerance * options.tolerance;
  const double bound2 = 36.0 * kappa * kappa;  // (6 κ∞)² of (4.2), compared with squares
  bool frozen = false;
  for (int it = 1; it <= options.max_iterations; ++it) {
    const Vec3 delta = kernel.step(f, !frozen);
    f -= delta;
    const double step2 = delta.squaredNorm(), size2 = f.squaredNorm();
    if (!std::isfinite(size2) || size2 >= std::numbers::pi * std::numbers::pi) break;
    if (step2 <= tolerance2 * size2 || (step2 <= 1e-20 * size2 && step2 >= 0.25 * previous) || size2 == 0.0 ||
        (!frozen && size2 <= 0.01 && bound2 * step2 * step2 <= tolerance2 * size2))  // (4.2)
      return {rotation(f), f, it};
    frozen = step2 <= 1e-8 * size2;
    previous = step2;
  }
  std::ostringstream msg;
  msg << "the discrete attitude equation (128) has no solution near the identity: Newton "
      << "did not converge (‖g‖ = " << g.norm() << ", last ‖f‖ = " << f.norm()
      << ", needs ‖f‖ < π)";
  throw Error(msg.str());
}

}  // namespace

Vec3 discrete_attitude_residual_map(const Vec3& f, const Mat3& J) {
  return residual_map(f, J * f, coefficients_of_square(f.squaredNorm()));  // (128)
}

Mat3 discrete_attitude_jacobian(const Vec3& f, const Mat3& J) {
  return jacobian(f, J * f, J, coefficients_of_square(f.squaredNorm()));  // (130)
}

DiscreteAttitude solve_discrete_attitude(const Vec3& g, const Mat3& J, const DiscreteAttitudeOptions& options) {
  return solve_discrete_attitude(g, J, Mat3(J.inverse()), options);
}

DiscreteAttitude solve_discrete_attitude(const Vec3& g, const Mat3& J, const Mat3& J_inverse,
                                         const DiscreteAttitudeOptions& options) {
  // Start (4.1): the second-order solution of G(f) = J f + ½ f × J f + O(‖f‖³) = g, f₁ = J⁻¹g,
  // then f₀ = J⁻¹(g − ½ f₁ × g), with an O(‖f‖³) error. Everything below depends on g and J
  // only (a restarted run repeats it bit for bit).
  const Vec3 f1 = J_inverse * g;
  const Vec3 f0 = J_inverse * (g - 0.5 * f1.cross(g));
  const double kappa = J.cwiseAbs().rowwise().sum().maxCoeff() * J_inverse.cwiseAbs().rowwise().sum().maxCoeff();
  const bool diagonal = J(0, 1) == 0.0 && J(0, 2) == 0.0 && J(1, 2) == 0.0 && J(1, 0) == 0.0 && J(2, 0) == 0.0 &&
                        J(2, 1) == 0.0;
  return diagonal ? newton(DiagonalKernel(g, J.diagonal()), f0, g, kappa, options)
                  : newton(GeneralKernel(g, J), f0, g, kappa, options);
}

}  // namespace noether
