#pragma once
// The force Jacobian K = ∂(f, M)/∂(x, θ) of a potential at a state (docs/equations.md §20): the
// model's own (Potential::force_jacobian) when it has one, else central differences of its
// forces — labelled, so that a caller can say which it used.
#include <noether/potential.hpp>

#include <functional>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct ForceJacobian {
  Eigen::MatrixXd K;      // (3n + 3m)², the ordering of Potential::force_jacobian
  bool analytic = false;  // false: central differences (20.4)
};

// K at `state`, evaluating with `workspace` (made by `potential`).
ForceJacobian force_jacobian(const Potential& potential, const State& state, Workspace& workspace);

// Central differences of a vector function g of the state along the first steps.size() coordinates
// of z = (x, θ, γ, Π) (21.1; θ a right perturbation R exp(S(θ))): column c is
// [g(z + h_c e_c) − g(z − h_c e_c)] / 2h_c with h_c = steps(c); 2 steps.size() evaluations of g.
Eigen::MatrixXd differenced_state_jacobian(const State& state, const Eigen::VectorXd& steps,
                                          const std::function<Eigen::VectorXd(const State&)>& g);

// K by central differences of the forces and moments (20.4): positions stepped by 1e-5 L (L the
// smallest distance between two centres, or the largest |x| for one body), attitudes by 1e-5
// rad in the body frame; 2 (3n + 3m) evaluations. Relative error ~1e-10 for smooth models.
Eigen::MatrixXd differenced_force_jacobian(const Potential& potential, const State& state, Workspace& workspace);

}  // namespace noether

#pragma GCC visibility pop
