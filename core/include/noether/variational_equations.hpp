#pragma once
// The variational equations of the continuous inertial Hamiltonian equations (29)–(32) in the
// coordinates z of (21.1) (docs/equations.md eq. 21.10): V̇ = A(z) V, with K the force Jacobian
// (§20) at the state,
//     δẋ = δγ/m,   δθ̇ = J⁻¹δΠ − Ω × δθ,   δγ̇ = K_x (δx, δθ),
//     δΠ̇ = δΠ × Ω + Π × J⁻¹δΠ + K_θ (δx, δθ).
// What a general-purpose ODE solver integrates beside the state to carry the STM of the flow.
#include <noether/state.hpp>
#include <noether/system.hpp>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// dV = A(state) V; V and dV are (6n + 6m) × c.
void variational_rhs(const System& system, const State& state, const Eigen::MatrixXd& K,
                     Eigen::Ref<const Eigen::MatrixXd> V, Eigen::Ref<Eigen::MatrixXd> dV);

// out += τ B K^F V: the forces beyond the potential, K^F = ∂(f^F, M^F)/∂z ((3n + 3m) × (6n + 6m),
// ForcingEvaluator::jacobian, 33.5), placed in the rows of γ and Π — in the variational
// equations with τ = 1 (33.8), in the forced LGVI's kicks with τ = ±h/2 (33.6)–(33.7). `out` may
// be V itself.
void add_forcing_tangent(const System& system, const Eigen::MatrixXd& KF, double tau,
                         Eigen::Ref<const Eigen::MatrixXd> V, Eigen::Ref<Eigen::MatrixXd> out);

}  // namespace noether

#pragma GCC visibility pop
