// The step-halving check of an orbit the energy cannot certify (docs/user-guide.md, "Verdict"):
// a small body's orbital energy is lost in the large bodies' (a spacecraft's 0.03 J against a
// binary's 1e10 J), so the run's energy error says nothing about it. Instead the scene is
// integrated over one period of that orbit twice, at the run's step h and at h/2, and the
// orbit's relative position compared: for a method of order p the difference is the error at h
// times (1 − 2^−p), an estimate of it that does not depend on what perturbs the orbit.
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "simulation_impl.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace noether {

ResolutionCheck check_resolution(const Simulation::Impl& m, const RunSummary& judged) {
  ResolutionCheck check;
  const Scene& scene = m.scene;
  const double h = m.integrator->fixed_step();
  if (judged.orbits.empty() || !(h > 0) || !m.registry || !judged.stop_reason.empty() ||
      !scene.integrator.params.has("step"))
    return check;
  // Only an orbit the energy cannot certify (as judge() found it).
  const OrbitScale& orbit = judged.orbits.front();
  if (!orbit.uncertified) return check;

  // One period of the orbit at t0 (vis-viva; an unbound pair: the time to cross its separation),
  // in whole steps, no longer than the run.
  const System& system = scene.system;
  const int body = system.index_of(orbit.body), about = system.index_of(orbit.about);
  if (body < 0 || about < 0) return check;
  const auto b = static_cast<std::size_t>(body), a = static_cast<std::size_t>(about);
  const State& initial = scene.initial;
  const double M = system.G() * (system.body(a).mass + system.body(b).mass);
  const Vec3 r = initial.x.col(static_cast<Eigen::Index>(b)) - initial.x.col(static_cast<Eigen::Index>(a));
  const Vec3 v = initial.p.col(static_cast<Eigen::Index>(b)) / system.body(b).mass -
                 initial.p.col(static_cast<Eigen::Index>(a)) / system.body(a).mass;
  const double inverse_a = 2.0 / r.norm() - v.squaredNorm() / M;
  const double period = inverse_a > 0 ? 2 * std::numbers::pi * std::sqrt(1.0 / (inverse_a * inverse_a * inverse_a) / M)
                                      : r.norm() / std::max(v.norm(), 1e-300);
  const double run_length = m.state.t - initial.t;
  const double steps = std::max(2.0, std::ceil(std::min(period, run_length) / h));
  if (!std::isfinite(steps) || steps > 1e9) return check;
  const double window = steps * h;

  Scene probe = scene;
  probe.run.t_end = initial.t + window;
  probe.run.output_every = window;
  Vec3 relative[2];
  try {
    for (int k = 0; k < 2; ++k) {
      char step[32];
      std::snprintf(step, sizeof step, "%.17g", h / (k + 1));
      probe.integrator.params.set("step", Params::scalar(step));
      Simulation run(probe, *m.registry, RunOptions{}, m.custom_potential ? m.potential : nullptr);
      const StopInfo stop = run.integrate(probe.run.t_end);
      if (!stop.reason.empty()) return check;  // an event inside the window: no comparison
      const State& end = run.state();
      relative[k] = end.x.col(static_cast<Eigen::Index>(b)) - end.x.col(static_cast<Eigen::Index>(a));
    }
  } catch (const Error&) {  // the halved step failed too: the energy's verdict stands
    return check;
  }
  check.done = true;
  check.body = orbit.body;
  check.about = orbit.about;
  check.window = window;
  check.per_window = (relative[0] - relative[1]).norm() / relative[0].norm();
  check.over_run = check.per_window * std::max(1.0, run_length / window);
  return check;
}

}  // namespace noether
