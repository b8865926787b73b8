#include <noether/error.hpp>
#include <noether/potential.hpp>

#include <algorithm>

namespace noether {

SumPotential::SumPotential(std::vector<std::shared_ptr<const Potential>> terms)
    : terms_(std::move(terms)) {
  if (terms_.empty()) throw Error("a sum of potentials needs at least one term");
}

void SumPotential::evaluate(const State& state, Forces& forces) const {
  terms_.front()->evaluate(state, forces);
  for (std::size_t m = 1; m < terms_.size(); ++m) {
    scratch_.f.resize(forces.f.rows(), forces.f.cols());
    scratch_.M.resize(forces.M.rows(), forces.M.cols());
    terms_[m]->evaluate(state, scratch_);
    forces.U += scratch_.U;
    forces.f += scratch_.f;
    forces.M += scratch_.M;
  }
}

Potential::~Potential() = default;
std::vector<PairModel> Potential::pair_models() const { return {}; }
bool Potential::position_hessian(const State&, Eigen::MatrixXd&) const { return false; }

bool SumPotential::position_hessian(const State& state, Eigen::MatrixXd& hessian) const {
  Eigen::MatrixXd term;
  for (std::size_t m = 0; m < terms_.size(); ++m) {
    if (!terms_[m]->position_hessian(state, m == 0 ? hessian : term)) return false;
    if (m > 0) hessian += term;
  }
  return true;
}

std::vector<PairModel> SumPotential::pair_models() const {
  std::vector<PairModel> all;
  for (const auto& t : terms_) {
    auto some = t->pair_models();
    all.insert(all.end(), some.begin(), some.end());
  }
  return all;
}

}  // namespace noether
