// The stepping loop (docs/equations.md §16): outputs, the final time, events and rollback for
// every integrator.
#include <noether/error.hpp>
#include <noether/stepping.hpp>

#include "run/event_watch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace noether {

namespace {
constexpr double kVanishingStep = 1e-14;      // of t_end − t_start
constexpr std::int64_t kStalledSteps = 1000;  // in a row
}  // namespace

std::int64_t whole_steps(double interval, double h, const char* what) {
  const double n = std::round(interval / h);
  // Step k is at t0 + k h: beyond 2^53 steps k is no longer exact in a double (and the count
  // would soon overflow); such a run is refused rather than silently miscounted.
  if (!std::isfinite(n) || n > 0x1p53) {
    std::ostringstream msg;
    msg << what << " = " << interval << " is " << interval / h << " steps of " << h
        << ": more than 2^53 steps, which noether cannot count exactly; use a larger step or a shorter run";
    throw SceneError(msg.str());
  }
  if (n < 1 || std::abs(n * h - interval) > 1e-9 * interval) {
    std::ostringstream msg;
    msg << what << " = " << interval << " is not a whole number of steps of " << h << " ("
        << interval / h << " steps); choose integrator.step = " << interval << "/N for a whole N";
    throw SceneError(msg.str());
  }
  return static_cast<std::int64_t>(n);
}

namespace {

// The output times t0 + kΔ (k ≥ 1) before t_end, then t_end itself, one at a time (a long run
// holds none of them in memory).
class OutputTimes {
 public:
  // Output times t0 + kΔ after `from` (a continued run: those up to `from` were seen).
  OutputTimes(double t0, double t_end, double every, double from) : t0_(t0), t_end_(t_end), every_(every) {
    if (!(every > 0.0) || !(t_end > from)) throw SceneError("output times need t_end > t0 and output_every > 0");
    if (!((t_end - t0) / every <= 0x1p53))
      throw SceneError("run.output_every is more than 2^53 output frames before t_end, which noether cannot "
                       "count exactly; raise run.output_every");
    if (from > t0) k_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor((from - t0) / every)));
    set();
    while (next_ <= from + 1e-12 * std::max(1.0, std::abs(from)) && next_ < t_end_) {
      ++k_;
      set();
    }
  }
  bool done() const { return done_; }
  double next() const { return next_; }
  void advance() {
    if (next_ == t_end_) {
      done_ = true;
      return;
    }
    ++k_;
    set();
  }

 private:
  void set() {
    const double t = t0_ + static_cast<double>(k_) * every_;
    next_ = t >= t_end_ - 1e-12 * std::abs(t_end_) ? t_end_ : t;
  }
  double t0_, t_end_, every_, next_ = 0.0;
  std::int64_t k_ = 1;
  bool done_ = false;
};

}  // namespace

// The state at t ∈ [s0.t, s1.t] for integrators without dense output: positions and momenta
// by cubic Hermite interpolation of x and v = γ/m (16.2), attitudes along the geodesic
// R0 exp(s log(R0ᵀR1)) (what the event functions read; spins are not filled).
void hermite_state(const System& system, const State& s0, const State& s1, double t, State& out) {
  const double dt = s1.t - s0.t, s = (t - s0.t) / dt;
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s,
               h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  // d/dt of the four: the velocity of the interpolant
  const double d00 = (6 * s * s - 6 * s) / dt, d10 = 3 * s * s - 4 * s + 1, d01 = (-6 * s * s + 6 * s) / dt,
               d11 = 3 * s * s - 2 * s;
  out.x.resize(3, s0.x.cols());
  out.p.resize(3, s0.x.cols());
  for (Eigen::Index i = 0; i < s0.x.cols(); ++i) {
    const double m = system.body(static_cast<std::size_t>(i)).mass;
    const Vec3 v0 = s0.p.col(i) / m, v1 = s1.p.col(i) / m;
    out.x.col(i) = h00 * s0.x.col(i) + h10 * dt * v0 + h01 * s1.x.col(i) + h11 * dt * v1;
    out.p.col(i) = m * (d00 * s0.x.col(i) + d10 * v0 + d01 * s1.x.col(i) + d11 * v1);
  }
  out.R.resize(s0.R.size());
  for (std::size_t k = 0; k < s0.R.size(); ++k) out.R[k] = s0.R[k] * exp_so3(s * log_so3(s0.R[k].transpose() * s1.R[k]));
  out.t = t;
}


StopInfo advance(Integrator& integrator, const Potential& potential, const System& system,
                 State& state, const Schedule& schedule, Observer& observer) {
  const double t_start = state.t, t_end = schedule.t_end;
  // Step k and output frames are counted from t0: the run's start, also when this call
  // continues it.
  const double t0 = std::isnan(schedule.t_origin) ? t_start : schedule.t_origin;
  if (!(t_end > t_start) || !(schedule.output_every > 0.0))
    throw SceneError("the run needs t_end > t0 and output_every > 0");
  const double h = integrator.fixed_step();
  std::int64_t n_steps = 0, stride = 0;
  std::optional<OutputTimes> outputs;  // for methods that choose their steps
  if (h > 0) {
    n_steps = whole_steps(t_end - t0, h, "run.t_end − t0");
    stride = whole_steps(schedule.output_every, h, "run.output_every");
    if (schedule.steps_before >= n_steps)
      throw SceneError("the run is already at or beyond t_end = " + std::to_string(t_end));
  } else {
    outputs.emplace(t0, t_end, schedule.output_every, t_start);
  }

  Forces forces;
  forces.resize(system);
  // Output frames between steps are evaluated with the integrator's own evaluator (the model
  // choices its steps made), or with a workspace of the loop's when it has none.
  std::unique_ptr<Workspace> own_workspace;
  auto evaluate = [&](const State& at, Forces& into) {
    if (PotentialEvaluator* evaluator = integrator.potential_evaluator()) return (*evaluator)(at, into);
    if (!own_workspace) own_workspace = potential.make_workspace();
    potential.evaluate(at, into, *own_workspace);
  };
  if (state.tangent.size() > 0)
    if (const std::string why = integrator.tangent_map_unavailable(); !why.empty())
      throw Error("this integrator cannot carry the state's tangent: " + why);
  if (!schedule.integrator_at_state) integrator.start(state);
  integrator.current(state, forces);
  state.t = t_start;
  double last_observed = t_start;
  StopInfo stop;
  // A frame is the method's own state, or one interpolated between its steps (counted).
  auto observe = [&](bool interpolated = false) {
    if (interpolated) ++stop.interpolated_frames;
    observer.observe(state, forces, interpolated);
    last_observed = state.t;
  };
  if (schedule.observe_start) observe();

  // What may cut a step: the schedule's events, then its further cuts (ties: the first).
  EventWatch events(system, schedule.events);
  std::vector<StepCut*> cuts;
  if (!events.empty()) cuts.push_back(&events);
  cuts.insert(cuts.end(), schedule.cuts.begin(), schedule.cuts.end());
  // The states at the last step's start and end: two buffers whose roles swap after each step
  // (the pointers, not the contents).
  State ends[2], probe;
  State *previous = &ends[0], *reached = &ends[1];
  if (!cuts.empty()) {
    *previous = state;
    for (StepCut* c : cuts) c->arm(system, state);
  }
  // The state at τ inside the last step: the method's dense output, else hermite_state.
  const std::function<const State&(double)> positions_at = [&](double tau) -> const State& {
    if (!integrator.interpolate(tau, probe)) hermite_state(system, *previous, *reached, tau, probe);
    return probe;
  };

  std::int64_t stalled = 0;  // adaptive steps in a row that barely moved t
  for (std::int64_t k = schedule.steps_before + 1;; ++k) {
    stop.steps = k;
    const double t_prev = integrator.time();
    try {
      integrator.step(t_end);
    } catch (const Error&) {
      integrator.current(state, forces);  // the last valid state (the contract of step())
      throw;
    }
    const double t = h > 0 ? t0 + static_cast<double>(k) * h : integrator.time();
    if (schedule.on_step) schedule.on_step(t);
    // An adaptive method whose step has collapsed: 1000 steps in a row each shorter than 1e-14
    // of the run (10^14 more to go) is a method that will never arrive, not a slow one.
    if (h <= 0) {
      if (t - t_prev > kVanishingStep * (t_end - t_start)) {
        stalled = 0;
      } else if (++stalled >= kStalledSteps) {
        std::ostringstream msg;
        msg << "the adaptive step has vanished: " << stalled << " steps in a row each shorter than "
            << kVanishingStep << " of the run, the last from t = " << t_prev << " to " << t << " (h = "
            << t - t_prev << "); the tolerance cannot be met here (a singular or overflowing force? "
            << "a close approach? check the scene's scale, or use a fixed-step method)";
        integrator.current(state, forces);
        throw IntegrationError(msg.str(), integrator.time());
      }
    }

    // The cuts (events): the earliest inside (t_prev, t] of any (16.3).
    if (!cuts.empty() || schedule.after_step) {
      integrator.current_state(*reached);
      reached->t = t;
    }
    if (!cuts.empty()) {
      if (!reached->x.allFinite())  // not a collision: the method failed
        throw IntegrationError("the state became non-finite (NaN or infinite positions) in the step to t = " +
                                   std::to_string(t) + "; the last valid state is kept",
                               t_prev);
      double t_event = std::numeric_limits<double>::infinity();
      StepCut* hit = nullptr;
      const StepCut::Step taken{t_prev, t, *previous, *reached, positions_at};
      for (StepCut* c : cuts)
        // A method that passed t_end (jm-hybrid, dense dopri5) reports no event beyond it.
        if (const std::optional<double> b = c->cut(system, taken); b && *b < t_event && *b <= t_end) t_event = *b, hit = c;
      if (hit) {
        // Outputs before the event, then the state at the event itself.
        if (h <= 0)
          for (; !outputs->done() && outputs->next() < t_event; outputs->advance()) {
            integrator.interpolate(outputs->next(), state);
            evaluate(state, forces);
            observe(true);
          }
        bool interpolated = false;
        if (h > 0 || !integrator.interpolate(t_event, state)) {
          // No dense output: one shortened step of the method from the step's start.
          integrator.start(*previous);
          integrator.step(t_event);
          integrator.current(state, forces);
        } else {
          evaluate(state, forces);
          interpolated = true;
        }
        state.t = t_event;
        if (schedule.after_step) schedule.after_step(state);
        observe(interpolated);
        hit->describe(system, t_event, stop);
        stop.t = t_event;
        return stop;
      }
    }
    if (schedule.after_step) {
      // A method that passed t_end (dense dopri5): its state at t_end, where the run ends.
      if (t > t_end && integrator.interpolate(t_end, probe)) {
        probe.t = t_end;
        schedule.after_step(probe);
      } else {
        schedule.after_step(*reached);
      }
    }
    if (!cuts.empty()) std::swap(previous, reached);

    if (h > 0) {
      if (k % stride == 0 || k == n_steps) {
        integrator.current(state, forces);
        state.t = t;
        observe();
      }
      if (k == n_steps) break;
    } else {
      const double tol = 1e-12 * std::max(1.0, std::abs(t));
      for (; !outputs->done() && outputs->next() <= t + tol; outputs->advance()) {
        const double tau = outputs->next();
        bool interpolated = false;
        if (std::abs(tau - t) <= tol) {
          integrator.current(state, forces);
        } else {
          if (!integrator.interpolate(tau, state))
            throw Error("the integrator chooses its own steps but has no dense output to reach t = " +
                        std::to_string(tau));
          evaluate(state, forces);
          interpolated = true;
        }
        state.t = tau;
        observe(interpolated);
      }
      if (outputs->done()) break;
    }
    if (schedule.interrupt && *schedule.interrupt) {  // a signal: stop here, with this state
      if (last_observed != t) {
        integrator.current(state, forces);
        state.t = t;
        observe();
      }
      std::ostringstream why;
      why.precision(10);
      why << "interrupted by signal " << static_cast<int>(*schedule.interrupt) << " at t = " << t;
      stop.reason = why.str();
      stop.event = "interrupted";
      stop.t = t;
      return stop;
    }
  }
  stop.t = state.t;
  return stop;
}

}  // namespace noether
