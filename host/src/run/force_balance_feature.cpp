// The forces' balance as a run feature (force_balance_feature.hpp).
#include "run/force_balance_feature.hpp"

#include <noether/force_model.hpp>

namespace noether::detail {

void ForceBalanceFeature::begin_segment(State& state) {
  state.force_balance = Eigen::MatrixXd::Zero(kBalanceRows, forces_);  // what the forces put in starts again
}

void ForceBalanceFeature::observe_frame(const State& state, bool, RunSummary& summary) {
  // Column j: force j's W, ΔP, ΔL since the segment began (rows 0, 1–3, 4–6).
  const auto columns = static_cast<std::size_t>(state.force_balance.cols());
  for (std::size_t j = 0; j < summary.forces.size() && j < columns; ++j) {
    const auto c = static_cast<Eigen::Index>(j);
    summary.forces[j].work = state.force_balance(0, c);
    summary.forces[j].linear_momentum = state.force_balance.col(c).segment<3>(1);
    summary.forces[j].angular_momentum = state.force_balance.col(c).segment<3>(4);
  }
}

}  // namespace noether::detail
