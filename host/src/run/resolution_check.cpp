// The step-halving check of an orbit the energy cannot certify (docs/user-guide.md, "Verdict"):
// a small body's orbital energy is lost in the large bodies' (a spacecraft's 0.03 J against a
// binary's 1e10 J), so the run's energy error says nothing about it. Instead the scene is
// integrated over one period of that orbit twice, at the run's step h and at h/2, and the
// orbit's relative position compared: for a method of order p the difference is the error at h
// times (1 − 2^−p), an estimate of it that does not depend on what perturbs the orbit.
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "run/event_watch.hpp"
#include "run/refined_run.hpp"
#include "run/simulation_impl.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <numbers>
#include <utility>

namespace noether {

namespace {

Vec3 relative_position(const State& s, std::size_t body, std::size_t about) {
  return s.x.col(static_cast<Eigen::Index>(body)) - s.x.col(static_cast<Eigen::Index>(about));
}

// An adaptive method's run repeated whole at a tenfold tighter tolerance (rtol and atol / 10):
// the difference is nearly its error (global errors scale about with the tolerance). Where
// rtol / 10 would ask for less than 1e-14, which double precision cannot meet, at a tenfold
// looser one instead: the difference is then nearly that run's error, an upper bound of the
// run's. Only a run that took at most run.rerun_seconds and reached its end (not an event): the
// run the derived numbers' errors are measured by too (RefinedRun).
ResolutionCheck check_tolerance(const Simulation::Impl& m, const RunSummary& judged, ResolutionCheck check,
                                std::size_t b, std::size_t a, RefinedRun& refined) {
  const Refinement* r = refined.refinement();
  if (!r || !(r->tolerance_factor > 0) || !judged.stop_reason.empty()) return ResolutionCheck{};
  const Rerun* run = refined.get();
  if (!run) return ResolutionCheck{};  // the other tolerance failed: the energy's verdict stands
  const bool tighter = r->tolerance_factor < 1.0;
  check.done = check.whole_run = true;
  check.window = m.state.t - m.scene.initial.t;
  check.how = tighter ? "at a tenfold tighter tolerance" : "at a tenfold looser tolerance (an upper bound)";
  check.change = tighter ? "tightening the tolerance tenfold" : "loosening the tolerance tenfold";
  check.remedy = "a tighter tolerance";
  if (!run->stop.reason.empty()) {
    check.ends_differently = "it stops: " + run->stop.reason;
    check.per_window = check.over_run = std::numeric_limits<double>::infinity();
    return check;
  }
  const Vec3 r_end = relative_position(m.state, b, a);
  check.per_window = check.over_run = (r_end - relative_position(run->end, b, a)).norm() / r_end.norm();
  return check;
}

// The scene run from t0 at step `step` to t_end (events on); the state and stop where it ended.
std::pair<State, StopInfo> rerun(const Simulation::Impl& m, double step, double t_end) {
  Rerun run = rerun_scene(m, step, t_end, t_end - m.scene.initial.t);
  return {std::move(run.end), run.stop};
}

}  // namespace

ResolutionCheck check_resolution(const Simulation::Impl& m, const RunSummary& judged, RefinedRun& refined) {
  ResolutionCheck check;
  const Scene& scene = m.scene;
  const double h = m.integrator->fixed_step();
  // (A run an event ended is checked up to its event; an interrupted one is not checked.)
  const bool event = !judged.stop_reason.empty();
  if (judged.orbits.empty() || !m.registry || (event && !is_event(judged.stop_reason))) return check;
  // Only an orbit the energy cannot certify (as judge() found it).
  const OrbitScale& orbit = judged.orbits.front();
  if (!orbit.uncertified) return check;
  const System& system = scene.system;
  const int body = system.index_of(orbit.body), about = system.index_of(orbit.about);
  if (body < 0 || about < 0) return check;
  const auto b = static_cast<std::size_t>(body), a = static_cast<std::size_t>(about);
  const State& initial = scene.initial;
  const double run_length = m.state.t - initial.t;
  check.body = orbit.body;
  check.about = orbit.about;
  if (!(h > 0)) return check_tolerance(m, judged, check, b, a, refined);  // a method that chooses its steps
  if (!scene.integrator.params.has("step")) return ResolutionCheck{};

  // A run that took at most run.rerun_seconds is repeated whole at h/2 (twice its cost): the
  // difference at its end is measured, not extrapolated, which matters for chaotic motion
  // (a spacecraft near a binary), where one orbit's difference says little about the run's.
  // (Not a run whose state was set from outside, or loaded: the scene's is another trajectory.)
  if (judged.wall_seconds <= scene.run.rerun_seconds && scene.run.rerun_seconds > 0 && m.scene_trajectory) {
    // To the end on the step grid: t_end, or the first step after the event (RefinedRun).
    const Rerun* run = refined.get();
    if (!run) return ResolutionCheck{};  // the halved step failed: the energy's verdict stands
    const State& half = run->end;
    const StopInfo& stop = run->stop;
    check.done = check.whole_run = true;
    check.window = run_length;
    const bool same_end = event ? is_event(stop.reason) && judged.stop_reason.rfind(stop.event + ":", 0) == 0 &&
                                      std::abs(stop.t - m.state.t) <= 0.01 * std::max(run_length, 1e-300)
                                : stop.reason.empty();
    if (!same_end) {
      std::ostringstream why;
      why.precision(10);
      if (stop.reason.empty())
        why << "at h/2 the run reaches t = " << half.t << " without the event";
      else
        why << "at h/2 the run stops otherwise: " << stop.reason;
      check.ends_differently = why.str();
      check.per_window = check.over_run = std::numeric_limits<double>::infinity();
      return check;
    }
    const Vec3 r = relative_position(m.state, b, a);
    check.per_window = check.over_run = (r - relative_position(half, b, a)).norm() / r.norm();
    return check;
  }

  // Otherwise one period of the orbit at t0 (vis-viva; an unbound pair: the time to cross its
  // separation), in whole steps, at h and h/2, extrapolated linearly to the run's length.
  const double M = system.G() * (system.body(a).mass + system.body(b).mass);
  const Vec3 r = relative_position(initial, b, a);
  const Vec3 v = initial.p.col(static_cast<Eigen::Index>(b)) / system.body(b).mass -
                 initial.p.col(static_cast<Eigen::Index>(a)) / system.body(a).mass;
  const double inverse_a = 2.0 / r.norm() - v.squaredNorm() / M;
  const double period = inverse_a > 0 ? 2 * std::numbers::pi * std::sqrt(1.0 / (inverse_a * inverse_a * inverse_a) / M)
                                      : r.norm() / std::max(v.norm(), 1e-300);
  const double steps = std::max(2.0, std::ceil(std::min(period, run_length) / h));
  if (!std::isfinite(steps) || steps > 1e9) return ResolutionCheck{};
  const double window = steps * h;
  Vec3 relative[2];
  try {
    for (int k = 0; k < 2; ++k) {
      const auto [end, stop] = rerun(m, h / (k + 1), initial.t + window);
      if (!stop.reason.empty()) return ResolutionCheck{};  // an event inside the window: no comparison
      relative[k] = relative_position(end, b, a);
    }
  } catch (const Error&) {  // the halved step failed too: the energy's verdict stands
    return ResolutionCheck{};
  }
  check.done = true;
  check.window = window;
  check.per_window = (relative[0] - relative[1]).norm() / relative[0].norm();
  check.over_run = check.per_window * std::max(1.0, run_length / window);
  return check;
}

}  // namespace noether
