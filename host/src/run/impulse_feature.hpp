#pragma once
// The scene's impulses as a run feature (docs/user-guide.md, "Impulses"; docs/equations.md §24):
// their order in time and how many of them the run has applied. Its one field, the count at
// every frame, tells a continued run which impulse comes next — also when the run was killed
// between an impulse's two frames (the state before it, at its time, and the state after) — and
// where in the recorded frames the impulses were, so that the summary read back from them moves
// its references as the run did. Each is a jump of the state at its time (RunFeature::jump): the
// body's momentum and the tangent's columns jump (docs/equations.md eqs. 24.1–24.7).
#include <noether/scene.hpp>

#include "run/run_feature.hpp"

#include <optional>
#include <string>
#include <vector>

namespace noether::detail {

class ImpulseFeature final : public RunFeature {
 public:
  // The impulses of a run on `system` from t0; a fixed-step integrator (step h > 0) applies each
  // at a step of its grid, so those still to come must lie a whole number of steps after t0
  // (SceneError).
  // `units`: the scene's, which its warnings name (when declared).
  ImpulseFeature(const System& system, const std::vector<Impulse>& impulses, double t0, double h,
                 Units units = {});
  std::string_view name() const override { return "impulses"; }
  // At t0 none is applied; from a new segment (Simulation::set_state), those after its time are
  // still to come.
  void start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) override;
  std::vector<std::string> fields() const override { return {"impulses.applied"}; }
  void save(Eigen::Ref<const Eigen::MatrixXd> columns, std::span<double> out) const override;
  void restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd> columns) override;
  std::optional<double> next_jump() const override;
  // The next impulse applied where the run stands, at its time (24.1–24.7).
  void jump(StateJump& at) override;
  std::size_t jumps_in(std::span<const double> fields) const override { return applied_in(fields); }
  // An impulse that turned a bound pair (the body and the one it is given about) unbound is
  // warned about, with the speeds (a Δv in mm/s typed as m/s sends Dimorphos away): at once on
  // stderr, and in the summary's warnings.
  void after_jump(const State& before, const State& after) override;
  void save_running(SavedSummary& out) const override;
  void restore_running(const SavedSummary& in) override;
  void summarize(RunSummary& summary) const override;

  // The scene's index of the next impulse to apply, if any is left.
  std::optional<std::size_t> next() const;
  void mark_applied() { ++applied_; }
  // How many a frame's saved fields say were applied.
  static std::size_t applied_in(std::span<const double> fields) { return static_cast<std::size_t>(fields[0]); }

 private:
  const System& system_;
  const std::vector<Impulse>& impulses_;
  std::vector<std::size_t> order_;  // the scene's impulses by time (equal times: the scene's order)
  std::size_t applied_ = 0;         // order_'s first `applied_` have been applied
  Units units_;
  std::vector<std::string> warnings_;  // one per impulse that unbound its pair
};

}  // namespace noether::detail
