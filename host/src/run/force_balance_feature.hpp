#pragma once
// The forces' balance as a run feature (docs/forces.md, "Balance"; docs/equations.md eq. 33.3):
// the work W and the momenta ΔP, ΔL each force put in since the segment began, which the
// integrators carry in State::force_balance. It starts them at zero with each new segment (a state
// set from outside) and reads each force's part into the summary at every frame; the run's
// statistics measure the energy and momentum errors from E0 + W, P0 + ΔP, L0 + ΔL.
#include "run/run_feature.hpp"

namespace noether::detail {

class ForceBalanceFeature final : public RunFeature {
 public:
  explicit ForceBalanceFeature(std::size_t forces) : forces_(static_cast<Eigen::Index>(forces)) {}
  std::string_view name() const override { return "forces"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  void begin_segment(State& state) override;
  void observe_frame(const State& state, bool first_of_segment, RunSummary& summary) override;

 private:
  Eigen::Index forces_;
};

}  // namespace noether::detail
