#pragma once
// A chart of the full body problem's phase space (SE(3)ⁿ × momenta) about a base state, for
// linearisations and shooting (docs/equations.md §18): a perturbation
//
//   δ = (δx_1..δx_n, δv_1..δv_n, η_1..η_r, δΠ_1..δΠ_r) ∈ R^{6n+6r}
//
// stands for x_i = x_i⁰ + s_x δx_i, v_i = γ_i/m_i = v_i⁰ + s_v δv_i, R_k = R_k⁰ exp(S(η_k)),
// Π_k = Π_k⁰ + s_Π,k δΠ_k, with scales s chosen so that every component is of order one. The
// chart is a diffeomorphism near δ = 0 (‖η‖ < π): local(retract(δ)) = δ.
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <Eigen/Dense>

#include <vector>

namespace noether {

class PhaseChart {
 public:
  // length: s_x; rate: s_v = rate × length and s_Π,k = rate × tr(J_k)/2.
  PhaseChart(const System& system, State base, double length, double rate);

  Eigen::Index dimension() const { return d_; }
  const State& base() const { return base_; }
  const System& system() const { return *system_; }
  const Eigen::VectorXd& scale() const { return scale_; }
  double length() const { return length_; }
  double rate() const { return rate_; }

  State retract(const Eigen::VectorXd& delta) const;
  Eigen::VectorXd local(const State& state) const;
  // Their derivatives in the tangent coordinates z = (δx, θ, δγ, δΠ) of State::tangent
  // (docs/equations.md eq. 21.1; θ a body-frame turn R exp(S(θ))): ∂z/∂δ at retract(δ), a
  // (6n + 6r) × d matrix (an attitude's block is the right Jacobian J_r(η) of SO(3)), and ∂δ/∂z at
  // `state` for local (its block J_r⁻¹(log(R⁰ᵀ R))).
  Eigen::MatrixXd retract_derivative(const Eigen::VectorXd& delta) const;
  Eigen::MatrixXd local_derivative(const State& state) const;

  // Offsets of the blocks in δ.
  Eigen::Index x(std::size_t body) const { return 3 * static_cast<Eigen::Index>(body); }
  Eigen::Index v(std::size_t body) const { return 3 * (n_ + static_cast<Eigen::Index>(body)); }
  Eigen::Index eta(std::size_t rigid) const { return 6 * n_ + 3 * static_cast<Eigen::Index>(rigid); }
  Eigen::Index Pi(std::size_t rigid) const { return 6 * n_ + 3 * (r_ + static_cast<Eigen::Index>(rigid)); }

  // Orthonormal basis (columns) of the perturbations that leave the barycentre's position and
  // velocity alone: Σ m_i δx_i = 0, Σ m_i δv_i = 0. The barycentre moves uniformly and on its
  // own (Σ f_i = 0), so this subspace is invariant under every linearised flow or map.
  Eigen::MatrixXd barycentre_free_basis() const;

  // The infinitesimal rotation of the base state about the axis e through its barycentre c:
  // δx_i = e × (x_i − c), δv_i = e × (v_i − v_c) − frame × (e × (x_i − c)) + e × (frame × (x_i − c)),
  // η_k = R_kᵀ e, δΠ_k = 0 (body-frame momenta do not change). `frame` is the angular velocity of
  // the frame the velocities are measured in (zero: inertial).
  Eigen::VectorXd rotation_generator(const Vec3& e, const Vec3& frame = Vec3::Zero()) const;

 private:
  const System* system_;
  State base_;
  double length_, rate_;
  Eigen::Index n_, r_, d_;
  Eigen::VectorXd scale_;
};

}  // namespace noether
