#pragma once
// Periodic orbits by least action (docs/equations.md §8; Vanderbei 2002): planar point masses
// of a model (the scene's bodies and potential, OrbitModel), period T; every coordinate a
// truncated Fourier series in the phase τ = 2π t / T,
//     z(τ) = c0 + Σ_{k=1}^{F} a_k cos kτ + b_k sin kτ,
// the action A = ∫₀^T Σ_j ½ m_j ‖ż_j‖² − U(z) dt — the kinetic part exactly from the
// coefficients, the potential part by the trapezoid rule on m equally spaced points (exact for
// trigonometric polynomials of degree < m), U and its gradient from the model's potential —
// minimized with its analytic gradient by L-BFGS (NLopt) from random starts. With the
// choreography ansatz all bodies follow one curve, z_j(τ) = z(τ + 2πj/n).
#include <noether/periodic_orbit.hpp>

#include <Eigen/Dense>

#include <numbers>
#include <string>
#include <vector>

namespace noether {

struct LeastActionProblem {
  OrbitModel model;            // the bodies (their masses) and the potential
  double period = 2 * std::numbers::pi;
  int modes = 15;              // F
  int points = 100;            // m; > 2F (no aliasing), a multiple of n for a choreography
  bool choreography = false;
  // Throws SceneError with an actionable message for any inconsistent setting.
  void validate() const;
  std::size_t n() const { return model.n(); }
  double mass(std::size_t j) const { return model.system.body(j).mass; }
  std::size_t curves() const { return choreography ? 1 : n(); }
  std::size_t size() const { return curves() * 2 * (1 + 2 * static_cast<std::size_t>(modes)); }
};

struct FourierOrbit {
  Eigen::VectorXd coefficients;
  double action = 0;
  double residual = 0;       // max ‖m_j z̈_j − F_j‖ / max ‖F_j‖ at the quadrature points (F_j
                             // in 3-D: a potential that pushes out of the plane leaves a residual)
  double min_distance = 0;   // closest approach of two bodies on the curve
  int evaluations = 0;       // action evaluations of the minimizer
  // Initial state at t = 0 (planar ξ) of the orbit with the problem's period.
  Eigen::VectorXd initial_state(const LeastActionProblem& p) const;
};

// The action and its gradient at coefficients c, the potential evaluated with `workspace`
// (the model's; a fresh one when null).
double action(const LeastActionProblem& p, const Eigen::VectorXd& c, Eigen::VectorXd* gradient,
              Workspace* workspace = nullptr);

// Minimizes from one start; `residual` etc. filled in.
FourierOrbit minimize_action(const LeastActionProblem& p, const Eigen::VectorXd& start,
                             int max_evaluations = 20000);

// Random start: a_k, b_k ~ N(0, 1/k²), c0 = 0, from a seeded generator.
Eigen::VectorXd random_start(const LeastActionProblem& p, unsigned seed);

// Positions of body j at phase τ = 2π t / T on the Fourier curve (for pictures and checks).
Eigen::Vector2d fourier_position(const LeastActionProblem& p, const Eigen::VectorXd& c, std::size_t j, double t);

}  // namespace noether
