#pragma once
// The scene run again, finer, for the checks of a finished run (resolution_check.cpp,
// derived_check.cpp): at half its step (a fixed-step method) or at a tenfold tighter tolerance
// (a method that chooses its steps; tenfold looser where rtol / 10 is below what double precision
// meets) — the bodies' trajectory alone (events on; the tangent, the chaos indicators and the
// particles off), with the run's model (its potential when given in code).
#include <noether/simulation.hpp>

#include <optional>
#include <string>

namespace noether {

struct Rerun {
  State end;          // where it ended
  StopInfo stop;      // why (an event, or t_end)
  RunSummary summary;  // its summary there (not judged by a check of its own)
};

// The scene from t0 at step `step` to `t_end`, a frame every `output_every`.
Rerun rerun_scene(const Simulation::Impl& m, double step, double t_end, double output_every);
// The same with the integrator's parameters `integrator` (another tolerance).
Rerun rerun_scene(const Simulation::Impl& m, const Params& integrator, double t_end, double output_every);

// The integrator's tolerance `key` ("rtol", "atol"): the scene's, or the plugin's documented
// default; NaN when it has none.
double integrator_tolerance(const Simulation::Impl& m, const std::string& key);

// How a finished run is repeated (DerivedError: the same numbers, public).
struct Refinement {
  double step = 0.0;              // h of a fixed-step method (halved), else 0
  double rtol = 0.0, atol = 0.0;  // the tolerances of one that chooses its steps
  double tolerance_factor = 0.0;  // what they are multiplied by: 0.1, or 10 where rtol / 10 < 1e-14
  int order = 0;                  // the method's declared order p (0: none)
};

// The run repeated finer to where it ended (a fixed step: on its step grid, past an event by one
// step, so that the finer run meets it too; a tolerance: to t_end past an event, where the finer
// run stops at its own), its frames as often as the run's (what derived numbers are measured
// from), made once for every check that asks (the resolution check's whole run, the derived
// numbers') when the run finishes — a run that took at most run.rerun_seconds, from its scene's
// initial state, not interrupted.
class RefinedRun {
 public:
  RefinedRun(const Simulation::Impl& m, const RunSummary& judged);
  // How it is repeated; null when it is not (why_not says why).
  const Refinement* refinement() const { return refinement_ ? &*refinement_ : nullptr; }
  const std::string& why_not() const { return why_not_; }
  // The run; null when it is not repeated or failed (an Error at the finer step or tolerance).
  const Rerun* get();

 private:
  const Simulation::Impl& m_;
  const RunSummary& judged_;
  std::optional<Refinement> refinement_;
  std::string why_not_;
  bool tried_ = false;
  std::optional<Rerun> run_;
};

}  // namespace noether
