#pragma once
// Diagnostics: the quantities the continuous flow conserves (docs/equations.md §3) and the distance of
// every attitude from SO(3).
#include <noether/state.hpp>
#include <noether/system.hpp>

namespace noether {

struct Diagnostics {
  double kinetic_translational = 0.0;  // Σ ‖γ_i‖²/2m_i
  double kinetic_rotational = 0.0;     // Σ ½ Π_kᵀ J_k⁻¹ Π_k
  double potential = 0.0;              // U
  double energy = 0.0;                 // E = T + U
  Vec3 linear_momentum = Vec3::Zero();   // Σ γ_i
  Vec3 angular_momentum = Vec3::Zero();  // Σ (x_i × γ_i + R_k Π_k), about the origin
  double orthogonality_error = 0.0;      // max_k ‖I − R_kᵀR_k‖_F
};

// U is passed in (the integrator has just computed it) so diagnostics cost no extra
// potential evaluation.
Diagnostics diagnose(const System& system, const State& state, double U);

}  // namespace noether
