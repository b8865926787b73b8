#pragma once
// Potential: a gravitational model U(x_1..x_n, R_1..R_n) and its derivatives (docs/equations.md §2).
// A Potential is immutable once made: every method is const and thread-safe. What an
// evaluation writes (scratch, the orders a tolerance chose, what a run came close to) lives in
// a Workspace the caller owns (noether/workspace.hpp); PotentialEvaluator pairs the two.
#include <noether/forces.hpp>
#include <noether/state.hpp>
#include <noether/workspace.hpp>

#include <memory>
#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// What a model chose for one pair of bodies, and whether the run stayed where the choice
// holds (tolerance-driven models; docs/equations.md §15).
struct PairModel {
  std::string body_a, body_b;
  std::string model;             // e.g. "point masses", "series order 6"
  int order = 0;
  double tolerance = 0.0;        // the error bound asked for (15.1)
  double estimated_error = 0.0;  // the estimate (15.2) at `separation`
  double separation = 0.0;       // the closest separation the choice was made for
  // Set when the bodies came closer than `separation` and the estimate there exceeded the
  // tolerance (the first time).
  bool exceeded = false;
  double exceeded_time = 0.0, exceeded_separation = 0.0, exceeded_error = 0.0;
};

class Potential {
 public:
  virtual ~Potential();
  // A workspace for one evaluating thread. The default is empty: models that write nothing
  // while evaluating need not override it.
  virtual std::unique_ptr<Workspace> make_workspace() const;
  // Makes the model's choices (a tolerance's series orders, docs/equations.md §15) at `initial`,
  // the scene's initial state, before the model is shared: the one non-const call, made once by
  // the host (PluginRegistry::make_potential with an initial state). Every workspace made after
  // it evaluates with those choices, whatever state it first sees, so that a run continued from
  // any of its frames (resumed, loaded) models each pair as the run from t0 did. A model never
  // told chooses at its workspace's first evaluation. The default does nothing.
  virtual void choose_models(const State& initial);
  // Fills U, f_i = −∂U/∂x_i and, for rigid bodies, the body-frame moments M_k, writing only
  // into `workspace` (made by this potential's make_workspace()). `forces` is already sized
  // for the system; implementations overwrite every entry.
  virtual void evaluate(const State& state, Forces& forces, Workspace& workspace) const = 0;
  // One evaluation with a fresh workspace: for one-off evaluations and tests. Loops keep a
  // workspace (PotentialEvaluator) instead: this one allocates, and forgets what it saw.
  void evaluate(const State& state, Forces& forces) const;
  // The model chosen for each pair, for models that choose (none by default), with what the
  // evaluations made with `workspace` saw.
  virtual std::vector<PairModel> pair_models(const Workspace& workspace) const;
  // Optional: the force Jacobian (docs/equations.md §20)
  //   K = ∂(f_1, …, f_n, M_1, …, M_m) / ∂(x_1, …, x_n, θ_1, …, θ_m),
  // a (3n + 3m)² matrix: rows and columns 3i…3i+2 for body i's position, 3n + 3k… for rigid
  // body k's attitude, perturbed in its body frame, R_k exp(S(θ_k)). On positions K = −∂²U/∂x∂x;
  // on a body's own attitude K has the antisymmetric part ½ S(M_k) (20.3). For the variational
  // equations and tangent maps of every integrator, and Newton's Jacobians. Returns false (the
  // default) when the model does not provide it: callers use force_jacobian() (force_jacobian.hpp),
  // which then differences the forces and says so. `K` comes in sized and zeroed.
  virtual bool force_jacobian(const State& state, Eigen::MatrixXd& K, Workspace& workspace) const;
};

// A shared model with a workspace of one's own: what one integrator (one thread) evaluates.
class PotentialEvaluator {
 public:
  explicit PotentialEvaluator(std::shared_ptr<const Potential> potential);
  void operator()(const State& state, Forces& forces) { potential_->evaluate(state, forces, *workspace_); }
  const Potential& potential() const { return *potential_; }
  const std::shared_ptr<const Potential>& shared() const { return potential_; }
  const Workspace& workspace() const { return *workspace_; }
  std::vector<PairModel> pair_models() const { return potential_->pair_models(*workspace_); }
  // K = ∂(f, M)/∂(x, θ) at `state` (noether::force_jacobian, force_jacobian.hpp): the model's
  // own, else central differences; `analytic` says which.
  Eigen::MatrixXd force_jacobian(const State& state, bool* analytic = nullptr);

 private:
  std::shared_ptr<const Potential> potential_;
  std::unique_ptr<Workspace> workspace_;
};

// The sum of several models: U = Σ U_m, forces and moments add.
class SumPotential final : public Potential {
 public:
  explicit SumPotential(std::vector<std::shared_ptr<const Potential>> terms);
  std::unique_ptr<Workspace> make_workspace() const override;
  using Potential::evaluate;
  void evaluate(const State& state, Forces& forces, Workspace& workspace) const override;
  std::vector<PairModel> pair_models(const Workspace& workspace) const override;
  bool force_jacobian(const State& state, Eigen::MatrixXd& K, Workspace& workspace) const override;

 private:
  std::vector<std::shared_ptr<const Potential>> terms_;
};

}  // namespace noether

#pragma GCC visibility pop
