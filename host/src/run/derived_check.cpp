// The errors of the numbers a run derives from its trajectory (docs/user-guide.md, "Verdict"):
// the energy and momenta cannot see a phase error, yet a period, a ΔP or a libration amplitude
// is what users publish. The run is repeated whole at half the step and each number's change
// turned into an estimate of its error at h by Richardson extrapolation: for a method of order
// p, Q(h) − Q* ≈ (Q(h) − Q(h/2)) · 2^p / (2^p − 1): the mutual period, the periods before and
// after each impulse and their difference ΔP — ΔP from its own change, in which the errors the
// two periods share cancel —, and each libration amplitude. For the Didymos scene the period's
// estimate at 1200 s is 443 s against a true 444 s (tests/test_derived_check.cpp). The errors
// are kept beside the run (Simulation::Impl::derived) and put on every later summary's numbers,
// which the features rebuild each time (with_derived_errors).
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "run/event_watch.hpp"
#include "run/half_step_run.hpp"
#include "run/simulation_impl.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace noether {

std::string DerivedError::method() const {
  char text[96];
  if (order > 0)
    std::snprintf(text, sizeof text, "the run repeated at half the step, Richardson order %d", order);
  else
    std::snprintf(text, sizeof text, "the run repeated at half the step, twice its change (order not declared)");
  return text;
}

namespace {

// Why the run cannot be repeated at half the step ("" when it can).
std::string why_not_repeated(const Simulation::Impl& m, const RunSummary& judged) {
  if (!m.scene_trajectory) return "the run does not start from its scene (a state was set, or it was loaded)";
  if (!judged.stop_reason.empty() && !is_event(judged.stop_reason)) return "the run was interrupted";
  if (!(m.integrator->fixed_step() > 0) || !m.scene.integrator.params.has("step"))
    return "integrator '" + m.scene.integrator.plugin + "' chooses its own steps: there is no step to halve";
  if (!m.registry) return "the run has no plugin registry to repeat it with";
  const double limit = m.scene.run.rerun_seconds;
  if (!(limit > 0.0)) return "run.rerun_seconds is 0: the run is not repeated";
  if (judged.wall_seconds > limit) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the run took %.3g s, more than the %.3g s up to which it is repeated at half the step "
                  "(run.rerun_seconds)",
                  judged.wall_seconds, limit);
    return text;
  }
  return "";
}

// A body that librates about its binary's line of centres, followed by the frames.
bool librates(const SpinState& s) {
  return !s.other.empty() && !s.undersampled && std::isfinite(s.libration_amplitude) && s.libration_amplitude <= 90.0;
}

// A closest approach between steps: an encounter, not the start or the end of the run.
bool encounter(const ClosestApproach& c) { return c.where == ClosestApproach::Where::kEncounter; }

// Q(h), Q(h/2) and the method's order: the error of Q(h) (DerivedError).
DerivedError estimate(double at_h, double at_half, double h, int order) {
  DerivedError e;
  e.step = h;
  e.order = order;
  e.at_half_step = at_half;
  const double factor = order > 0 ? std::ldexp(1.0, order) / (std::ldexp(1.0, order) - 1.0) : 2.0;
  e.error = factor * std::abs(at_h - at_half);
  return e;
}

}  // namespace

RunSummary check_derived(const Simulation::Impl& m, const RunSummary& judged, RunAtHalfStep& half_step) {
  RunSummary out = judged;
  const bool changes = std::any_of(judged.period_changes.begin(), judged.period_changes.end(),
                                   [](const PeriodChange& c) { return c.measured(); });
  const bool librations = std::any_of(judged.spin_states.begin(), judged.spin_states.end(), librates);
  const bool encounters = std::any_of(judged.closest_approaches.begin(), judged.closest_approaches.end(), encounter);
  const bool event = is_event(judged.stop_reason);
  if (judged.mutual_revolutions < 1 && !changes && !librations && !encounters && !event) return out;  // nothing derived
  // Why no error is estimated: said on each number that asked.
  auto not_estimated = [&](const std::string& why) {
    if (judged.mutual_revolutions >= 1) out.mutual_period_error.why_not = why;
    for (PeriodChange& c : out.period_changes)
      if (c.measured()) c.change_error.why_not = why;
    for (SpinState& spin : out.spin_states)
      if (librates(spin)) spin.libration_error.why_not = why;
    for (ClosestApproach& c : out.closest_approaches)
      if (encounter(c)) c.distance_error.why_not = why;
    if (event) out.stop_time_error.why_not = why;
  };
  if (const std::string why = why_not_repeated(m, judged); !why.empty()) {
    not_estimated(why);
    return out;
  }
  const HalfStepRun* half = half_step.get();
  if (!half) {
    not_estimated("the run at half the step failed");
    return out;
  }
  const RunSummary& at_half = half->summary;
  const double h = m.integrator->fixed_step();
  const int p = m.integrator->order();
  if (judged.mutual_revolutions >= 1) {
    if (at_half.mutual_revolutions < 1 || at_half.mutual_pair != judged.mutual_pair)
      out.mutual_period_error.why_not = "at half the step the mutual orbit makes no whole revolution";
    else
      out.mutual_period_error = estimate(judged.mutual_period, at_half.mutual_period, h, p);
  }
  // Each jump's periods and ΔP against the same jump's at half the step (the impulses come at the
  // same times in both runs).
  for (std::size_t k = 0; k < out.period_changes.size() && k < judged.period_changes.size(); ++k) {
    PeriodChange& c = out.period_changes[k];
    if (!c.measured()) continue;
    const PeriodChange* there = nullptr;
    for (const PeriodChange& d : at_half.period_changes)
      if (d.t == c.t) there = &d;
    if (!there || !there->measured() || at_half.mutual_pair != judged.mutual_pair) {
      c.change_error.why_not = "at half the step the orbit is not timed on both sides of this jump";
      continue;
    }
    c.before_error = estimate(c.before, there->before, h, p);
    c.after_error = estimate(c.after, there->after, h, p);
    c.change_error = estimate(c.change(), there->change(), h, p);
  }
  // Each librating body's amplitude against its amplitude at half the step.
  for (SpinState& spin : out.spin_states) {
    if (!librates(spin)) continue;
    const SpinState* there = nullptr;
    for (const SpinState& s : at_half.spin_states)
      if (s.body == spin.body) there = &s;
    if (!there || !librates(*there))
      spin.libration_error.why_not = "at half the step it does not librate, or its frames cannot follow it";
    else
      spin.libration_error = estimate(spin.libration_amplitude, there->libration_amplitude, h, p);
  }
  // Each pair's encounter against the same pair's at half the step (its distance's and time's
  // errors with the frames' interpolation bounds added: the same frames in both runs, the
  // Richardson difference cannot see them).
  for (ClosestApproach& c : out.closest_approaches) {
    if (!encounter(c)) continue;
    const ClosestApproach* there = nullptr;
    for (const ClosestApproach& d : at_half.closest_approaches)
      if (d.pair == c.pair) there = &d;
    if (!there || !encounter(*there)) {
      c.distance_error.why_not = "at half the step the closest approach is not an encounter";
      continue;
    }
    c.distance_error = estimate(c.distance, there->distance, h, p);
    c.distance_error.error += c.frames_error;
    c.time_error = estimate(c.t, there->t, h, p);
    c.time_error.error += c.frames_time_error;
  }
  // The event that stopped the run (a collision, an escape) against the same event at half the
  // step: the reasons alike but for their times.
  if (event) {
    auto what = [](const std::string& reason) { return reason.substr(0, reason.rfind(" at t = ")); };
    if (what(at_half.stop_reason) != what(judged.stop_reason))
      out.stop_time_error.why_not = "at half the step the run does not stop at the same event";
    else
      out.stop_time_error = estimate(judged.final_state.t, at_half.final_state.t, h, p);
  }
  return out;
}

void with_derived_errors(const RunSummary& from, RunSummary& into) {
  if (into.stop_reason == from.stop_reason) into.stop_time_error = from.stop_time_error;
  for (ClosestApproach& c : into.closest_approaches)
    for (const ClosestApproach& e : from.closest_approaches)
      if (e.pair == c.pair) c.distance_error = e.distance_error, c.time_error = e.time_error;
  into.mutual_period_error = from.mutual_period_error;
  for (PeriodChange& c : into.period_changes)
    for (const PeriodChange& e : from.period_changes)
      if (e.t == c.t) c.before_error = e.before_error, c.after_error = e.after_error, c.change_error = e.change_error;
  for (SpinState& spin : into.spin_states)
    for (const SpinState& e : from.spin_states)
      if (e.body == spin.body) spin.libration_error = e.libration_error;
}

}  // namespace noether
