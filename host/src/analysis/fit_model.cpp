// The model a fit compares with observations: one run of the scene with its sensitivities to the
// free keys, sampled where the observations need it (docs/equations.md §28).
#include "io/json_text.hpp"
#include "scene/scene_sensitivity.hpp"

#include <noether/conjunction.hpp>
#include <noether/error.hpp>
#include <noether/fit.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>
#include <noether/trajectory.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

namespace noether {

namespace {

// "file:line" of an observation, for messages.
std::string where_of(const std::string& file, const Observation& o) {
  return (file.empty() ? std::string("observation") : file) + ":" + std::to_string(o.line);
}

// A frame of the run: positions and velocities, with their derivatives (28.1):
//     ∂x/∂p from the tangent's position rows, ∂v/∂p = (∂γ/∂p − v ∂m/∂p) / m.
void record(Trajectory& trajectory, const Simulation& sim, const Eigen::MatrixXd& dm) {
  const State& s = sim.state();
  const System& system = sim.scene().system;
  const auto n = static_cast<Eigen::Index>(system.size()), r = static_cast<Eigen::Index>(system.rigid_count());
  const Eigen::Index P = dm.cols();
  if (s.tangent.cols() != P) throw Error("a fit's run carries " + std::to_string(s.tangent.cols()) +
                                         " tangent columns, not its " + std::to_string(P) + " sensitivities");
  Eigen::Matrix3Xd v(3, n);
  Eigen::MatrixXd dx = s.tangent.topRows(3 * n), dv(3 * n, P);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double m = system.body(static_cast<std::size_t>(j)).mass;
    v.col(j) = s.p.col(j) / m;
    dv.middleRows(3 * j, 3) =
        (s.tangent.middleRows(3 * n + 3 * r + 3 * j, 3) - v.col(j) * dm.row(j)) / m;  // (28.1)
  }
  trajectory.append(s.t, s.x, v, dx, dv);
}

}  // namespace

Prediction predict(const std::string& scene_file, const std::vector<std::string>& overrides,
                   const std::vector<Observation>& observations, const std::vector<std::string>& free,
                   PluginRegistry& registry, const std::string& observations_file) {
  if (observations.empty()) throw SceneError("a fit needs observations");
  const Scene base = load_scene(scene_file, overrides);
  const double t0 = base.initial.t;
  double t_last = t0;
  for (const auto& o : observations) {
    if (o.observable.is_lightcurve())
      throw SceneError(where_of(observations_file, o) + ": " + observable_name(o.observable.kind) +
                       " cannot be fitted yet (its derivatives through the attitudes are not computed); fit "
                       "positions, sky offsets, ranges or range rates");
    if (!(o.t >= t0))
      throw SceneError(where_of(observations_file, o) + ": t = " + detail::exact_text(o.t) + " is before the run starts (t0 = " +
                       detail::exact_text(t0) + ")");
    // An event time is the model's event nearest to the row's t (30.1): the run goes on a tenth
    // of its span past it, so that the nearest event is in the run — to an output time (a whole
    // number of a fixed-step method's steps).
    if (o.observable.is_event_time()) {
      const double every = base.run.output_every, need = std::max(o.t, o.value) * 1.1 - 0.1 * t0;
      t_last = std::max(t_last, every > 0 ? t0 + std::ceil((need - t0) / every) * every : need);
    } else {
      t_last = std::max(t_last, o.t);
    }
  }
  if (!(t_last > t0)) throw SceneError("a fit needs an observation after the run's start (t0 = " + detail::exact_text(t0) + ")");
  // The scene runs to the last observation, with the sensitivities to the free keys only.
  std::string keys;
  for (const auto& k : free) keys += (keys.empty() ? "" : ", ") + k;
  std::vector<std::string> as_run = overrides;
  for (const std::string& o : {"run.t_end=" + detail::exact_text(t_last), std::string("run.stm=false"),
                               std::string("run.chaos=false"), "run.sensitivities=[" + keys + "]"})
    as_run.push_back(o);
  std::unique_ptr<Simulation> sim;
  try {
    sim = std::make_unique<Simulation>(load_scene(scene_file, as_run), registry);
  } catch (const SceneError& e) {  // a key that cannot be varied: named by run.sensitivities' message
    std::string what = e.what();
    const std::string prefix = "run.sensitivities: ";
    if (what.compare(0, prefix.size(), prefix) == 0) what = "--free " + what.substr(prefix.size());
    throw SceneError(what);
  }
  const Scene& scene = sim->scene();
  const Eigen::MatrixXd dm = sim->mass_sensitivities();

  // Where to sample: each impulse, the observations the method can stop at, the output times —
  // a time within 1e-9 of the span of one already taken is the same time (the first kept).
  const double every = scene.run.output_every, h = sim->fixed_step(), same = 1e-9 * (t_last - t0);
  std::set<double> times, impulse_times;
  auto take = [&](double t) {
    const auto next = times.lower_bound(t - same);
    if (next == times.end() || *next > t + same) times.insert(t);
  };
  for (const auto& impulse : scene.impulses)
    if (impulse.time > t0 && impulse.time <= t_last) {
      take(impulse.time);
      impulse_times.insert(impulse.time);
    }
  for (const auto& o : observations) {
    if (o.t <= t0 || o.observable.is_event_time()) continue;
    if (h > 0) {
      const double steps = std::round((o.t - t0) / h);
      if (std::abs(steps * h - (o.t - t0)) > 1e-9 * (o.t - t0)) continue;  // between steps: interpolated
    }
    take(o.t);
  }
  take(t_last);
  for (std::int64_t k = 1;; ++k) {
    const double t = t0 + static_cast<double>(k) * every;
    if (!(t < t_last)) break;
    take(t);
  }

  Trajectory trajectory;
  for (std::size_t j = 0; j < scene.system.size(); ++j) {
    trajectory.names.push_back(scene.system.body(j).name);
    trajectory.masses.push_back(scene.system.body(j).mass);
  }
  record(trajectory, *sim, dm);
  for (double t : times) {
    const bool impulse = impulse_times.count(t) > 0;
    const StopInfo stop = sim->integrate(t, !impulse);
    if (!stop.event.empty()) {
      std::ostringstream why;
      why.precision(10);
      why << "the run stopped at t = " << sim->time() << " (" << stop.reason << "), before the last observation (t = "
          << t_last << "); a fit needs the whole span";
      throw IntegrationError(why.str(), 0);
    }
    record(trajectory, *sim, dm);
    if (impulse) {  // the state just before the impulse is recorded; now the one after it
      sim->integrate(t, true);
      record(trajectory, *sim, dm);
    }
  }

  // Each observation: the sampled r, u and their derivatives, and the observable's gradient (28.2).
  Prediction out;
  out.verdict = sim->finish().verdict;
  out.names = sim->sensitivity_names();
  const auto N = static_cast<Eigen::Index>(observations.size()), P = static_cast<Eigen::Index>(out.names.size());
  out.values.resize(N);
  out.jacobian.resize(N, P);
  Eigen::Matrix3Xd x, v;
  Eigen::MatrixXd dx, dv;
  // The conjunctions of each pair and line of sight the event rows name, found once (30.1).
  struct Events {
    std::size_t target, center;
    Eigen::Vector3d line_of_sight;
    std::vector<Conjunction> all;
  };
  std::vector<Events> events;
  auto events_of = [&](const Observable& e) -> const std::vector<Conjunction>& {
    for (const auto& known : events)
      if (known.target == e.target && known.center == e.center && known.line_of_sight == e.line_of_sight)
        return known.all;
    events.push_back({e.target, e.center, e.line_of_sight, conjunctions(trajectory, e.target, e.center, e.line_of_sight)});
    return events.back().all;
  };
  for (Eigen::Index i = 0; i < N; ++i) {
    const Observation& o = observations[static_cast<std::size_t>(i)];
    if (o.observable.is_event_time()) {  // (30.1), (30.2)
      try {
        const Conjunction c =
            nearest_conjunction(events_of(o.observable), trajectory, o.observable.target, o.observable.center, o.t);
        out.values[i] = c.t;
        out.jacobian.row(i) = c.dt_dp;
      } catch (const SceneError& e) {
        throw SceneError(where_of(observations_file, o) + ": " + e.what());
      }
      continue;
    }
    try {
      trajectory.sample(o.t, x, v, dx, dv);
    } catch (const SceneError& e) {
      throw SceneError(where_of(observations_file, o) + ": " + e.what());
    }
    const auto a = static_cast<Eigen::Index>(o.observable.target), b = static_cast<Eigen::Index>(o.observable.center);
    const ObservableValue value = evaluate(o.observable, x.col(a) - x.col(b), v.col(a) - v.col(b));
    out.values[i] = value.value;
    out.jacobian.row(i) = value.d_r.transpose() * (dx.middleRows(3 * a, 3) - dx.middleRows(3 * b, 3)) +
                          value.d_u.transpose() * (dv.middleRows(3 * a, 3) - dv.middleRows(3 * b, 3));
  }
  return out;
}

}  // namespace noether
