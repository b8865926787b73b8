#pragma once
// Parameters of the dynamics (docs/derivatives.md, "Sensitivities to parameters of the
// dynamics"; docs/equations.md §22): what a tangent map needs, beside the force Jacobian K, to
// carry columns ∂z/∂p of a tangent for parameters p that the equations of motion depend on —
// a body's mass or density, G, a shape's semi-axes. For each p: how the bodies' masses and
// inertias move with it, and the models at p ± d, p ± 2d, whose forces at a fixed configuration
// give ∂(f, M)/∂p by a fourth-order central difference (22.1); with forces beyond the potential,
// the forces made at the same points (33.9).
#include <noether/force_model.hpp>
#include <noether/forces.hpp>
#include <noether/lie.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <memory>
#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct DynamicsParameter {
  std::string name;           // the scene key it moves, as `--set` takes it: "bodies.beta.mass"
  Eigen::VectorXd mass;       // ∂m_i/∂p, one per body
  std::vector<Mat3> inertia;  // ∂J_k/∂p, one per rigid body (body frame)
  // ∂(f, M)/∂p = Σ_s weights[s] (f, M)(models[s]): the models made with p moved by a stencil's
  // offsets (everything else as the run's), and its weights (22.1).
  // Empty for a parameter of the forces alone (a tide's k2): the potential does not move.
  std::vector<std::shared_ptr<const Potential>> models;
  std::vector<double> weights;
  // With forces beyond the potential (docs/equations.md §33): the scene's forces made with p
  // moved by the same offsets, and the systems (masses, inertias) they were made for;
  // ∂(f^F, M^F)/∂p = Σ_s weights[s] (f^F, M^F)(forcings[s]) at a fixed z (33.9). Empty without.
  std::vector<std::shared_ptr<const Forcing>> forcings;
  std::vector<System> systems;
};

// The parameters a run carries sensitivities to, in the order of the tangent's last columns.
// Immutable once made: the threads that carry it share it.
struct ParameterDerivatives {
  std::vector<DynamicsParameter> parameters;
  std::size_t size() const { return parameters.size(); }
};

// One thread's evaluations of G = ∂(f_1, …, f_n, M_1, …, M_m)/∂(p_1, …, p_P) at a state, the
// rows ordered as Potential::force_jacobian's: the stencil of (22.1) at the state's positions and
// attitudes.
class ParameterForces {
 public:
  explicit ParameterForces(std::shared_ptr<const ParameterDerivatives> derivatives);
  // G at `state`, (3n + 3m) × P: evaluations_per_call() evaluations of the potential, one of
  // each parameter's models.
  const Eigen::MatrixXd& operator()(const State& state);
  // G^F = ∂(f^F, M^F)/∂p at `state` (33.9), the rows as G's: the forces beyond the potential
  // made at each parameter's stencil; zero when the parameters carry none (has_forcing()).
  const Eigen::MatrixXd& forcing(const State& state);
  bool has_forcing() const { return has_forcing_; }
  // G + G^F: what the continuous variational equations add (22.2), (33.9).
  const Eigen::MatrixXd& with_forcing(const State& state);
  const ParameterDerivatives& derivatives() const { return *derivatives_; }
  std::size_t size() const { return derivatives_->size(); }
  std::int64_t evaluations_per_call() const { return evaluations_per_call_; }
  // Whether a state's tangent can carry these parameters: none carried, or at least P columns
  // (the parameters' are the last P).
  bool fits(const Eigen::MatrixXd& tangent) const {
    return tangent.size() == 0 || tangent.cols() >= static_cast<Eigen::Index>(size());
  }

 private:
  std::shared_ptr<const ParameterDerivatives> derivatives_;
  std::vector<std::vector<PotentialEvaluator>> models_;  // per parameter, its stencil's models
  std::vector<std::vector<ForcingEvaluator>> forcings_;  // per parameter, its stencil's forces
  bool has_forcing_ = false;
  Forces forces_;
  Eigen::MatrixXd G_, G_forcing_, G_sum_;
  std::int64_t evaluations_per_call_ = 0;
};

// The parameters' inhomogeneous terms of the variational equations (22.2), added to dV's columns
// (one per parameter, rows as State::tangent_coordinates):
//     δẋ_i += −(∂m_i/∂p / m_i²) γ_i,      δθ̇_k += δΩ_k,      δγ̇_i += ∂f_i/∂p,
//     δΠ̇_k += Π_k × δΩ_k + ∂M_k/∂p,      δΩ_k = −J_k⁻¹ (∂J_k/∂p) Ω_k,
// with G = ∂(f, M)/∂p at the state (ParameterForces).
void add_parameter_rhs(const System& system, const State& state, const ParameterDerivatives& derivatives,
                       const Eigen::MatrixXd& G, Eigen::Ref<Eigen::MatrixXd> dV);

}  // namespace noether

#pragma GCC visibility pop
