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

struct OutputSchedule {
  double t_end = 0.0;         // integrate from state.t to t_end
  double output_every = 0.0;  // observer interval; the observer also sees t0 and t_end
};

class NOETHER_API Integrator {
 public:
  virtual ~Integrator() = default;
  // Advances `state` to schedule.t_end. On IntegrationError, `state` holds the last valid
  // state (at e.t_reached()).
  virtual void integrate(State& state, const OutputSchedule& schedule, Observer& observer) = 0;
  const WorkCounters& work() const { return work_; }

 protected:
  WorkCounters work_;
};

}  // namespace noether
