#pragma once
// Integrator: one step at a time of a State of a System (docs/equations.md §3–7). The host's
// stepping loop (noether/stepping.hpp) owns everything around the steps — output times, the
// final time, events, rollback, progress — so an integrator is only its method.
//
// Contract, for every integrator plugin:
//  * start(s) begins (or begins again) at s; s.t is the start time. The loop restarts an
//    integrator without dense output to land on an event time with one shortened step.
//  * step(t_max) takes one step. A method that chooses its step length (fixed or adaptive)
//    never passes t_max: it ends that step at t_max exactly. A method whose step length is an
//    outcome (jm-hybrid) may pass t_max, and must then provide dense output.
//  * If step() throws (IntegrationError for a method failure), the integrator stays at the
//    state before the step: current() returns the last valid state.
//  * It evaluates the potential through a PotentialEvaluator of its own (the potential is
//    shared and immutable; the workspace is the integrator's), so that runs on several
//    threads may share one potential.
//  * interpolate(t, s): the state at t inside the last step, [t_prev, time()], by the method's
//    own dense output; false when it has none.
//  * Derivatives (docs/derivatives.md): a method that carries the tangent map of its steps says
//    so (tangent_map_unavailable() empty). Started from a state whose `tangent` is not empty, it
//    carries those variations: current(), current_state() and interpolate() return
//    V(t) = ∂z(t)/∂z(t_start) V(t_start), the derivative of the method's own map (not of the
//    exact flow). Started without one, it carries none.
#include <noether/force_model.hpp>
#include <noether/forces.hpp>
#include <noether/parameter_derivatives.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>

#include <cstdint>
#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct WorkCounters {
  std::int64_t steps = 0;
  std::int64_t potential_evaluations = 0;
  std::int64_t newton_iterations = 0;
  std::int64_t rejected_steps = 0;  // −1: not reported by the method
};

// A per-step record an integrator may keep (e.g. the phase and parameter coordinate of every
// step of jm-hybrid), written to /integrator/<name> of the output: `width` numbers per step.
struct StepSeries {
  std::string name;
  std::size_t width = 1;
  std::vector<double> values;  // steps × width, row-major
  std::string description;
};

class Integrator {
 public:
  virtual ~Integrator();
  virtual void start(const State& state) = 0;
  virtual void step(double t_max) = 0;
  // The time of the current state.
  virtual double time() const = 0;
  // The current state and the forces there (for output; an evaluation made only for this is
  // not counted as work).
  virtual void current(State& state, Forces& forces) = 0;
  // The current state alone (the loop's event checks after every step): by default current()
  // with scratch forces; integrators whose current() evaluates the potential override it.
  virtual void current_state(State& state);
  // Dense output inside the last step; false (the default) when the method has none.
  virtual bool interpolate(double t, State& state);
  // The fixed step h of a fixed-step method (the loop then requires whole numbers of steps
  // between outputs and reports t0 + k h exactly); 0 for methods that choose their steps.
  virtual double fixed_step() const;
  // The method's order of convergence p (its global error ~ h^p), which the run's step-halving
  // estimate of derived quantities' errors uses (Richardson: 2^p / (2^p − 1) times the change);
  // 0 (the default): not declared.
  virtual int order() const;
  // Empty when start() accepts a state that carries a tangent; else why not, in words (the
  // default: "this method has no tangent map").
  virtual std::string tangent_map_unavailable() const;
  // Sensitivities to parameters of the dynamics (masses, G, shapes; docs/derivatives.md): from
  // the next start() on, the last `parameters->size()` columns of a carried tangent are ∂z/∂p_j,
  // and each step adds the derivative of its map with respect to p_j (docs/equations.md §22).
  // Returns "" when the method does so; else why not, in words (the default: it does not).
  virtual std::string carry_parameters(std::shared_ptr<const ParameterDerivatives> parameters);
  // Forces beyond the potential (force_model.hpp; docs/equations.md §33), before the first
  // start(): the method adds them to its steps and, from a state whose force_balance has a
  // column per force, carries their balance (33.3)–(33.4) in current(), current_state() and
  // interpolate(). Returns "" when it does; else why not, in words (the default: it does not).
  virtual std::string add_forcing(std::shared_ptr<const Forcing> forcing);
  // Per-step records, if the integrator keeps any (none by default): the rows kept since the
  // last call, which the integrator then forgets (the host streams them to the output as the
  // run goes, so a long run's records never accumulate in memory).
  virtual std::vector<StepSeries> take_step_series();
  // The evaluator (the shared potential with this integrator's own workspace) the steps use:
  // the host evaluates output frames with it (the same model choices as the steps) and reports
  // what it saw (pair models). Null by default: the host then uses a workspace of its own.
  virtual PotentialEvaluator* potential_evaluator();
  // Exact continuation (`noether run --resume`, Simulation::save): the method's own variables
  // that the State does not hold, or holds only after rounding (a relative frame's coordinates,
  // a two-step form's previous step), as a fixed number of doubles for a given system; empty
  // (the default) when start(current state) continues the method exactly. restore(s, data)
  // continues from a checkpoint taken where the state was s (by default: start(s)).
  virtual std::vector<double> checkpoint() const;
  virtual void restore(const State& state, const std::vector<double>& data);
  const WorkCounters& work() const { return work_; }

 protected:
  WorkCounters work_;
};

}  // namespace noether

#pragma GCC visibility pop
