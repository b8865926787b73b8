// The scene run again, finer (refined_run.hpp).
#include "run/refined_run.hpp"

#include <noether/error.hpp>

#include "run/event_watch.hpp"
#include "run/simulation_impl.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace noether {

namespace {

void set_number(Params& params, const char* key, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  params.set(key, Params::scalar(text));
}

}  // namespace

Rerun rerun_scene(const Simulation::Impl& m, double step, double t_end, double output_every) {
  Params integrator = m.scene.integrator.params;
  set_number(integrator, "step", step);
  return rerun_scene(m, integrator, t_end, output_every);
}

Rerun rerun_scene(const Simulation::Impl& m, const Params& integrator, double t_end, double output_every) {
  Scene probe = m.scene;
  probe.run.t_end = t_end;
  probe.run.stm = false;  // the bodies' trajectory is compared, not its derivatives
  probe.run.sensitivities.clear();
  probe.run.chaos = false;
  probe.particles = {};  // the bodies' orbit is checked; particles add nothing to it
  probe.run.output_every = output_every;
  probe.integrator.params = integrator;
  Simulation run(probe, *m.registry, RunOptions{}, m.custom_potential ? m.potential : nullptr);
  Rerun out;
  out.stop = run.integrate(t_end);
  out.end = run.state();
  out.summary = run.summary();
  return out;
}

double integrator_tolerance(const Simulation::Impl& m, const std::string& key) {
  const Params& given = m.scene.integrator.params;
  if (given.has(key)) return given.at(key).as_double();
  for (const ParamDoc& doc : m.registry->info(m.scene.integrator.plugin).params)
    if (doc.name == key && doc.default_value && doc.default_value[0] != '(') return std::stod(doc.default_value);
  return std::numeric_limits<double>::quiet_NaN();
}

RefinedRun::RefinedRun(const Simulation::Impl& m, const RunSummary& judged) : m_(m), judged_(judged) {
  const std::string& plugin = m.scene.integrator.plugin;
  if (!m.scene_trajectory) {
    why_not_ = "the run does not start from its scene (a state was set, or it was loaded)";
    return;
  }
  if (!judged.stop_reason.empty() && !is_event(judged.stop_reason)) {
    why_not_ = "the run was interrupted";
    return;
  }
  if (!m.registry) {
    why_not_ = "the run has no plugin registry to repeat it with";
    return;
  }
  const double limit = m.scene.run.rerun_seconds;
  if (!(limit > 0.0)) {
    why_not_ = "run.rerun_seconds is 0: the run is not repeated";
    return;
  }
  if (judged.wall_seconds > limit) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the run took %.3g s, more than the %.3g s up to which it is repeated finer (run.rerun_seconds)",
                  judged.wall_seconds, limit);
    why_not_ = text;
    return;
  }
  Refinement r;
  r.order = m.integrator->order();
  if (m.integrator->fixed_step() > 0) {
    if (!m.scene.integrator.params.has("step")) {
      why_not_ = "integrator '" + plugin + "' takes a fixed step the scene does not set: there is no step to halve";
      return;
    }
    r.step = m.integrator->fixed_step();
  } else {
    r.rtol = integrator_tolerance(m, "rtol");
    r.atol = integrator_tolerance(m, "atol");
    if (!(r.rtol > 0)) {
      why_not_ = "integrator '" + plugin + "' chooses its own steps and has no tolerance (rtol) to tighten";
      return;
    }
    r.tolerance_factor = r.rtol / 10 >= 1e-14 ? 0.1 : 10.0;
  }
  refinement_ = r;
}

const Rerun* RefinedRun::get() {
  if (!tried_ && refinement_) {
    tried_ = true;
    const Refinement& r = *refinement_;
    const double t0 = m_.scene.initial.t;
    const bool event = !judged_.stop_reason.empty();
    try {
      if (r.step > 0) {
        const double h = r.step;
        const double end = t0 + std::ceil((m_.state.t - t0) / h - 1e-9) * h + (event ? h : 0.0);
        run_ = rerun_scene(m_, h / 2, end, m_.scene.run.output_every);
      } else {
        Params integrator = m_.scene.integrator.params;
        set_number(integrator, "rtol", r.rtol * r.tolerance_factor);
        if (r.atol > 0) set_number(integrator, "atol", r.atol * r.tolerance_factor);
        run_ = rerun_scene(m_, integrator, event ? std::max(m_.scene.run.t_end, m_.state.t) : m_.state.t,
                           m_.scene.run.output_every);
      }
    } catch (const Error&) {
      run_.reset();
    }
  }
  return run_ ? &*run_ : nullptr;
}

}  // namespace noether
