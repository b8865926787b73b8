#pragma once
// The tangent map of the inertial Hamiltonian LGVI step (93)–(97): the exact derivative of the
// discrete map, differentiated through the implicit attitude equation (93) rather than around it
// (docs/equations.md §21, eqs. 21.3–21.8). Compositions are products of these maps.
#include <noether/lie.hpp>
#include <noether/parameter_derivatives.hpp>
#include <noether/system.hpp>

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

}  // namespace lgvi
