#pragma once
// The continuous equations of motion, inertial frame, Hamiltonian form (MATH.md §3; seed 000
// eqs. (29)–(32)), as a first-order system y' = F(t, y) for general-purpose ODE solvers:
//     ẋ_i = γ_i / m_i        γ̇_i = −∂U/∂x_i
//     Ṙ_k = R_k S(Ω_k)       Π̇_k = Π_k × Ω_k + M_k,    Ω_k = J_k⁻¹ Π_k
// R is carried as nine plain numbers, as the seed's Runge–Kutta does: a general-purpose solver
// lets it drift off SO(3), and that drift is part of what noether reports.
#include <noether/forces.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace noether {

class InertialEquations {
 public:
  InertialEquations(const System& system, std::shared_ptr<const Potential> potential);

  // Length of y: 6 per body, 12 more per rigid body.
  std::size_t size() const { return size_; }
  // y = [x (3n) | γ (3n) | R (9 per rigid body, column-major) | Π (3 per rigid body)].
  void pack(const State& state, double* y) const;
  void unpack(const double* y, double t, State& state) const;
  // dydt = F(t, y): one potential evaluation.
  void rhs(double t, const double* y, double* dydt);
  // Forces of the last rhs() call.
  const Forces& forces() const { return forces_; }
  std::int64_t evaluations() const { return evaluations_; }
  const System& system() const { return system_; }
  const Potential& potential() const { return *potential_; }

 private:
  System system_;
  std::shared_ptr<const Potential> potential_;
  std::size_t size_;
  State scratch_;
  Forces forces_;
  std::int64_t evaluations_ = 0;
};

}  // namespace noether
