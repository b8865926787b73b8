#pragma once
// Periodic orbits of planar point masses (G = 1 or the scene's G; docs/equations.md §8–9, Vanderbei 2002):
// closure of one period, the monodromy matrix of the variational equations integrated with a
// high-order method, its multipliers with the directions of the first integrals projected
// out, and Newton (shooting) refinement of an orbit's initial state and period.
#include <noether/system.hpp>
#include <noether/state.hpp>

#include <Eigen/Dense>

#include <complex>
#include <string>
#include <vector>

namespace noether {

// Planar phase-space point ξ = (x_1, y_1, …, x_n, y_n, u_1, v_1, …, u_n, v_n) (positions, velocities).
struct PlanarSystem {
  double G = 1.0;
  std::vector<double> masses;
  std::size_t n() const { return masses.size(); }
  // From a scene: point masses with z = 0 and v_z = 0 only (clear SceneError otherwise).
  static PlanarSystem from(const System& system, const State& state, Eigen::VectorXd& xi);
  // Accelerations and the Jacobian A(ξ) = [[0, I], [K, 0]] of the flow ξ̇ = F(ξ).
  Eigen::VectorXd rhs(const Eigen::VectorXd& xi) const;
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& xi) const;
  double energy(const Eigen::VectorXd& xi) const;
};

struct FlowOptions {
  double rtol = 1e-13;
  double atol = 1e-15;
};

struct FlowResult {
  Eigen::VectorXd end;          // ξ(T)
  Eigen::MatrixXd monodromy;    // Φ(T) = ∂ξ(T)/∂ξ(0) (empty if not asked for)
  std::size_t steps = 0;
};

// Integrates ξ (and Φ with Φ(0) = I when `variational`) over [0, T] with Fehlberg 7(8).
FlowResult integrate_flow(const PlanarSystem& sys, const Eigen::VectorXd& xi0, double T,
                          bool variational, const FlowOptions& options = {});

// The directions of the first integrals at ξ (docs/equations.md §9): translations ×2, moving frame ×2,
// rotation, and dilation (x − 3v/2, −v/2 − 3a/2) per body; columns of a 4n × 6 matrix.
Eigen::MatrixXd invariant_directions(const PlanarSystem& sys, const Eigen::VectorXd& xi);

struct Stability {
  std::vector<std::complex<double>> multipliers;            // eigenvalues of Φ(T) Π, by modulus
  std::vector<std::complex<double>> unprojected;            // eigenvalues of Φ(T)
  std::vector<std::complex<double>> right_projected;        // eigenvalues of Φ(T) Π (the seed's)
  double max_projected = 0.0, max_unprojected = 0.0;        // max |λ(ΛΠ)|, max |λ(Λ)|
  std::string verdict;  // "linearly stable", "unstable", or "undecided"
};

// Multipliers of Φ Π, Π = I − P (PᵀP)⁻¹ Pᵀ. `tolerance` decides: all |λ| ≤ 1 + tol → stable;
// some |λ| > 1 + 100 tol → unstable; else undecided.
Stability stability(const PlanarSystem& sys, const Eigen::VectorXd& xi0, const Eigen::MatrixXd& monodromy,
                    double tolerance);

// The seed's first-order monodromy Π_i (I + h A(ξ(t_i))), h = T/steps, along the flow.
Eigen::MatrixXd first_order_monodromy(const PlanarSystem& sys, const Eigen::VectorXd& xi0, double T,
                                      std::size_t steps, const FlowOptions& options = {});

struct Refinement {
  Eigen::VectorXd xi0;
  double period = 0;
  double closure = 0;  // ‖ξ(T) − ξ(0)‖ after refinement
  int iterations = 0;
};

// Newton (shooting) on ξ0 (and T if `free_period`): minimum-norm Gauss–Newton steps on
// ξ(T; ξ0) − ξ0 = 0 (the Jacobian [Φ(T) − I | F(ξ(T))] is singular along the symmetries, so
// steps are least squares). With a free period a step that would change T by more than 10 %
// is not taken (the trivial solution T → 0 attracts otherwise).
Refinement refine_periodic_orbit(const PlanarSystem& sys, const Eigen::VectorXd& xi0, double T,
                                 double target = 1e-12, int max_iterations = 12,
                                 const FlowOptions& options = {}, bool free_period = false);

}  // namespace noether
