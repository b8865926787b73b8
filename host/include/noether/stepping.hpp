#pragma once
// The stepping loop: the one place that drives an Integrator from t0 to t_end. It calls the
// Observer at t0, at every output time and at the end; reports the final time exactly; stops
// at events (close approach, collision of the bodies' extents) for every integrator alike;
// and on a failed step leaves `state` at the last valid state (docs/equations.md §16).
#include <noether/forces.hpp>
#include <noether/integrator.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <csignal>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace noether {

class Observer {
 public:
  virtual ~Observer() = default;
  // Called at t0, at every output time and at the end (or at the event that ended the run),
  // with the potential evaluated at that state; `interpolated` when the state was interpolated
  // between the method's steps (dense output) rather than reached by the method.
  virtual void observe(const State& state, const Forces& forces, bool interpolated) = 0;
};

// A body leaving another (run.escape): stop when `body` goes farther than `distance` from
// `about` (0: off), or, with `unbound`, when their two-body energy turns positive (osculating
// e ≥ 1; docs/equations.md eq. 16.8).
struct Escape {
  std::size_t body = 0, about = 0;
  double distance = 0.0;
  bool unbound = false;
};

struct Events {
  // Stop when two body centres come closer than this (0: off).
  double close_approach = 0.0;
  // Stop when two bodies touch: their surfaces when one has a solid shape (eq. 16.5), else
  // their spheres of Body::radius (pairs where both radii are 0 are not checked).
  bool collisions = true;
  std::optional<Escape> escape;
};

struct StopInfo;

// What may end a step early (docs/equations.md §16): a function of the state crossing zero
// inside a step, which the stepping loop locates and cuts the step at. The events are one
// (run/event_watch.hpp); contact will be another. The loop calls `arm` where it starts, `cut`
// after every step the method takes, and, when the earliest cut of all is this one's, stops
// there and asks `describe` for the stop's reason.
class StepCut {
 public:
  virtual ~StepCut() = default;
  // At the state the loop starts from.
  virtual void arm(const System& system, const State& start) = 0;
  // A step the method took, (t_prev, t]: the states at its ends and `at(τ)`, the state at τ
  // inside it (the method's dense output, else hermite_state).
  struct Step {
    double t_prev, t;
    const State& previous;
    const State& reached;
    const std::function<const State&(double)>& at;
  };
  // The earliest time in the step where the cut falls (none: the step stands). Called for
  // every step, whatever the other cuts found.
  virtual std::optional<double> cut(const System& system, const Step& step) = 0;
  // The stop at its last cut, time t: its reason, event and pair (StopInfo's).
  virtual void describe(const System& system, double t, StopInfo& stop) const = 0;
};

struct Schedule {
  double t_end = 0.0;         // integrate from state.t to t_end
  double output_every = 0.0;  // observer interval; the observer also sees t0 and t_end
  Events events;
  // Called after every step with the time reached (progress reports); may be empty.
  std::function<void(double)> on_step;
  // When non-null and set (to a signal number, by a signal handler), the run stops after the
  // current step: the state there is observed and the run ends as by an event, "interrupted".
  const volatile std::sig_atomic_t* interrupt = nullptr;
  // Called after every step that stands (not one an event cut short) with the state the method
  // reached, its tangent included, and at an event with the state there; before the frame at
  // that time is observed. May be empty (then no state is read after a step without events).
  std::function<void(const State&)> after_step = nullptr;
  // Further cuts of the steps beside `events` (the run features': run/event_feature.cpp), in
  // the order that breaks ties; not owned.
  std::vector<StepCut*> cuts = {};

  // Continuing a run (Simulation::integrate called again, `noether run --resume`): the time of
  // step 0 and of frame 0 (NaN: state.t); the fixed steps already taken from there to state.t;
  // whether the starting state is observed (it was, by the run being continued); and whether
  // the integrator already stands at `state` (then it is not started again, so its next step
  // is the one an uninterrupted run would take).
  double t_origin = std::numeric_limits<double>::quiet_NaN();
  std::int64_t steps_before = 0;
  bool observe_start = true;
  bool integrator_at_state = false;
};

// What ended the run.
struct StopInfo {
  std::string reason;  // empty when t_end was reached, else the event, in words
  std::string event;   // "", "close approach", "collision", "escape", "unbound" or "interrupted"
  double t = 0.0;
  std::size_t body_a = 0, body_b = 0;  // the pair of an event
  // Output frames that were interpolated between the method's steps (dense output), not states
  // the method itself reached.
  std::int64_t interpolated_frames = 0;
  // Fixed-step methods: the steps from t_origin to the end of the run (Schedule::steps_before
  // of a continuation).
  std::int64_t steps = 0;
};

// The stepping loop: advances `state` (at state.t) with `integrator` through the schedule to
// schedule.t_end, the observer seeing every output frame. On return `state` is the final state
// (at t_end or at the event). On IntegrationError it is the last valid state and the error
// propagates. (Simulation::integrate is this loop with the output file and the summary.)
StopInfo advance(Integrator& integrator, const Potential& potential, const System& system,
                 State& state, const Schedule& schedule, Observer& observer);

// The state at t ∈ [s0.t, s1.t] for integrators without dense output: positions and momenta
// by cubic Hermite interpolation of x and v = γ/m (16.2), attitudes along the geodesic
// R0 exp(s log(R0ᵀR1)); spins are not filled. Events and particles read it.
void hermite_state(const System& system, const State& s0, const State& s1, double t, State& out);

// For fixed-step methods: the number of steps of size h in `interval`. Throws SceneError
// (naming `what`) when the interval is not a whole number of steps.
std::int64_t whole_steps(double interval, double h, const char* what);


}  // namespace noether
