#pragma once
// The events as a run feature (run.close_approach, run.collisions, run.escape;
// docs/user-guide.md "Events", docs/equations.md §16): the scene's watched pairs, which cut the
// step they happen in (EventWatch, a StepCut of the stepping loop) and end the run there.
#include <noether/scene.hpp>

#include "run/event_watch.hpp"
#include "run/run_feature.hpp"

namespace noether::detail {

class EventFeature final : public RunFeature {
 public:
  EventFeature(const System& system, const RunSettings& run)
      : watch_(system, Events{run.close_approach, run.collisions, run.escape}) {}
  // Whether the scene watches any pair (none: the feature is not made).
  bool watches_any() const { return !watch_.empty(); }
  std::string_view name() const override { return "events"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  StepCut* step_cut() override { return &watch_; }

 private:
  EventWatch watch_;
};

}  // namespace noether::detail
