#pragma once
// The continuous equations of motion as first-order systems y' = F(t, y) for general-purpose
// ODE solvers (docs/equations.md §3; Lee, Leok & McClamroch 2007 §2–3, the left face of the cube of Fig. 7). Four forms:
//
//   inertial, Hamiltonian (29)–(32):  ẋ = γ/m, γ̇ = −∂U/∂x, Ṙ = R S(Ω), Π̇ = Π × Ω + M, Ω = J⁻¹Π
//   inertial, Lagrangian (25)–(28):   ẋ = v, m v̇ = −∂U/∂x, Ṙ = R S(Ω), J Ω̇ + Ω × J Ω = M
//   relative, Hamiltonian (two rigid bodies; X = R2ᵀ(x1 − x2), Γ = m R2ᵀ(v1 − v2),
//     R = R2ᵀR1, Π = R Π1, ω = J_R⁻¹ Π with J_R = R J1 Rᵀ):
//     Ẋ = Γ/m + X × Ω2,  Γ̇ = Γ × Ω2 − ∂U/∂X,  Ṙ = S(ω) R − S(Ω2) R,
//     Π̇ = Π × Ω2 + M,  Π̇2 = Π2 × Ω2 + M2,  and body 2: ẋ2 = γ2/m2, γ̇2 = R2 ∂U/∂X, Ṙ2 = R2 S(Ω2)
//   relative, Lagrangian (55)–(62): the same with V = Γ/m, ω and Ω2 as variables:
//     V̇ = V × Ω2 − (1/m) ∂U/∂X,  ω̇ = J_R⁻¹(M − ω × J_R ω) − Ω2 × ω,  J2 Ω̇2 + Ω2 × J2 Ω2 = M2
// with M = R M1 (moment on body 1 seen from body 2) and M2 = X × ∂U/∂X − M the moment on body 2
// (our sign of M is the negative of Lee et al.'s in the relative equations). Attitudes are
// carried as nine plain numbers, as Lee et al.'s Runge–Kutta does: a general-purpose solver lets
// them drift off SO(3), and that drift is part of what noether reports.
#include <noether/forces.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// An interface only: the forms live in continuous_equations.cpp. Each holds the potential
// with a workspace of its own (PotentialEvaluator), so it is one thread's.
class ContinuousEquations {
 public:
  virtual ~ContinuousEquations();
  virtual std::size_t size() const = 0;
  // Inertial State ↔ y of this form.
  virtual void pack(const State& state, double* y) const = 0;
  virtual void unpack(const double* y, double t, State& state) const = 0;
  // dydt = F(t, y): one potential evaluation, counted.
  virtual void rhs(double t, const double* y, double* dydt) = 0;
  // Offsets in y of every 3×3 attitude (column-major), for optional re-orthonormalisation.
  virtual std::vector<std::size_t> rotation_offsets() const = 0;
  // The forces at an inertial state (for output): not counted as an evaluation.
  virtual void forces(const State& state, Forces& forces) = 0;
  // Potential evaluations made by rhs() so far.
  virtual std::int64_t evaluations() const = 0;
  virtual const System& system() const = 0;
  virtual PotentialEvaluator& evaluator() = 0;
};

// frame: "inertial" or "relative" (two rigid bodies only); form: "hamiltonian" or
// "lagrangian". Throws SceneError for anything else, or a relative frame the scene cannot have.
std::unique_ptr<ContinuousEquations> make_continuous_equations(
    const System& system, std::shared_ptr<const Potential> potential,
    const std::string& frame = "inertial", const std::string& form = "hamiltonian");

}  // namespace noether

#pragma GCC visibility pop
