// The mutual orbit of a two-body-like scene as a run feature (mutual_orbit_feature.hpp).
#include "run/mutual_orbit_feature.hpp"

#include <noether/error.hpp>

#include "run/summary_schema.hpp"

#include <algorithm>
#include <limits>

namespace noether::detail {

MutualOrbitFeature::MutualOrbitFeature(const System& system, std::size_t a, std::size_t b)
    : system_(system), a_(std::min(a, b)), b_(std::max(a, b)), clock_(system, a_, b_) {}

void MutualOrbitFeature::after_jump(const State&, const State& after) {
  // A second jump at the same instant (two impulses at one time) is part of the first.
  if (after.t != clock_.t0())
    ended_.push_back({clock_.t0(), clock_.timing() ? clock_.revolutions() : 0,
                      clock_.timing() ? clock_.period() : std::numeric_limits<double>::quiet_NaN()});
  clock_.start_at(after);
}

void MutualOrbitFeature::observe_frame(const State& state, bool first_of_segment, RunSummary&) {
  if (first_of_segment) ended_.clear(), clock_.forget_undersampling(), clock_.start_at(state);
  clock_.track(state);
}

void MutualOrbitFeature::save_running(SavedSummary& out) const {
  out.numbers.push_back({"mutual_orbit", clock_.pack()});
  if (ended_.empty()) return;  // (HDF5 refuses an attribute of no numbers)
  std::vector<double> ended;
  for (const Stretch& s : ended_) ended.insert(ended.end(), {s.t0, static_cast<double>(s.revolutions), s.period});
  out.numbers.push_back({"mutual_orbit.ended", std::move(ended)});
}

void MutualOrbitFeature::restore_running(const SavedSummary& in) {
  const std::vector<double>* v = in.number("mutual_orbit");
  if (!v) return;  // an older checkpoint: timed from the loaded state
  // 13 numbers: a checkpoint from before the angular rate was kept (the next crossing linear);
  // 14: from before the frames' spacing was judged.
  if (!clock_.unpack(*v)) throw Error("its mutual orbit's running values are not 15 numbers");
  ended_.clear();
  const std::vector<double>* ended = in.number("mutual_orbit.ended");
  if (!ended) return;  // no jump yet, or a checkpoint from before the stretches were kept
  if (ended->size() % 3 != 0) throw Error("its mutual orbit's ended stretches are not triples of numbers");
  for (std::size_t k = 0; k < ended->size(); k += 3)
    ended_.push_back({(*ended)[k], static_cast<int>((*ended)[k + 1]), (*ended)[k + 2]});
}

void MutualOrbitFeature::summarize(RunSummary& summary) const {
  const bool timing = clock_.timing();
  summary.mutual_pair = timing ? system_.body(a_).name + "–" + system_.body(b_).name : std::string();
  summary.mutual_undersampled = timing && clock_.undersampled();
  if (summary.mutual_undersampled) {  // nothing timed can be trusted (below, each stretch alike)
    summary.mutual_period = std::numeric_limits<double>::quiet_NaN();
    summary.mutual_revolutions = 0;
    summary.period_changes.clear();
    return;
  }
  summary.mutual_period = clock_.period();
  summary.mutual_revolutions = clock_.revolutions();
  // Each jump: the stretch it ended, and the one it began (the next jump's, or the current one).
  summary.period_changes.clear();
  for (std::size_t k = 0; k < ended_.size(); ++k) {
    PeriodChange c;
    const bool last = k + 1 == ended_.size();
    c.t = last ? clock_.t0() : ended_[k + 1].t0;
    c.before = ended_[k].period, c.revolutions_before = ended_[k].revolutions;
    c.after = last ? (timing ? clock_.period() : std::numeric_limits<double>::quiet_NaN()) : ended_[k + 1].period;
    c.revolutions_after = last ? (timing ? clock_.revolutions() : 0) : ended_[k + 1].revolutions;
    summary.period_changes.push_back(c);
  }
}

}  // namespace noether::detail
