#pragma once
// The scene run again at another step, for the step-halving checks (resolution_check.cpp,
// derived_check.cpp): the bodies' trajectory alone — events on; the tangent, the chaos
// indicators and the particles off —, with the run's model (its potential when given in code).
#include <noether/simulation.hpp>

#include <optional>

namespace noether {

struct HalfStepRun {
  State end;          // where it ended
  StopInfo stop;      // why (an event, or t_end)
  RunSummary summary;  // its summary there (not judged by a check of its own)
};

// The scene from t0 at step `step` to `t_end`, a frame every `output_every`.
HalfStepRun rerun_scene(const Simulation::Impl& m, double step, double t_end, double output_every);
// The same with the integrator's parameters `integrator` (a tighter tolerance).
HalfStepRun rerun_scene(const Simulation::Impl& m, const Params& integrator, double t_end, double output_every);

// The run repeated at half its step to where it ended (on its step grid: past an event by one
// step, so that the half-step run meets it too), its frames as often as the run's (what derived
// numbers are measured from), made once for every check that asks (the resolution check's
// whole run, the derived numbers') when the run finishes.
class RunAtHalfStep {
 public:
  RunAtHalfStep(const Simulation::Impl& m, const RunSummary& judged) : m_(m), judged_(judged) {}
  // The run; null when it failed (an Error at the halved step).
  const HalfStepRun* get();

 private:
  const Simulation::Impl& m_;
  const RunSummary& judged_;
  bool tried_ = false;
  std::optional<HalfStepRun> run_;
};

}  // namespace noether
