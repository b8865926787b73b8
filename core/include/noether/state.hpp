#pragma once
// State: what changes during a run (docs/equations.md §1), stored as contiguous arrays. Positions and
// linear momenta for every body; attitudes R and body angular momenta Π for rigid bodies only,
// indexed by System::rigid_index().
#include <noether/lie.hpp>
#include <noether/system.hpp>

#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The largest coordinate a position may have: beyond it the square of a distance between two
// positions can overflow a double (|x_a − x_b|² ≤ 12 max|x|² < 1.8e308 needs max|x| < 3.9e153),
// and separations, potentials and every derived number with them become infinite or zero.
// Scenes, particles and prescribed bodies beyond it are refused (docs/reliability.md, "Input").
inline constexpr double kLargestCoordinate = 1e150;

struct State {
  double t = 0.0;
  Eigen::Matrix3Xd x;      // x_i, inertial positions
  Eigen::Matrix3Xd p;      // γ_i = m_i v_i, inertial linear momenta
  std::vector<Mat3> R;     // R_k ∈ SO(3), body → inertial, rigid bodies only
  Eigen::Matrix3Xd Pi;     // Π_k = J_k Ω_k, body frame, rigid bodies only
  // The tangent of the state, when a run carries it (run.stm; docs/derivatives.md): the
  // variations V = ∂z/∂(z0, …) of the coordinates (21.1)
  //     z = (x_1 … x_n, θ_1 … θ_m, γ_1 … γ_n, Π_1 … Π_m),
  // θ_k the right perturbation R_k exp(S(θ_k)) of an attitude, one row per coordinate (6n + 6m)
  // and one column per variation carried. Empty: no tangent is carried.
  Eigen::MatrixXd tangent;
  // The balance of the scene's forces beyond gravity (force_model.hpp; docs/equations.md §33),
  // when it has any: one column per force, rows W, ΔP, ΔL (kBalanceRows), what the force put in
  // since t0. An integrator that accepts forces carries it like the tangent. Empty: no forces.
  Eigen::MatrixXd force_balance;

  // A state of the right shape for `system`: zeros, identity attitudes.
  static State zeros(const System& system);
  // The number of coordinates of z (21.1): 6n + 6m.
  static Eigen::Index tangent_rows(const System& system);
  // The names of z's coordinates (21.1), "alpha.position.x", "alpha.attitude.x" (θ),
  // "alpha.momentum.x" (γ), "alpha.angular_momentum.x" (Π, body frame).
  static std::vector<std::string> tangent_coordinates(const System& system);
  // z(to) − z(from) in the coordinates (21.1), attitudes by log(R_fromᵀ R_to): the chart in which
  // tangents are differenced (two states of the same system).
  static Eigen::VectorXd difference(const State& from, const State& to);
};

}  // namespace noether

#pragma GCC visibility pop
