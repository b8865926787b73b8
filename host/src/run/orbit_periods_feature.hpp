#pragma once
// Every bound pair's orbit period as a run feature (RunSummary::orbit_periods;
// docs/user-guide.md "Orbit periods"): at the run's first frame each body's orbit about the
// body, at least as heavy, to which it is bound closest (bound_pairs, attracting_pairs.hpp) — but
// the binary's, timed as the mutual orbit —, each timed by an OrbitClock (orbit_clock.hpp), afresh
// after each jump (an impulse). Its running values are kept in a saved simulation, so a loaded
// run's periods are the uninterrupted run's.
#include "run/orbit_clock.hpp"
#include "run/run_feature.hpp"

#include <optional>
#include <vector>

namespace noether::detail {

class OrbitPeriodsFeature final : public RunFeature {
 public:
  // `skip`: the binary's pair, whose period the mutual orbit feature gives.
  OrbitPeriodsFeature(const System& system, std::optional<std::pair<std::size_t, std::size_t>> skip)
      : system_(system), skip_(skip) {}
  std::string_view name() const override { return "orbit_periods"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  void observe_frame(const State& state, bool first_of_segment, RunSummary&) override;
  void after_jump(const State& before, const State& after) override;
  void save_running(SavedSummary& out) const override;
  void restore_running(const SavedSummary& in) override;
  void summarize(RunSummary& summary) const override;

 private:
  struct Timed {
    std::size_t body, about;
    OrbitClock clock;
  };
  void choose_pairs(const State& state);
  const System& system_;
  std::optional<std::pair<std::size_t, std::size_t>> skip_;
  std::vector<Timed> timed_;
};

}  // namespace noether::detail
