#pragma once
// The scene's impulses as a run feature (docs/user-guide.md, "Impulses"; docs/equations.md §24):
// their order in time and how many of them the run has applied. Its one field, the count at
// every frame, tells a continued run which impulse comes next — also when the run was killed
// between an impulse's two frames (the state before it, at its time, and the state after) — and
// where in the recorded frames the impulses were, so that the summary read back from them moves
// its references as the run did. Simulation::integrate applies them (simulation.cpp).
#include <noether/scene.hpp>

#include "run/run_feature.hpp"

#include <optional>

namespace noether::detail {

class ImpulseFeature final : public RunFeature {
 public:
  explicit ImpulseFeature(const std::vector<Impulse>& impulses);
  std::string_view name() const override { return "impulses"; }
  // At t0 none is applied; from a new segment (Simulation::set_state), those after its time are
  // still to come.
  void start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) override;
  void after_step(const State&, Eigen::Ref<const Eigen::MatrixXd>) override {}
  std::vector<std::string> fields() const override { return {"impulses.applied"}; }
  void save(Eigen::Ref<const Eigen::MatrixXd> columns, std::span<double> out) const override;
  void restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd> columns) override;
  void summarize(RunSummary&) const override {}

  // The scene's index of the next impulse to apply, if any is left.
  std::optional<std::size_t> next() const;
  void mark_applied() { ++applied_; }
  // How many a frame's saved fields say were applied.
  static std::size_t applied_in(std::span<const double> fields) { return static_cast<std::size_t>(fields[0]); }

 private:
  const std::vector<Impulse>& impulses_;
  std::vector<std::size_t> order_;  // the scene's impulses by time (equal times: the scene's order)
  std::size_t applied_ = 0;         // order_'s first `applied_` have been applied
};

}  // namespace noether::detail
