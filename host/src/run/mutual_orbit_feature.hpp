#pragma once
// The mutual orbit of a two-body-like scene as a run feature (RunSummary::mutual_period;
// docs/user-guide.md, "Summary reference"), timed by an OrbitClock (orbit_clock.hpp) from the
// segment's start.
// An impulse (any feature's jump) times the orbit afresh from the state after it; the stretches
// it ends are kept, so the summary has the period before and after each jump (its
// period_changes: ΔP in one run). Jumps at one instant are one. Its running values are kept in
// a saved simulation, so a loaded run's periods are the uninterrupted run's.
#include "run/orbit_clock.hpp"
#include "run/run_feature.hpp"

#include <vector>

namespace noether::detail {

class MutualOrbitFeature final : public RunFeature {
 public:
  // The orbit of bodies a and b of `system` (binary_pair.hpp), the lower index first.
  MutualOrbitFeature(const System& system, std::size_t a, std::size_t b);
  std::string_view name() const override { return "mutual_orbit"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  void observe_frame(const State& state, bool first_of_segment, RunSummary&) override;
  void after_jump(const State& before, const State& after) override;
  void save_running(SavedSummary& out) const override;
  void restore_running(const SavedSummary& in) override;
  void summarize(RunSummary& summary) const override;

 private:
  // A stretch of the orbit between jumps, timed: where it began, its whole revolutions, period.
  struct Stretch {
    double t0;
    int revolutions;
    double period;
  };

  const System& system_;
  std::size_t a_, b_;
  OrbitClock clock_;
  std::vector<Stretch> ended_;  // the stretches jumps ended, in order (the current one: clock_)
};

}  // namespace noether::detail
