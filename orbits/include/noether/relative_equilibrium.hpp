#pragma once
// Relative equilibria of the full body problem (docs/equations.md §18; Scheeres 2006, 2009;
// Bellerose & Scheeres 2008): configurations that turn rigidly at a rate ω about the axis k̂ of
// the total angular momentum through the barycentre, every body locked to the frame. Found by
// Newton from a scene's state, for any potential plugin; and their linear stability from the
// linearisation in the turning frame, with the symmetry directions projected out.
#include <noether/full_body_model.hpp>
#include <noether/phase_chart.hpp>

#include <Eigen/Dense>

#include <complex>
#include <limits>
#include <string>
#include <vector>

namespace noether {

// The member of the one-parameter family of relative equilibria that is sought: the one at a
// given separation of two bodies, at a given total angular momentum, or at a given rate.
enum class EquilibriumFamily { separation, angular_momentum, rate };

struct EquilibriumOptions {
  EquilibriumFamily fix = EquilibriumFamily::separation;
  double value = std::numeric_limits<double>::quiet_NaN();  // default: the guess's own
  std::size_t body_a = 0, body_b = 1;                        // the pair whose separation is fixed
  double tolerance = 1e-12;  // on the largest scaled residual (18.2)
  int max_iterations = 60;
  // Turn each rigid body of the guess so that its principal axis nearest to k̂ lies along k̂,
  // and, for two bodies, its in-plane principal axis nearest to the line of centres onto that
  // line: the nearest symmetric configuration (long or short axis towards the other body).
  bool align = true;
};

struct RelativeEquilibrium {
  State state;  // at t = 0, barycentre at rest at the origin, velocities of the rigid rotation
  Vec3 axis = Vec3::UnitZ();  // k̂, the direction of the total angular momentum
  double rate = 0;            // ω
  double residual = 0;        // largest scaled residual of (18.2) at the solution
  int iterations = 0;
  double separation = 0;        // ‖x_a − x_b‖
  double angular_momentum = 0;  // L · k̂
  double energy = 0;
  double alignment = 0;  // the largest turn the guess's attitudes were given (rad)
  double contact = 0;    // the sum of the pair's bounding radii (Body::radius; 0 if unknown)
  bool converged = false;
};

// Newton (minimum-norm Gauss–Newton steps, halved until the residual falls) from `guess`
// (usually a scene's initial state): k̂ is the guess's total angular
// momentum about its barycentre, ω starts from the guess's centripetal balance. Throws
// SceneError when the guess has no angular momentum or the bodies do not attract.
RelativeEquilibrium find_relative_equilibrium(const FullBodyModel& model, const State& guess,
                                              const EquilibriumOptions& options = {});

// One normal mode of the linearisation: an eigenvalue λ (one of each ±λ, ±λ̄ group) and what
// moves in it.
struct NormalMode {
  std::complex<double> eigenvalue;
  double frequency = 0;  // |Im λ| (rad per unit time); 0 for a real pair
  std::string kind;      // the dominant motion: "libration of beta", "tilt of alpha", "orbit (in-plane)", ...
  double weight = 0;     // the share of that motion in the (scaled) eigenvector
  bool in_plane = false; // no motion out of the plane ⟂ k̂ (to 1e-6)
  Eigen::VectorXcd shape;  // the eigenvector, unit norm, in equilibrium_chart's coordinates
};

struct EquilibriumStability {
  Eigen::MatrixXd linearisation;            // A = ∂F/∂δ in the turning frame (18.3), scaled chart
  std::vector<std::complex<double>> eigenvalues;  // of the reduced A (18.4), by imaginary part
  std::vector<NormalMode> modes;            // Re λ ≥ 0, Im λ ≥ 0, by frequency
  double max_real = 0;        // max |Re λ|
  double scale = 0;           // max(ω, max |λ|): what `tolerance` is relative to
  double invariance_defect = 0;  // how far span P and ker dL are from invariant (should be ~1e-8)
  bool planar = false;        // every mode is in-plane or out-of-plane
  std::string verdict;        // "linearly stable", "unstable", "undecided"
  std::string in_plane_verdict, out_of_plane_verdict;  // when planar
  // The energy–momentum test (18.5): the Hessian of E − ω L·k̂ on the perturbations that keep
  // L (all three components) and the barycentre, modulo the rotation about k̂. Positive
  // definite: a minimum of the energy at fixed angular momentum, stable also under dissipation
  // (Scheeres 2009's condition). Linearly stable with negative directions: stable only
  // gyroscopically, and any dissipation destabilises it.
  std::vector<double> hessian_eigenvalues;  // ascending, relative to the largest |value|
  int energetic_index = 0;                  // how many are < −tolerance
  std::string energetic_verdict;            // "energetically stable", "not energetically stable", "undecided"
};

// The turning frame's vector field at the equilibrium, linearised by central differences of the
// potential's forces and moments, reduced to the barycentre-free perturbations with fixed L·k̂
// modulo the rotations of the whole configuration, and its eigenvalues. Stable when every
// |Re λ| ≤ tolerance × scale; unstable when one exceeds 100 × that; else undecided.
EquilibriumStability linear_stability(const FullBodyModel& model, const RelativeEquilibrium& equilibrium,
                                      double tolerance = 1e-6);

// The oscillating mode that `body`'s libration dominates (kind "libration of BODY"), or nullptr.
const NormalMode* libration_mode(const EquilibriumStability& stability, const std::string& body);

// The chart the equilibrium's linearisation is written in (length: the largest distance from
// the barycentre; rate: ω).
PhaseChart equilibrium_chart(const FullBodyModel& model, const RelativeEquilibrium& equilibrium);

}  // namespace noether
