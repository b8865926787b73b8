// The scene run again at another step (half_step_run.hpp).
#include "run/half_step_run.hpp"

#include <noether/error.hpp>

#include "run/simulation_impl.hpp"

#include <cmath>
#include <cstdio>

namespace noether {

HalfStepRun rerun_scene(const Simulation::Impl& m, double step, double t_end, double output_every) {
  Params integrator = m.scene.integrator.params;
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", step);
  integrator.set("step", Params::scalar(text));
  return rerun_scene(m, integrator, t_end, output_every);
}

HalfStepRun rerun_scene(const Simulation::Impl& m, const Params& integrator, double t_end, double output_every) {
  Scene probe = m.scene;
  probe.run.t_end = t_end;
  probe.run.stm = false;  // the bodies' trajectory is compared, not its derivatives
  probe.run.sensitivities.clear();
  probe.run.chaos = false;
  probe.particles = {};  // the bodies' orbit is checked; particles add nothing to it
  probe.run.output_every = output_every;
  probe.integrator.params = integrator;
  Simulation run(probe, *m.registry, RunOptions{}, m.custom_potential ? m.potential : nullptr);
  HalfStepRun out;
  out.stop = run.integrate(t_end);
  out.end = run.state();
  out.summary = run.summary();
  return out;
}

const HalfStepRun* RunAtHalfStep::get() {
  if (!tried_) {
    tried_ = true;
    const double h = m_.integrator->fixed_step(), t0 = m_.scene.initial.t;
    const bool event = !judged_.stop_reason.empty();
    const double end = t0 + std::ceil((m_.state.t - t0) / h - 1e-9) * h + (event ? h : 0.0);
    try {
      run_ = rerun_scene(m_, h / 2, end, m_.scene.run.output_every);
    } catch (const Error&) {
      run_.reset();
    }
  }
  return run_ ? &*run_ : nullptr;
}

}  // namespace noether
