#pragma once
// The rigid bodies' spin states as a run feature (RunSummary::spin_states; docs/user-guide.md,
// "Spin states"): each rigid body's libration or rotation and nutation followed frame by frame
// (SpinStateTracker), their running values kept in a saved simulation, the states in the summary.
#include "run/run_feature.hpp"
#include "run/spin_state_tracker.hpp"

namespace noether::detail {

class SpinStateFeature final : public RunFeature {
 public:
  explicit SpinStateFeature(const System& system) : tracker_(system) {}
  std::string_view name() const override { return "spin_states"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  void observe_frame(const State& state, bool first_of_segment, RunSummary&) override;
  void save_running(SavedSummary& out) const override;
  void restore_running(const SavedSummary& in) override;
  void summarize(RunSummary& summary) const override { summary.spin_states = tracker_.spin_states(); }

 private:
  SpinStateTracker tracker_;
};

}  // namespace noether::detail
