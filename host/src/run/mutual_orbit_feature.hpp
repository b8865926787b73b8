#pragma once
// The mutual orbit of a two-body-like scene as a run feature (RunSummary::mutual_period;
// docs/user-guide.md, "Summary reference"): the angle the secondary sweeps about the primary in
// the orbit's plane at the segment's start, unwrapped frame by frame, each whole revolution's
// time interpolated between frames (cubic Hermite, from the angle and its rate), the period
// the last whole revolution's time over the revolutions.
// An impulse (any feature's jump) times the orbit afresh from the state after it; the stretches
// it ends are kept, so the summary has the period before and after each jump (its
// period_changes: ΔP in one run). Jumps at one instant are one. Its running values are kept in
// a saved simulation, so a loaded run's periods are the uninterrupted run's.
#include "run/run_feature.hpp"

#include <limits>
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
  void start_at(const State& state);  // the orbit's plane and the clock from here
  void track(const State& state);     // the angle swept since, whole revolutions timed
  Vec3 relative(const State& state) const { return state.x.col(b_) - state.x.col(a_); }
  Vec3 relative_velocity(const State& state) const {
    return state.p.col(b_) / system_.body(static_cast<std::size_t>(b_)).mass -
           state.p.col(a_) / system_.body(static_cast<std::size_t>(a_)).mass;
  }
  double rate(const State& state) const;  // the angle's rate of change in the plane

  // A stretch of the orbit between jumps, timed: where it began, its whole revolutions, period.
  struct Stretch {
    double t0;
    int revolutions;
    double period;
  };

  const System& system_;
  std::vector<Stretch> ended_;  // the stretches jumps ended, in order (the current one is below)
  Eigen::Index a_, b_;
  bool timing_ = false;  // false: a radial fall, no orbit to time
  Vec3 e1_ = Vec3::Zero(), e2_ = Vec3::Zero();  // the plane at the start: r0 and its prograde normal
  double t0_ = 0.0, t_prev_ = 0.0, angle_prev_ = 0.0, swept_ = 0.0;
  double rate_prev_ = std::numeric_limits<double>::quiet_NaN();  // the angle's rate at t_prev_
  int revolutions_ = 0;
  bool undersampled_ = false;  // frames more than a third of a turn apart seen: not measured
  double period_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace noether::detail
