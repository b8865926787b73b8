#pragma once
// Integrator: advances a State of a System to a time, calling an Observer at the requested
// output times. Reports its work and fails with an IntegrationError, never with a silently
// wrong state.
#include <noether/export.hpp>
#include <noether/forces.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace noether {

struct WorkCounters {
  std::int64_t steps = 0;
  std::int64_t potential_evaluations = 0;
  std::int64_t newton_iterations = 0;
  std::int64_t rejected_steps = 0;
};

class NOETHER_API Observer {
 public:
  virtual ~Observer() = default;
  // Called at t0 and at every output time, with the potential evaluated at that state.
  virtual void observe(const State& state, const Forces& forces) = 0;
};

// A per-step record an integrator may keep (e.g. the phase and parameter coordinate of every
// step of jm-hybrid), written to /integrator/<name> of the output: `width` numbers per step.
struct StepSeries {
  std::string name;
  std::size_t width = 1;
  std::vector<double> values;  // steps × width, row-major
  std::string description;
};

struct OutputSchedule {
  double t_end = 0.0;         // integrate from state.t to t_end
  double output_every = 0.0;  // observer interval; the observer also sees t0 and t_end
};

class NOETHER_API Integrator {
 public:
  virtual ~Integrator() = default;
  // Advances `state` to schedule.t_end, or to an event that ends the run early (then
  // stop_reason() says which). On IntegrationError, `state` holds the last valid state (at
  // e.t_reached()).
  virtual void integrate(State& state, const OutputSchedule& schedule, Observer& observer) = 0;
  const WorkCounters& work() const { return work_; }
  // Empty when the run reached t_end; otherwise the event that stopped it (e.g. a close
  // approach found by root finding).
  const std::string& stop_reason() const { return stop_reason_; }
  // Per-step records, if the integrator keeps any (empty by default).
  virtual std::vector<StepSeries> step_series() const { return {}; }

 protected:
  WorkCounters work_;
  std::string stop_reason_;
};

// For fixed-step methods: the number of steps of size h in `interval`. Throws SceneError
// (naming `plugin` and `what`) when the interval is not a whole number of steps.
std::int64_t whole_steps(double interval, double h, const char* what, const char* plugin);

// For adaptive methods: the output times from t0, t0 + Δ, t0 + 2Δ, ..., and t_end.
std::vector<double> output_times(double t0, double t_end, double output_every);

}  // namespace noether
