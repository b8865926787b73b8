// The errors of the numbers a run derives from its trajectory (docs/user-guide.md, "Verdict"):
// the energy and momenta cannot see a phase error, yet a period, a ΔP or a libration amplitude
// is what users publish. The run is repeated whole at half the step and each number's change
// turned into an estimate of its error at h by Richardson extrapolation: for a method of order
// p, Q(h) − Q* ≈ (Q(h) − Q(h/2)) · 2^p / (2^p − 1). For the Didymos scene the estimate at 1200 s
// is 442 s against a true 443 s (tests/test_derived_check.cpp).
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "run/event_watch.hpp"
#include "run/half_step_run.hpp"
#include "run/simulation_impl.hpp"

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
  if (judged.wall_seconds > kWholeRunSeconds) {
    char text[160];
    std::snprintf(text, sizeof text, "the run took %.3g s, more than the %.0f s up to which it is repeated at half the step",
                  judged.wall_seconds, kWholeRunSeconds);
    return text;
  }
  return "";
}

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

void check_derived(const Simulation::Impl& m, const RunSummary& judged, RunAtHalfStep& half_step, RunSummary& out) {
  out.mutual_period_error = {};
  if (judged.mutual_revolutions < 1) return;  // nothing derived to check
  DerivedError& period = out.mutual_period_error;
  if (const std::string why = why_not_repeated(m, judged); !why.empty()) {
    period.why_not = why;
    return;
  }
  const double h = m.integrator->fixed_step();
  const HalfStepRun* half = half_step.get();
  if (!half) {
    period.why_not = "the run at half the step failed";
    return;
  }
  const RunSummary& at_half = half->summary;
  if (at_half.mutual_revolutions < 1 || at_half.mutual_pair != judged.mutual_pair) {
    period.why_not = "at half the step the mutual orbit makes no whole revolution";
    return;
  }
  period = estimate(judged.mutual_period, at_half.mutual_period, h, m.integrator->order());
}

}  // namespace noether
