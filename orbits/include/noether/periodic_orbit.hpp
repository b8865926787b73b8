#pragma once
// Periodic orbits on a scene's own model (docs/equations.md §8–9, Vanderbei 2002): the flow of
// point masses in 3-D under the scene's potential, integrated by an integrator plugin through
// the stepping loop; closure of one period; the monodromy matrix of the variational equations;
// its multipliers with the directions of the first integrals projected out; and Newton
// (shooting) refinement of an orbit's initial state and period.
#include <noether/potential.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <Eigen/Dense>

#include <complex>
#include <memory>
#include <string>
#include <vector>

namespace noether {

// Phase point ξ = (x_1, …, x_n, v_1, …, v_n) ∈ R^{6n} of n point masses (positions, velocities).
struct OrbitModel {
  System system;
  std::shared_ptr<const Potential> potential;
  std::vector<PluginConfig> potentials;        // the scene's `potential:` entries
  std::shared_ptr<PluginRegistry> registry;    // for the flow's integrator plugin

  // The scene's bodies and potential, made by name. Refuses rigid bodies by name (orbits of
  // rigid bodies are not supported yet).
  static OrbitModel from_scene(const Scene& scene, PluginRegistry& registry);
  // n point masses under mutual gravity (the point-mass plugin), G as given.
  static OrbitModel point_masses(const std::vector<double>& masses, double G, PluginRegistry& registry);

  std::size_t n() const { return system.size(); }
  Eigen::VectorXd phase_point(const State& state) const;
  State state(const Eigen::VectorXd& xi, double t = 0.0) const;
  // The model is shared and immutable; the evaluations below write into `workspace` (made
  // by potential->make_workspace(), one per thread), or into a fresh one when it is omitted.
  // ξ̇ = F(ξ) = (v, f/m): one potential evaluation.
  Eigen::VectorXd rhs(const Eigen::VectorXd& xi, Workspace& workspace) const;
  Eigen::VectorXd rhs(const Eigen::VectorXd& xi) const;
  // A(ξ) = ∂F/∂ξ = [[0, I], [K, 0]], K = ∂(f/m)/∂x = −M⁻¹ ∂²U/∂x∂x (9.2): from the
  // potential's force_jacobian() when it has one (20.1), else by central differences of the forces
  // (6n evaluations; the variational flow is then much slower).
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& xi, Workspace& workspace) const;
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& xi) const;
  // E = Σ ½ m_j ‖v_j‖² + U(x).
  double energy(const Eigen::VectorXd& xi) const;
  // z = 0 and v_z = 0 for every body (to 1e-12 of the orbit's scale), and the potential keeps
  // them there (f_z = 0).
  bool planar(const Eigen::VectorXd& xi) const;
};

// Between the planar layout (x_1, y_1, …, x_n, y_n, u_1, v_1, …) of the least-action finder
// and ξ.
Eigen::VectorXd lift_planar(const Eigen::VectorXd& planar);
Eigen::VectorXd planar_part(const Eigen::VectorXd& xi);

struct FlowOptions {
  double rtol = 1e-13;
  double atol = 1e-15;
};

struct FlowResult {
  Eigen::VectorXd end;        // ξ(T)
  Eigen::MatrixXd monodromy;  // Φ(T) = ∂ξ(T)/∂ξ(0) (empty if not asked for)
  std::size_t steps = 0;
};

// ξ over [0, T]: without `variational`, by the rk plugin (Fehlberg 7(8) at rtol, atol) through
// the stepping loop; with it, ξ and Φ (Φ(0) = I) together by Fehlberg 7(8), Φ̇ = A(ξ) Φ (9.1).
FlowResult integrate_flow(const OrbitModel& model, const Eigen::VectorXd& xi0, double T, bool variational,
                          const FlowOptions& options = {});

// The directions of the first integrals of a planar orbit of mutual point-mass gravity at ξ
// (docs/equations.md §9), in the planar layout: translations ×2, moving frame ×2, rotation,
// dilation and the flow; columns of a 4n × 7 matrix.
Eigen::MatrixXd invariant_directions(const OrbitModel& model, const Eigen::VectorXd& xi);

struct Stability {
  std::vector<std::complex<double>> multipliers;      // in-plane: eigenvalues of Π Φ Π, by modulus
  std::vector<std::complex<double>> unprojected;      // in-plane: eigenvalues of Φ
  std::vector<std::complex<double>> right_projected;  // in-plane: eigenvalues of Φ Π (Vanderbei's)
  std::vector<std::complex<double>> out_of_plane;     // eigenvalues of the (z, v_z) block of Φ
  double max_projected = 0.0, max_unprojected = 0.0;  // max |λ(ΠΦΠ)|, max |λ(Φ)|
  std::string verdict;  // "linearly stable", "unstable", or "undecided" (in-plane)
};

// Multipliers of a planar orbit of mutual point-mass gravity: the in-plane block of Φ with
// Π = I − P (PᵀP)⁻¹ Pᵀ applied. `tolerance` decides: all |λ| ≤ 1 + tol → stable; some
// |λ| > 1 + 100 tol → unstable; else undecided. Refuses (SceneError, by name) orbits that are
// not planar and potentials other than point-mass, whose first integrals differ.
Stability stability(const OrbitModel& model, const Eigen::VectorXd& xi0, const Eigen::MatrixXd& monodromy,
                    double tolerance);

// Vanderbei's first-order monodromy Π_i (I + h A(ξ(t_i))), h = T/steps, along the flow.
Eigen::MatrixXd first_order_monodromy(const OrbitModel& model, const Eigen::VectorXd& xi0, double T,
                                      std::size_t steps, const FlowOptions& options = {});

struct Refinement {
  Eigen::VectorXd xi0;
  double period = 0;
  double closure = 0;  // ‖ξ(T) − ξ(0)‖ after refinement (the variational flow's)
  int iterations = 0;
};

// Newton (shooting) on ξ0 (and T if `free_period`): minimum-norm Gauss–Newton steps on
// ξ(T; ξ0) − ξ0 = 0 (the Jacobian [Φ(T) − I | F(ξ(T))] is singular along the symmetries, so
// steps are least squares). With a free period a step that would change T by more than 10 %
// is not taken (the trivial solution T → 0 attracts otherwise).
Refinement refine_periodic_orbit(const OrbitModel& model, const Eigen::VectorXd& xi0, double T,
                                 double target = 1e-12, int max_iterations = 30,
                                 const FlowOptions& options = {}, bool free_period = false);

// A scene `noether run` accepts: the model's bodies at ξ0 and its potential, one period with
// rkf78.
std::string orbit_scene(const OrbitModel& model, const Eigen::VectorXd& xi0, double period,
                        const std::string& description);

}  // namespace noether
