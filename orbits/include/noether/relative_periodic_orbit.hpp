#pragma once
// Relative periodic orbits of the full body problem (docs/equations.md §19): states that an
// integrator's map over a time T returns turned by an angle α about the total angular
// momentum's axis, Rot(−α) Φ_T(s) = s. Φ_T is any integrator plugin through the stepping loop:
// the continuous flow with an adaptive method (rk rkf78, cvode), or the LGVI's discrete map with
// T = N h, whose periodic orbits are those of the symplectic map itself. Shooting (Newton on s
// and α, T fixed) and the multipliers of D(Rot(−α) Φ_T) with the symmetry directions projected out.
#include <noether/full_body_model.hpp>
#include <noether/phase_chart.hpp>
#include <noether/scene.hpp>

#include <complex>
#include <string>
#include <vector>

namespace noether {

// Φ_T(s) by `integrator` (collisions and close approaches are not watched).
State integrator_map(const FullBodyModel& model, const PluginConfig& integrator, const State& s, double T);

// s turned by the rotation Q about the origin: x → Q x, γ → Q γ, R → Q R, Π unchanged (and the
// tangent's rows of x and γ turned by Q, when it carries one).
State rotated(const State& s, const Mat3& Q);

// The monodromy of δ ↦ local(Rot(Q) Φ_T(retract(δ))) at δ = 0 from `integrator`'s tangent map
// (docs/equations.md eq. 19.4, §21): exact for the map up to the charts' own derivatives.
// Empty when the integrator carries no tangent map.
Eigen::MatrixXd tangent_monodromy(const FullBodyModel& model, const PluginConfig& integrator, const PhaseChart& chart,
                                  double T, const Mat3& Q);

// The gradients of the conserved quantities in `chart`'s coordinates at its base: row 0 ∂E/∂δ,
// then ∂(L·a)/∂δ for each column a of `axes` (L about the barycentre). Analytic, from the
// potential's forces and moments.
Eigen::MatrixXd conserved_gradients(const FullBodyModel& model, const PhaseChart& chart, const Eigen::Matrix3Xd& axes);

// How far the map returns a state from itself, up to a turn about k̂ (19.1), without Newton.
struct RelativeClosure {
  double angle = 0;    // α: the turn of the first two bodies' line of centres about k̂ over T, in (−π, π]
  double closure = 0;  // the largest scaled component of local(Rot(−α) Φ_T(s)), as the shooting measures it
  State end;           // Φ_T(s)
};
RelativeClosure relative_closure(const FullBodyModel& model, const PluginConfig& integrator, const State& s, double T);

struct RelativePeriodicOrbit {
  State state;       // the barycentre at rest at the origin
  double period = 0;
  double angle = 0;  // α
  Vec3 axis = Vec3::UnitZ();
  double closure = 0;  // largest scaled component of the chart residual (19.1)
  double initial_closure = 0;
  int iterations = 0;
  // The shooting's Jacobian: "tangent map" (the integrator's, eq. 19.6) or "differences" (of the
  // whole map, for integrators without one).
  std::string jacobian;
  // Closed: the shooting converged (what the commands write and judge; the residual of a flow
  // with rtol 1e-13 is ~1e-11, of the LGVI's map ~1e-13).
  static constexpr double closed_tolerance = 1e-9;
  bool closed() const { return closure <= closed_tolerance; }
};

// Newton from (guess, T, α0): minimum-norm Gauss–Newton steps on (19.1) with L·k̂ held at the
// guess's, halved until the residual falls; the Jacobian from the integrator's tangent map (19.6),
// or by central differences of the map for an integrator without one (or with `differenced`, to
// compare).
RelativePeriodicOrbit shoot_relative_periodic_orbit(const FullBodyModel& model, const PluginConfig& integrator,
                                                    const State& guess, double period, double angle,
                                                    double tolerance = 1e-13, int max_iterations = 20,
                                                    bool differenced = false);

struct OrbitMultipliers {
  std::vector<std::complex<double>> multipliers;  // of the reduced map (19.2), by modulus
  double max_modulus = 0;
  double invariance_defect = 0;
  // ‖Mᵀ∇E − ∇E‖ / ‖∇E‖: whether the map conserves E (a flow) or not (a symplectic map, which
  // conserves a modified energy); the energy and the flow are projected out only when it does.
  double energy_defect = 0;
  bool energy_conserved = false;
  std::string verdict;  // "linearly stable" (every |μ| ≤ 1 + tol), "unstable" (> 1 + 100 tol), "undecided"
  // How the monodromy was made: "tangent map" (the integrator's, §21) or "differences" (of the
  // whole map, for integrators without one: noise ~ the integrator's error / 1e-5).
  std::string monodromy;
  // Set apart, not judged: a Lyapunov orbit's pair at 1 on a map that does not conserve E (its
  // family and its phase; lyapunov_multipliers).
  std::vector<std::complex<double>> family;
};

// The monodromy D(Rot(−α) Φ_T) — from the integrator's tangent map, or by central differences
// of the map for an integrator without one — restricted to the barycentre-free
// perturbations with L·k̂ (and, when the map conserves it, the energy) fixed, modulo the
// rotations (and the flow).
// `differenced`: difference the map even when the integrator has a tangent map (to compare).
OrbitMultipliers relative_orbit_multipliers(const FullBodyModel& model, const PluginConfig& integrator,
                                            const RelativePeriodicOrbit& orbit, double tolerance = 1e-6,
                                            bool differenced = false);

}  // namespace noether
