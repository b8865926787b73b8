#include <noether/error.hpp>
#include <noether/force_jacobian.hpp>
#include <noether/potential.hpp>

#include <algorithm>

namespace noether {

Workspace::~Workspace() = default;

Potential::~Potential() = default;
std::unique_ptr<Workspace> Potential::make_workspace() const { return std::make_unique<Workspace>(); }
void Potential::evaluate(const State& state, Forces& forces) const {
  const auto workspace = make_workspace();
  evaluate(state, forces, *workspace);
}
void Potential::choose_models(const State&) {}
std::vector<PairModel> Potential::pair_models(const Workspace&) const { return {}; }
bool Potential::force_jacobian(const State&, Eigen::MatrixXd&, Workspace&) const { return false; }

PotentialEvaluator::PotentialEvaluator(std::shared_ptr<const Potential> potential)
    : potential_(std::move(potential)) {
  if (!potential_) throw Error("a potential evaluator needs a potential");
  workspace_ = potential_->make_workspace();
  if (!workspace_) throw Error("a potential's make_workspace() returned no workspace");
}

Eigen::MatrixXd PotentialEvaluator::force_jacobian(const State& state, bool* analytic) {
  ForceJacobian J = noether::force_jacobian(*potential_, state, *workspace_);
  if (analytic) *analytic = J.analytic;
  return std::move(J.K);
}

namespace {
// Each term's workspace, and the forces of the terms after the first.
struct SumWorkspace final : Workspace {
  std::vector<std::unique_ptr<Workspace>> terms;
  Forces term_forces;
};
}  // namespace

SumPotential::SumPotential(std::vector<std::shared_ptr<const Potential>> terms)
    : terms_(std::move(terms)) {
  if (terms_.empty()) throw Error("a sum of potentials needs at least one term");
}

std::unique_ptr<Workspace> SumPotential::make_workspace() const {
  auto w = std::make_unique<SumWorkspace>();
  for (const auto& t : terms_) w->terms.push_back(t->make_workspace());
  return w;
}

void SumPotential::evaluate(const State& state, Forces& forces, Workspace& workspace) const {
  auto& w = workspace_as<SumWorkspace>(workspace, "a sum of potentials");
  terms_.front()->evaluate(state, forces, *w.terms.front());
  for (std::size_t m = 1; m < terms_.size(); ++m) {
    Forces& term = w.term_forces;
    term.f.resize(forces.f.rows(), forces.f.cols());
    term.M.resize(forces.M.rows(), forces.M.cols());
    terms_[m]->evaluate(state, term, *w.terms[m]);
    forces.U += term.U;
    forces.f += term.f;
    forces.M += term.M;
  }
}

// Analytic when every term is (the terms' Jacobians add); else false, and the whole sum is
// differenced.
bool SumPotential::force_jacobian(const State& state, Eigen::MatrixXd& K, Workspace& workspace) const {
  auto& w = workspace_as<SumWorkspace>(workspace, "a sum of potentials");
  Eigen::MatrixXd term;
  for (std::size_t m = 0; m < terms_.size(); ++m) {
    if (m > 0) term.setZero(K.rows(), K.cols());
    if (!terms_[m]->force_jacobian(state, m == 0 ? K : term, *w.terms[m])) return false;
    if (m > 0) K += term;
  }
  return true;
}

std::vector<PairModel> SumPotential::pair_models(const Workspace& workspace) const {
  const auto& w = workspace_as<SumWorkspace>(workspace, "a sum of potentials");
  std::vector<PairModel> all;
  for (std::size_t m = 0; m < terms_.size(); ++m) {
    auto some = terms_[m]->pair_models(*w.terms[m]);
    all.insert(all.end(), some.begin(), some.end());
  }
  return all;
}

}  // namespace noether
