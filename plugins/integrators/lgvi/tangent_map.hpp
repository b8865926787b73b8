#pragma once
// The tangent map of the inertial Hamiltonian LGVI step (93)–(97): the exact derivative of the
// discrete map, differentiated through the implicit attitude equation (93) rather than around it
// (docs/equations.md §21, eqs. 21.3–21.8). Compositions are products of these maps.
#include <noether/integrator.hpp>
#include <noether/lie.hpp>
#include <noether/parameter_derivatives.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace lgvi {

// V_{k+1} = (∂z_{k+1}/∂z_k) V_k for the step z_k → z_{k+1} of size h, given what the step
// computed: F_k of every rigid body, w_k = Π_k + (h/2) M_k (so that Π_{k+1} = F_kᵀ w_k +
// (h/2) M_{k+1}, (97)), and K_k, K_{k+1} the force Jacobians (§20) at both ends; V has 6n + 6m
// rows in the order (21.1).
//
// With `parameters`, V's last P columns are ∂z/∂p for parameters of the dynamics, and the
// step's direct dependence on them is added (22.3)–(22.5): G_k, G_next = ∂(f, M)/∂p at both
// ends, the masses' and inertias' derivatives, and the step's displacement x_{k+1} − x_k.
struct ParameterStep {
  const noether::ParameterDerivatives* parameters = nullptr;
  const Eigen::MatrixXd* G_k = nullptr;
  const Eigen::MatrixXd* G_next = nullptr;
  const Eigen::Matrix3Xd* displacement = nullptr;
};
Eigen::MatrixXd advance_tangent(const noether::System& system, double h, const std::vector<noether::Mat3>& F,
                                const Eigen::Matrix3Xd& w, const Eigen::MatrixXd& K_k, const Eigen::MatrixXd& K_next,
                                const Eigen::MatrixXd& V, const ParameterStep& parameters = {});

// What the inertial forms (Hamiltonian and Lagrangian: the same map z_k → z_{k+1}) hold to
// carry the tangent: the force Jacobian (§20) and, for parameters of the dynamics, ∂(f, M)/∂p
// (22.1) at z_k and z_{k+1}; their evaluations counted as the flow's work.
class TangentCarrier {
 public:
  bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) {
    parameter_forces_.emplace(std::move(parameters));
    return true;
  }
  // At z_k (a start): K_k, G_k when the state carries a tangent.
  void start(const noether::State& s, noether::PotentialEvaluator& evaluate, noether::WorkCounters& work);
  // At z_{k+1}, after the step's evaluation there.
  void at_next(const noether::State& s, noether::PotentialEvaluator& evaluate, noether::WorkCounters& work);
  // V ← (∂z_{k+1}/∂z_k) V (advance_tangent) with the step's F_k, w_k and x_{k+1} − x_k; then
  // z_{k+1} becomes z_k.
  void advance(const noether::System& system, double h, const std::vector<noether::Mat3>& F, const Eigen::Matrix3Xd& w,
               const Eigen::Matrix3Xd& displacement, Eigen::MatrixXd& V);
  // The forced kicks' own dependence on the parameters (docs/equations.md 33.9): G^F =
  // ∂(f^F, M^F)/∂p at `s` (whose tangent is not read), kept (nothing when the parameters carry
  // no forces); then, at a kick
  // of duration τ, V's parameter columns' momentum rows += τ G^F.
  void forcing_parameters_at(const noether::State& s);
  void add_forcing_parameters(double tau, Eigen::MatrixXd& V) const;

 private:
  bool carries_parameters(const noether::State& s) const { return s.tangent.size() > 0 && parameter_forces_; }
  void evaluate_at(const noether::State& s, noether::PotentialEvaluator& evaluate, noether::WorkCounters& work,
                   Eigen::MatrixXd& K, Eigen::MatrixXd& G);
  std::optional<noether::ParameterForces> parameter_forces_;
  Eigen::MatrixXd K_, K_next_, G_, G_next_, G_forcing_;
};

}  // namespace lgvi
