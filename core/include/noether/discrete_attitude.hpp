#pragma once
// The implicit attitude update of the Lie group variational integrator (docs/equations.md §4, Lee, Leok & McClamroch 2007
// eqs. (128)–(130)): given g = h (Π_k + (h/2) M_k), find F_k ∈ SO(3) with
//     S(g) = F_k Jd − Jd F_kᵀ,
// by writing F = exp(S(f)) and solving G(f) = g with Newton's method.
// Shared by every LGVI form (inertial and relative frame).
#include <noether/lie.hpp>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// G(f) = (sin‖f‖/‖f‖) J f + ((1 − cos‖f‖)/‖f‖²) f × J f      (128)
Vec3 discrete_attitude_residual_map(const Vec3& f, const Mat3& J);
// ∇G(f), the Jacobian of G                                  (130)
Mat3 discrete_attitude_jacobian(const Vec3& f, const Mat3& J);

struct DiscreteAttitudeOptions {
  double tolerance = 1e-15;  // stop when ‖Δf‖ ≤ tolerance ‖f‖ (or at the round-off floor)
  int max_iterations = 30;
};

struct DiscreteAttitude {
  Mat3 F;          // F_k = exp(S(f))
  Vec3 f;          // rotation vector of F_k, ‖f‖ < π
  int iterations;  // Newton iterations taken
};

// Throws noether::Error when Newton does not converge or ‖f‖ reaches π (the step is too large
// for the spin: no F near the identity solves (128)). The caller adds body and step.
DiscreteAttitude solve_discrete_attitude(const Vec3& g, const Mat3& J,
                                         const DiscreteAttitudeOptions& options = {});
// The same with J⁻¹ given (an integrator keeps it per body: no inversion per step).
DiscreteAttitude solve_discrete_attitude(const Vec3& g, const Mat3& J, const Mat3& J_inverse,
                                         const DiscreteAttitudeOptions& options = {});

}  // namespace noether

#pragma GCC visibility pop
