#pragma once
// ForceModel: a force that is not the gradient of a potential (docs/equations.md §33; docs/forces.md)
// — tides, radiation, drag. It may depend on the time, the positions, the attitudes and the
// momenta; it returns inertial forces on bodies and body-frame moments on rigid bodies, as a
// Potential does, but no energy. A scene lists them under `forces:`; an integrator that accepts
// them (Integrator::add_forcing) adds them to its step and keeps their balance — the work each
// did and the linear and angular momentum each put in — in State::force_balance, so that a run
// judges E − W, P − ΔP and L − ΔL, the quantities its forced flow conserves (33.3).
#include <noether/forces.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>
#include <noether/workspace.hpp>

#include <memory>
#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// A point mass whose gravity massless particles feel: G M, where it is and how fast it moves,
// and its radius — a sphere the particles land on (0: none, they pass through).
struct PointPull {
  double mu = 0.0;
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  double radius = 0.0;
};

class ForceModel {
 public:
  virtual ~ForceModel();
  // A workspace for one evaluating thread (empty by default), as Potential::make_workspace.
  virtual std::unique_ptr<Workspace> make_workspace() const;
  // Makes the model's choices at `initial`, the scene's initial state, before it is shared, as
  // Potential::choose_models (PluginRegistry::make_force with an initial state); the default
  // does nothing.
  virtual void choose_models(const State& initial);
  // What the model chose for each body it acts on with a chosen model (a prescribed body's
  // series order from a tolerance), as Potential::pair_models: body_a the body, body_b the
  // force (the host writes the force's name there). Empty by default and before choose_models.
  virtual std::vector<PairModel> pair_models() const;
  // Fills f_i (inertial, every body) and M_k (body frame, rigid bodies) at `state`; `forces`
  // comes sized for the system; implementations overwrite every entry (U is not used: 0).
  virtual void evaluate(const State& state, Forces& forces, Workspace& workspace) const = 0;
  // Whether the force depends on the momenta γ, Π (the forced LGVI then solves its closing
  // kick by iteration, (33.2)). True by default.
  virtual bool depends_on_momenta() const;
  // What the force does to massless particles (the scene's `particles:`) at `state`: it appends
  // the point masses whose gravity they feel to `pulls` — a body on a prescribed path pulls the
  // particles as it pulls the bodies, so that they move in the same field — and returns true;
  // false (the default) for a force the particles do not feel (radiation and tides act on the
  // bodies' shapes alone).
  virtual bool pull_particles(const State& state, std::vector<PointPull>& pulls) const;
};

// The rows of a force's balance, State::force_balance's column (33.3): the work W, the linear
// momentum ΔP and the angular momentum ΔL about the origin it put into the system since t0.
inline constexpr Eigen::Index kBalanceRows = 7;  // W, ΔP (3), ΔL (3)

// A scene's forces, immutable and shared by every thread: each with the name the output and
// the summary give it ("tides alpha").
struct ForceTerm {
  std::string name;
  std::shared_ptr<const ForceModel> model;
};
using Forcing = std::vector<ForceTerm>;

// The rate of the balance (33.3) of the force (f, M) at `state`: dW/dt = Σ f_i·γ_i/m_i +
// Σ M_k·J_k⁻¹Π_k, dΔP/dt = Σ f_i, dΔL/dt = Σ x_i × f_i + Σ R_k M_k.
Eigen::Matrix<double, kBalanceRows, 1> balance_rate(const System& system, const State& state, const Forces& force);

// A scene's forces with one thread's workspaces: what an integrator evaluates.
class ForcingEvaluator {
 public:
  ForcingEvaluator(const System& system, std::shared_ptr<const Forcing> forcing);
  std::size_t size() const { return forcing_->size(); }
  const Forcing& forcing() const { return *forcing_; }
  bool depends_on_momenta() const { return depends_on_momenta_; }
  // Throws Error, naming `who`, unless `state` carries a balance of these forces (a column each).
  void check_balance(const State& state, const char* who) const;
  // Evaluates every term at `state`: term(j) its force, total() their sum.
  void operator()(const State& state);
  const Forces& term(std::size_t j) const { return terms_[j]; }
  const Forces& total() const { return total_; }
  // A kick of every term's force held fixed for a time `tau` at fixed positions and attitudes,
  // from momenta (γ, Π) = (before.p, before.Pi) to (after.p, after.Pi): adds to `balance`
  // (kBalanceRows × size()) each term's share of it (33.4): W_j += τ (f_j·v̄ + M_j·Ω̄) with the
  // kick's mean velocities v̄ = (γ + γ')/2m and Ω̄ = J⁻¹(Π + Π')/2, so that Σ_j W_j is exactly
  // the kinetic energy the kick added.
  void add_kick(const State& before, const State& after, double tau, Eigen::MatrixXd& balance);
  // The forces in the continuous inertial Hamiltonian equations (continuous_equations.hpp, y =
  // [x | γ | R (9 each) | Π]): evaluates them at `state`, adds f^F to γ̇ and M^F to Π̇ in `dydt`,
  // and writes each force's balance rate (33.3), kBalanceRows numbers per force, to `balance_rates`.
  void add_to_inertial_hamiltonian(const State& state, double* dydt, double* balance_rates);
  // The Jacobian of the total force (f^F, M^F) at `state` with respect to z = (x, θ, γ, Π) of
  // (21.1) — rows f^F_1 … f^F_n, M^F_1 … M^F_m; 6n + 6m columns — by central differences (33.5),
  // 2 (6n + 6m) evaluations. Leaves term() and total() as they were.
  void jacobian(const State& state, Eigen::MatrixXd& J);

 private:
  System system_;
  std::shared_ptr<const Forcing> forcing_;
  std::vector<std::unique_ptr<Workspace>> workspaces_;
  std::vector<Forces> terms_;
  Forces total_;
  State mean_;
  std::vector<Forces> saved_terms_;
  Forces saved_total_;
  bool depends_on_momenta_ = false;
};

}  // namespace noether

#pragma GCC visibility pop
