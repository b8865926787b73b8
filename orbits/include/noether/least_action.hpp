#pragma once
// Periodic orbits by least action (docs/equations.md §8; Vanderbei 2002, Vanderbei): planar bodies with G = 1
// and period 2π; every coordinate a truncated Fourier series
//     z(t) = c0 + Σ_{k=1}^{F} a_k cos kt + b_k sin kt,
// the action A = ∫₀^{2π} Σ_j ½ m_j ‖ż_j‖² + Σ_{j<l} m_j m_l / ‖z_j − z_l‖ dt — the kinetic part
// exactly from the coefficients, the potential part by the trapezoid rule on m equally spaced
// points (exact for trigonometric polynomials of degree < m) — minimized with its analytic
// gradient by L-BFGS (NLopt) from random starts. With the choreography ansatz all bodies
// follow one curve, z_j(t) = z(t + 2πj/n).
#include <noether/periodic_orbit.hpp>

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace noether {

struct LeastActionProblem {
  std::vector<double> masses;  // > 0; equal for a choreography
  int modes = 15;              // F
  int points = 100;            // m; > 2F (no aliasing), a multiple of n for a choreography
  bool choreography = false;
  // Throws SceneError with an actionable message for any inconsistent setting.
  void validate() const;
  std::size_t n() const { return masses.size(); }
  std::size_t curves() const { return choreography ? 1 : n(); }
  std::size_t size() const { return curves() * 2 * (1 + 2 * static_cast<std::size_t>(modes)); }
};

struct FourierOrbit {
  Eigen::VectorXd coefficients;
  double action = 0;
  double residual = 0;       // max ‖m_j z̈_j − F_j‖ / max ‖F_j‖ at the quadrature points
  double min_distance = 0;   // closest approach of two bodies on the curve
  int evaluations = 0;       // action evaluations of the minimizer
  // Initial state at t = 0 (planar ξ) of the orbit with period 2π.
  Eigen::VectorXd initial_state(const LeastActionProblem& p) const;
};

// The action and its gradient at coefficients c.
double action(const LeastActionProblem& p, const Eigen::VectorXd& c, Eigen::VectorXd* gradient);

// Minimizes from one start; `residual` etc. filled in.
FourierOrbit minimize_action(const LeastActionProblem& p, const Eigen::VectorXd& start,
                             int max_evaluations = 20000);

// Random start: a_k, b_k ~ N(0, 1/k²), c0 = 0, from a seeded generator.
Eigen::VectorXd random_start(const LeastActionProblem& p, unsigned seed);

// Positions of body j at time t on the Fourier curve (for pictures and checks).
Eigen::Vector2d fourier_position(const LeastActionProblem& p, const Eigen::VectorXd& c, std::size_t j, double t);

}  // namespace noether
