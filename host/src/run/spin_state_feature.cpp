// The rigid bodies' spin states as a run feature (spin_state_feature.hpp).
#include "run/spin_state_feature.hpp"

#include "run/summary_schema.hpp"

namespace noether::detail {

void SpinStateFeature::observe_frame(const State& state, bool first_of_segment, RunSummary&) {
  if (first_of_segment) tracker_.start();  // a new segment: nothing seen yet
  tracker_.observe(state);
}

void SpinStateFeature::save_running(SavedSummary& out) const {
  if (const auto spin = tracker_.pack(); !spin.empty()) out.numbers.push_back({"spin_state", spin});
}

void SpinStateFeature::restore_running(const SavedSummary& in) {
  if (const std::vector<double>* spin = in.number("spin_state")) tracker_.unpack(*spin);  // absent: an older file
}

}  // namespace noether::detail
