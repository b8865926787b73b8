// The errors of the numbers a run derives from its trajectory (docs/user-guide.md, "Verdict"):
// the energy and momenta cannot see a phase error, yet a period, a ΔP or a libration amplitude
// is what users publish. The run is repeated whole finer (RefinedRun: at half the step, or an
// adaptive method's at a tenfold tighter tolerance) and each number's change turned into an
// estimate of its error (DerivedError): for a step and a method of order p by Richardson
// extrapolation, Q(h) − Q* ≈ (Q(h) − Q(h/2)) · 2^p / (2^p − 1). These are the mutual period, the
// periods before and after each impulse and their difference ΔP — ΔP from its own change, in
// which the errors the two periods share cancel —, every other attracting pair's orbit period,
// each libration's amplitude and period, each body's rotation period, each encounter and the
// time of the event that stopped the run. For the
// Didymos scene the period's estimate at 1200 s is 443 s against a true 444 s
// (tests/test_derived_check.cpp). The errors are kept beside the run (Simulation::Impl::derived)
// and put on every later summary's numbers, which the features rebuild each time
// (with_derived_errors).
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "run/event_watch.hpp"
#include "run/refined_run.hpp"
#include "run/simulation_impl.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace noether {

std::string DerivedError::method() const {
  char text[160];
  if (tolerance_factor > 1.0)
    return "the run repeated at a tenfold looser tolerance (rtol / 10 is below the 1e-14 double precision meets): "
           "its change, an upper bound";
  if (tolerance_factor > 0.0) {
    if (order > 0)
      std::snprintf(text, sizeof text, "the run repeated at a tenfold tighter tolerance, order %d", order);
    else
      std::snprintf(text, sizeof text, "the run repeated at a tenfold tighter tolerance, twice its change (order not declared)");
  } else if (order > 0) {
    std::snprintf(text, sizeof text, "the run repeated at half the step, Richardson order %d", order);
  } else {
    std::snprintf(text, sizeof text, "the run repeated at half the step, twice its change (order not declared)");
  }
  return text;
}

double DerivedError::exponent() const {
  if (tolerance_factor > 0.0) return order > 0 ? order / (order + 1.0) : 0.5;
  return order > 0 ? order : 1.0;
}

namespace {

// A body that librates about its binary's line of centres, followed by the frames: it has turned
// back each way.
bool librates(const SpinState& s) {
  return !s.other.empty() && !s.undersampled && std::isfinite(s.libration_amplitude) && s.libration_amplitude <= 90.0 &&
         s.turning_points >= 2;
}

// A closest approach between steps: an encounter, not the start or the end of the run.
bool encounter(const ClosestApproach& c) { return c.where == ClosestApproach::Where::kEncounter; }

// Q, Q of the finer run and how it was made finer: the error of Q (DerivedError).
DerivedError estimate(double value, double finer, const Refinement& r) {
  DerivedError e;
  e.step = r.step;
  e.tolerance = r.rtol;
  e.tolerance_factor = r.tolerance_factor;
  e.order = r.order;
  e.at_half_step = finer;
  double factor = 2.0;  // an order not declared
  if (r.tolerance_factor > 1.0)
    factor = 1.0;  // the looser run's change: an upper bound
  else if (r.tolerance_factor > 0.0 && r.order > 0)
    factor = 1.0 / (1.0 - std::pow(r.tolerance_factor, e.exponent()));
  else if (r.tolerance_factor == 0.0 && r.order > 0)
    factor = std::ldexp(1.0, r.order) / (std::ldexp(1.0, r.order) - 1.0);
  e.error = factor * std::abs(value - finer);
  return e;
}

}  // namespace

RunSummary check_derived(const RunSummary& judged, RefinedRun& refined) {
  RunSummary out = judged;
  const bool changes = std::any_of(judged.period_changes.begin(), judged.period_changes.end(),
                                   [](const PeriodChange& c) { return c.measured(); });
  const bool librations = std::any_of(judged.spin_states.begin(), judged.spin_states.end(), librates);
  const bool spins = std::any_of(judged.spin_states.begin(), judged.spin_states.end(),
                                 [](const SpinState& s) { return std::isfinite(s.spin_period); });
  const bool orbits = std::any_of(judged.orbit_periods.begin(), judged.orbit_periods.end(),
                                  [](const OrbitPeriod& o) { return o.revolutions >= 1; });
  const bool encounters = std::any_of(judged.closest_approaches.begin(), judged.closest_approaches.end(), encounter);
  const bool event = is_event(judged.stop_reason);
  if (judged.mutual_revolutions < 1 && !changes && !librations && !spins && !orbits && !encounters && !event)
    return out;  // nothing derived
  // Why no error is estimated: said on each number that asked.
  auto not_estimated = [&](const std::string& why) {
    if (judged.mutual_revolutions >= 1) out.mutual_period_error.why_not = why;
    for (PeriodChange& c : out.period_changes)
      if (c.measured()) c.change_error.why_not = why;
    for (SpinState& spin : out.spin_states) {
      if (librates(spin)) spin.libration_error.why_not = why;
      if (std::isfinite(spin.libration_period)) spin.libration_period_error.why_not = why;
      if (std::isfinite(spin.spin_period)) spin.spin_period_error.why_not = why;
    }
    for (ClosestApproach& c : out.closest_approaches)
      if (encounter(c)) c.distance_error.why_not = why;
    for (OrbitPeriod& o : out.orbit_periods)
      if (o.revolutions >= 1) o.error.why_not = why;
    if (event) out.stop_time_error.why_not = why;
  };
  if (!refined.refinement()) {
    not_estimated(refined.why_not());
    return out;
  }
  const Rerun* finer = refined.get();
  if (!finer) {
    not_estimated(refined.refinement()->step > 0 ? "the run at half the step failed"
                                                 : "the run at the other tolerance failed");
    return out;
  }
  const RunSummary& finer_run = finer->summary;
  const Refinement& h = *refined.refinement();
  const std::string at = h.step > 0               ? "at half the step"
                             : h.tolerance_factor < 1.0 ? "at the tighter tolerance"
                                                        : "at the looser tolerance";
  if (judged.mutual_revolutions >= 1) {
    if (finer_run.mutual_revolutions < 1 || finer_run.mutual_pair != judged.mutual_pair)
      out.mutual_period_error.why_not = at + " the mutual orbit makes no whole revolution";
    else
      out.mutual_period_error = estimate(judged.mutual_period, finer_run.mutual_period, h);
  }
  // Each jump's periods and ΔP against the same jump's at half the step (the impulses come at the
  // same times in both runs).
  for (std::size_t k = 0; k < out.period_changes.size() && k < judged.period_changes.size(); ++k) {
    PeriodChange& c = out.period_changes[k];
    if (!c.measured()) continue;
    const PeriodChange* there = nullptr;
    for (const PeriodChange& d : finer_run.period_changes)
      if (d.t == c.t) there = &d;
    if (!there || !there->measured() || finer_run.mutual_pair != judged.mutual_pair) {
      c.change_error.why_not = at + " the orbit is not timed on both sides of this jump";
      continue;
    }
    c.before_error = estimate(c.before, there->before, h);
    c.after_error = estimate(c.after, there->after, h);
    c.change_error = estimate(c.change(), there->change(), h);
  }
  // Each librating body's amplitude and period, and each body's rotation period, against the
  // same body's at half the step.
  for (SpinState& spin : out.spin_states) {
    const SpinState* there = nullptr;
    for (const SpinState& s : finer_run.spin_states)
      if (s.body == spin.body) there = &s;
    if (librates(spin)) {
      if (!there || !librates(*there))
        spin.libration_error.why_not = at + " it does not librate, or its frames cannot follow it";
      else
        spin.libration_error = estimate(spin.libration_amplitude, there->libration_amplitude, h);
    }
    if (std::isfinite(spin.libration_period)) {
      if (!there || !std::isfinite(there->libration_period)) {
        spin.libration_period_error.why_not = at + " its libration has no whole swing";
      } else {
        // With the turning points' interpolation added: the same frames in both runs.
        spin.libration_period_error = estimate(spin.libration_period, there->libration_period, h);
        spin.libration_period_error.error += spin.libration_period_frames_error;
      }
    }
    if (std::isfinite(spin.spin_period)) {
      if (!there || !std::isfinite(there->spin_period))
        spin.spin_period_error.why_not = at + " it does not turn once, or its frames cannot follow it";
      else
        spin.spin_period_error = estimate(spin.spin_period, there->spin_period, h);
    }
  }
  // Each attracting pair's orbit period against the same pair's.
  for (OrbitPeriod& o : out.orbit_periods) {
    if (o.revolutions < 1) continue;
    const OrbitPeriod* there = nullptr;
    for (const OrbitPeriod& d : finer_run.orbit_periods)
      if (d.body == o.body && d.about == o.about) there = &d;
    if (!there || there->revolutions < 1)
      o.error.why_not = at + " the orbit makes no whole revolution";
    else
      o.error = estimate(o.period, there->period, h);
  }
  // Each pair's encounter against the same pair's at half the step (its distance's and time's
  // errors with the frames' interpolation bounds added: the same frames in both runs, the
  // Richardson difference cannot see them).
  for (ClosestApproach& c : out.closest_approaches) {
    if (!encounter(c)) continue;
    const ClosestApproach* there = nullptr;
    for (const ClosestApproach& d : finer_run.closest_approaches)
      if (d.pair == c.pair) there = &d;
    if (!there || !encounter(*there)) {
      c.distance_error.why_not = at + " the closest approach is not an encounter";
      continue;
    }
    c.distance_error = estimate(c.distance, there->distance, h);
    c.distance_error.error += c.frames_error;
    c.time_error = estimate(c.t, there->t, h);
    c.time_error.error += c.frames_time_error;
  }
  // The event that stopped the run (a collision, an escape) against the same event at half the
  // step: the reasons alike but for their times.
  if (event) {
    auto what = [](const std::string& reason) { return reason.substr(0, reason.rfind(" at t = ")); };
    if (what(finer_run.stop_reason) != what(judged.stop_reason))
      out.stop_time_error.why_not = at + " the run does not stop at the same event";
    else
      out.stop_time_error = estimate(judged.final_state.t, finer_run.final_state.t, h);
  }
  return out;
}

void with_derived_errors(const RunSummary& from, RunSummary& into) {
  if (into.stop_reason == from.stop_reason) into.stop_time_error = from.stop_time_error;
  for (ClosestApproach& c : into.closest_approaches)
    for (const ClosestApproach& e : from.closest_approaches)
      if (e.pair == c.pair) c.distance_error = e.distance_error, c.time_error = e.time_error;
  into.mutual_period_error = from.mutual_period_error;
  for (OrbitPeriod& o : into.orbit_periods)
    for (const OrbitPeriod& e : from.orbit_periods)
      if (e.body == o.body && e.about == o.about) o.error = e.error;
  for (PeriodChange& c : into.period_changes)
    for (const PeriodChange& e : from.period_changes)
      if (e.t == c.t) c.before_error = e.before_error, c.after_error = e.after_error, c.change_error = e.change_error;
  for (SpinState& spin : into.spin_states)
    for (const SpinState& e : from.spin_states)
      if (e.body == spin.body)
        spin.libration_error = e.libration_error, spin.libration_period_error = e.libration_period_error,
        spin.spin_period_error = e.spin_period_error;
}

}  // namespace noether
