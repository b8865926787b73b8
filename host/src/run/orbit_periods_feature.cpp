// Every bound pair's orbit period as a run feature (orbit_periods_feature.hpp).
#include "run/orbit_periods_feature.hpp"

#include <noether/error.hpp>

#include "run/attracting_pairs.hpp"
#include "run/summary_schema.hpp"

namespace noether::detail {

namespace {
constexpr std::size_t kClock = 15;  // numbers per OrbitClock::pack
}  // namespace

void OrbitPeriodsFeature::choose_pairs(const State& state) {
  timed_.clear();
  for (const AttractingPair& p : bound_pairs(system_, state)) {
    if (skip_ && ((p.body == skip_->first && p.about == skip_->second) ||
                  (p.body == skip_->second && p.about == skip_->first)))
      continue;
    timed_.push_back({p.body, p.about, OrbitClock(system_, p.about, p.body)});
  }
}

void OrbitPeriodsFeature::observe_frame(const State& state, bool first_of_segment, RunSummary&) {
  if (first_of_segment) {
    choose_pairs(state);
    for (Timed& t : timed_) t.clock.start_at(state);
  }
  for (Timed& t : timed_) t.clock.track(state);
}

void OrbitPeriodsFeature::after_jump(const State&, const State& after) {
  for (Timed& t : timed_) t.clock.start_at(after);  // timed afresh, as the mutual orbit is
}

void OrbitPeriodsFeature::save_running(SavedSummary& out) const {
  if (timed_.empty()) return;  // (HDF5 refuses an attribute of no numbers)
  std::vector<double> pairs, clocks;
  for (const Timed& t : timed_) {
    pairs.insert(pairs.end(), {static_cast<double>(t.body), static_cast<double>(t.about)});
    const std::vector<double> c = t.clock.pack();
    clocks.insert(clocks.end(), c.begin(), c.end());
  }
  out.numbers.push_back({"orbit_periods.pairs", std::move(pairs)});
  out.numbers.push_back({"orbit_periods.clocks", std::move(clocks)});
}

void OrbitPeriodsFeature::restore_running(const SavedSummary& in) {
  const std::vector<double>* pairs = in.number("orbit_periods.pairs");
  const std::vector<double>* clocks = in.number("orbit_periods.clocks");
  if (!pairs || !clocks) return;  // none timed, or an older checkpoint: timed from the loaded state
  if (pairs->size() % 2 != 0 || clocks->size() != kClock * (pairs->size() / 2))
    throw Error("its orbit periods' running values are not 2 indices and 15 numbers a pair");
  timed_.clear();
  for (std::size_t k = 0; k < pairs->size() / 2; ++k) {
    const double body = (*pairs)[2 * k], about = (*pairs)[2 * k + 1];
    const double n = static_cast<double>(system_.size());
    if (!(body >= 0 && body < n && about >= 0 && about < n))
      throw Error("its orbit periods name a body the scene does not have");
    Timed t{static_cast<std::size_t>(body), static_cast<std::size_t>(about),
            OrbitClock(system_, static_cast<std::size_t>(about), static_cast<std::size_t>(body))};
    const auto from = clocks->begin() + static_cast<std::ptrdiff_t>(kClock * k);
    if (!t.clock.unpack(std::vector<double>(from, from + kClock)))
      throw Error("its orbit periods' running values are damaged");
    timed_.push_back(std::move(t));
  }
}

void OrbitPeriodsFeature::summarize(RunSummary& summary) const {
  summary.orbit_periods.clear();
  for (const Timed& t : timed_) {
    OrbitPeriod o;
    o.body = system_.body(t.body).name;
    o.about = system_.body(t.about).name;
    o.radial = !t.clock.timing();
    o.undersampled = t.clock.timing() && t.clock.undersampled();
    if (!o.radial && !o.undersampled) o.period = t.clock.period(), o.revolutions = t.clock.revolutions();
    summary.orbit_periods.push_back(o);
  }
}

}  // namespace noether::detail
