// Ensembles (docs/ensembles.md): samples drawn from (seed, index), run on a pool of threads, each
// result written at its index by the main thread.
#include <noether/ensemble.hpp>
#include <noether/error.hpp>
#include <noether/orbital_elements.hpp>
#include <noether/simulation.hpp>

#include "ensemble/ensemble_file.hpp"
#include "run/spin_state_tracker.hpp"

#include <algorithm>
#include <atomic>
#include <functional>
#include <limits>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <fcntl.h>
#include <mutex>
#include <sstream>
#include <sys/file.h>
#include <thread>
#include <unistd.h>

namespace noether {
using Clock = std::chrono::steady_clock;
using detail::EnsembleFile;
using detail::override_of;

EnsemblePlan::EnsemblePlan(const std::filesystem::path& scene_file, std::vector<std::string> overrides_given,
                           EnsembleOptions options_given)
    : overrides(std::move(overrides_given)), options(std::move(options_given)) {
  if (options.vary.empty()) throw SceneError("ensemble: nothing varies; give at least one --vary KEY=DISTRIBUTION");
  const std::size_t grid = grid_size(options.vary);
  samples = options.samples;
  const bool has_grid = std::any_of(options.vary.begin(), options.vary.end(),
                                    [](const Variation& v) { return v.kind == Variation::Kind::Grid; });
  if (samples == 0) {
    if (!has_grid) throw SceneError("ensemble: --samples N is needed (only grids give their own number of samples)");
    samples = grid;
  }
  if (has_grid && samples % grid != 0)
    throw SceneError("ensemble: --samples " + std::to_string(samples) + " is not a multiple of the grids' " +
                     std::to_string(grid) + " points");
  // The scene and every key checked before anything runs: sample 0's scene is built.
  base = load_scene(scene_file, overrides);
  try {
    (void)parse_scene(base.text, base.file, sample_overrides(0));
  } catch (const SceneError& e) {  // a varied key's error names --vary, not the --set it becomes
    std::string what = e.what();
    for (const auto& v : options.vary)
      if (what.rfind("--set " + v.key, 0) == 0) throw SceneError("--vary" + what.substr(5));
    throw;
  }
  if (!options.pair.empty()) {
    const auto comma = options.pair.find(',');
    if (comma == std::string::npos) throw SceneError("--pair '" + options.pair + "': expected two body names, a,b");
    auto find = [&](const std::string& name) {
      for (std::size_t i = 0; i < base.system.size(); ++i)
        if (base.system.body(i).name == name) return i;
      throw SceneError("--pair: the scene has no body '" + name + "'");
    };
    pair_a = find(options.pair.substr(0, comma));
    pair_b = find(options.pair.substr(comma + 1));
  } else if (base.system.size() < 2) {
    pair_b = 0;
  }
}

std::vector<std::string> EnsemblePlan::sample_overrides(std::size_t i) const {
  std::vector<std::string> out = overrides;
  const auto values = sample_values(options.vary, options.seed, i);
  for (std::size_t k = 0; k < options.vary.size(); ++k) out.push_back(override_of(options.vary[k], values[k]));
  return out;
}

std::filesystem::path sample_run_path(const std::filesystem::path& ensemble, std::size_t i) {
  return ensemble.parent_path() / (ensemble.stem().string() + "-sample-" + std::to_string(i) + ".h5");
}

SampleResult EnsemblePlan::run(std::size_t i, PluginRegistry& registry, const std::filesystem::path& output) const {
  SampleResult r;
  r.summary.assign(detail::summary_columns().size(), NAN);
  const auto t0 = Clock::now();
  try {
    RunOptions run;
    run.threads = 1;  // the samples are the ensemble's parallelism: one thread each
    if (i < options.trajectories) {
      run.output = sample_run_path(output, i);
      run.overwrite = true;
    }
    Simulation sim(parse_scene(base.text, base.file, sample_overrides(i)), registry, run);
    r.setup = std::chrono::duration<double>(Clock::now() - t0).count();
    try {
      sim.integrate(sim.scene().run.t_end);
    } catch (const IntegrationError& e) {
      r.outcome = 2;
      r.message = e.what();
    }
    const RunSummary s = sim.finish();
    if (r.outcome < 0) {
      r.outcome = s.stop_reason.empty() ? 0 : 1;
      r.message = s.stop_reason;
    }
    // A sample that finished but cannot be trusted (run.trust) says so, as `noether run` does.
    r.trustworthy = r.outcome == 2 ? -1 : s.verdict.trustworthy ? 1 : 0;
    if (r.trustworthy == 0) {
      std::string reasons;
      for (const auto& why : s.verdict.reasons) reasons += (reasons.empty() ? "" : "; ") + why;
      r.message += (r.message.empty() ? "" : "; ") + ("untrustworthy: " + reasons);
    }
    r.summary.clear();
    for (const detail::SummaryRow* column : detail::summary_columns()) r.summary.push_back(column->number(s));
    r.final_state = s.final_state;
    r.indicators = detail::indicator_values(sim.scene(), s);
    if (pair_a != pair_b) {
      const System& sys = sim.scene().system;
      const auto A = static_cast<Eigen::Index>(pair_a), B = static_cast<Eigen::Index>(pair_b);
      const double ma = sys.body(pair_a).mass, mb = sys.body(pair_b).mass, mu = sys.G() * (ma + mb);
      const RelativeState rel{s.final_state.x.col(B) - s.final_state.x.col(A),
                              s.final_state.p.col(B) / mb - s.final_state.p.col(A) / ma};
      try {
        const OrbitalElements el = elements_from_state(rel, mu);
        r.a = el.a, r.e = el.e, r.period = 2 * M_PI * std::sqrt(el.a * el.a * el.a / mu);
      } catch (const std::domain_error&) {  // unbound: NaN
      }
    }
  } catch (const Error& e) {  // a sample's scene or plugin refused: recorded, the rest go on
    r.outcome = 2;
    r.message = e.what();
  } catch (const std::exception& e) {
    r.outcome = 2;
    r.message = std::string("unexpected error: ") + e.what();
  }
  r.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

namespace detail {

namespace {
// The spin states a run of the scene reports, with no values yet (the bodies and their binary).
std::vector<SpinState> spin_state_template(const Scene& scene) { return SpinStateTracker(scene.system).spin_states(); }
}  // namespace

std::vector<Indicator> ensemble_indicators(const Scene& scene) {
  std::vector<Indicator> out;
  if (scene.run.chaos) {
    const std::string per_time = scene.units.declared ? "1/" + scene.units.of_time() : "1/time";
    out.insert(out.end(), {{"megno", "1"}, {"fli", "1"}, {"lyapunov", per_time}});
  }
  const std::string time = scene.units.declared ? scene.units.of_time() : "time";
  for (const SpinState& spin : spin_state_template(scene)) {
    if (!spin.other.empty())
      out.insert(out.end(), {{spin.body + ".libration_amplitude", "deg"}, {spin.body + ".libration_period", time},
                             {spin.body + ".turns", "1"}, {spin.body + ".max_pitch", "deg"},
                             {spin.body + ".max_roll", "deg"}});
    out.insert(out.end(), {{spin.body + ".max_nutation", "deg"}, {spin.body + ".spin_period", time}});
  }
  return out;
}

std::vector<double> indicator_values(const Scene& scene, const RunSummary& s) {
  std::vector<double> out;
  if (scene.run.chaos) out.insert(out.end(), {s.chaos_values.megno, s.chaos_values.fli, s.chaos_values.lyapunov});
  std::vector<SpinState> spins = s.spin_states;
  if (spins.size() != scene.system.rigid_count()) spins = spin_state_template(scene);  // a run that never started
  for (const SpinState& spin : spins) {
    if (!spin.other.empty())
      out.insert(out.end(),
                 {spin.libration_amplitude, spin.libration_period, spin.turns, spin.max_pitch, spin.max_roll});
    out.insert(out.end(), {spin.max_nutation, spin.spin_period});
  }
  return out;
}

}  // namespace detail

std::vector<double> SampleResult::pack() const {
  std::vector<double> out{static_cast<double>(outcome), static_cast<double>(trustworthy), a, e, period, wall, setup};
  out.insert(out.end(), summary.begin(), summary.end());
  out.push_back(static_cast<double>(indicators.size()));
  out.insert(out.end(), indicators.begin(), indicators.end());
  out.push_back(static_cast<double>(final_state.x.cols()));
  out.push_back(static_cast<double>(final_state.R.size()));
  out.push_back(final_state.t);
  out.insert(out.end(), final_state.x.data(), final_state.x.data() + final_state.x.size());
  out.insert(out.end(), final_state.p.data(), final_state.p.data() + final_state.p.size());
  for (const auto& R : final_state.R) out.insert(out.end(), R.data(), R.data() + 9);
  out.insert(out.end(), final_state.Pi.data(), final_state.Pi.data() + final_state.Pi.size());
  return out;
}

SampleResult SampleResult::unpack(const std::vector<double>& in, std::string message) {
  SampleResult r;
  std::size_t k = 0;
  auto next = [&] {
    if (k >= in.size()) throw Error("ensemble: a sample's result arrived truncated");
    return in[k++];
  };
  r.outcome = static_cast<std::int8_t>(next());
  r.trustworthy = static_cast<std::int8_t>(next());
  r.a = next(), r.e = next(), r.period = next(), r.wall = next(), r.setup = next();
  for (std::size_t j = 0; j < detail::summary_columns().size(); ++j) r.summary.push_back(next());
  const auto indicators = static_cast<std::size_t>(next());
  for (std::size_t j = 0; j < indicators; ++j) r.indicators.push_back(next());
  const auto nb = static_cast<Eigen::Index>(next()), nr = static_cast<Eigen::Index>(next());
  r.final_state.t = next();
  r.final_state.x.resize(3, nb);
  r.final_state.p.resize(3, nb);
  r.final_state.Pi.resize(3, nr);
  for (Eigen::Index j = 0; j < 3 * nb; ++j) r.final_state.x.data()[j] = next();
  for (Eigen::Index j = 0; j < 3 * nb; ++j) r.final_state.p.data()[j] = next();
  r.final_state.R.resize(static_cast<std::size_t>(nr));
  for (auto& R : r.final_state.R)
    for (int j = 0; j < 9; ++j) R.data()[j] = next();
  for (Eigen::Index j = 0; j < 3 * nr; ++j) r.final_state.Pi.data()[j] = next();
  r.message = std::move(message);
  return r;
}

EnsembleReport run_ensemble(const std::filesystem::path& scene_file, const std::vector<std::string>& overrides,
                            const EnsembleOptions& options, const std::filesystem::path& output,
                            const std::function<void(std::size_t, std::size_t)>& progress, RemoteWorkers* remote) {
  const auto start = Clock::now();
  const EnsemblePlan plan(scene_file, overrides, options);
  const std::size_t samples = plan.samples;
  EnsembleFile file(output, plan.base, plan.base.text, overrides, options, samples, plan.pair_a, plan.pair_b);

  EnsembleReport report;
  report.samples = samples;
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < samples; ++i)
    if (!file.done(i)) todo.push_back(i);
  report.skipped = samples - todo.size();
  unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, todo.size())));
  report.threads = threads;
  report.ranks = remote ? remote->count() + 1 : 1;

  // One dispenser of sample indices for the local threads and the remote workers alike (dynamic
  // distribution: runs may differ in length by orders of magnitude).
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<std::pair<std::size_t, SampleResult>> finished;
  std::atomic<unsigned> running{threads};
  auto worker = [&] {
    PluginRegistry registry;  // one per thread: nothing shared but the immutable plugin code
    for (;;) {
      const std::size_t t = next.fetch_add(1);
      if (t >= todo.size()) break;
      const std::size_t i = todo[t];
      SampleResult r = plan.run(i, registry, output);
      {
        std::lock_guard<std::mutex> lock(mutex);
        finished.emplace_back(i, std::move(r));
      }
      ready.notify_one();
    }
    running.fetch_sub(1);
    ready.notify_one();
  };
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < threads; ++k) pool.emplace_back(worker);

  // The main thread writes: each result at its index, committed every 50 ms at most (two
  // flushes: a few milliseconds), so a kill loses at most that much work. It also serves the
  // remote workers.
  auto last_commit = Clock::now();
  std::size_t written = 0, remote_busy = 0, remote_stopped = 0;
  const std::size_t remotes = remote ? remote->count() : 0;
  std::vector<std::pair<std::size_t, SampleResult>> arrived;
  std::vector<int> idle;
  for (;;) {
    std::deque<std::pair<std::size_t, SampleResult>> batch;
    {
      std::unique_lock<std::mutex> lock(mutex);
      ready.wait_for(lock, std::chrono::milliseconds(remote ? 1 : 200),
                     [&] { return !finished.empty() || running.load() == 0; });
      batch.swap(finished);
    }
    if (remote) {
      arrived.clear();
      idle.clear();
      remote->poll(arrived, idle);
      for (auto& item : arrived) {
        batch.push_back(std::move(item));
        --remote_busy;
      }
      for (int w : idle) {
        const std::size_t t = next.fetch_add(1);
        if (t < todo.size()) {
          remote->assign(w, todo[t]);
          ++remote_busy;
        } else {
          remote->assign(w, RemoteWorkers::kNone);
          ++remote_stopped;
        }
      }
    }
    for (auto& [i, r] : batch) {
      file.write(i, sample_values(options.vary, options.seed, i), options.vary, r);
      ++written;
      (r.outcome == 0 ? report.completed : r.outcome == 1 ? report.stopped : report.failed) += 1;
      if (r.trustworthy == 0) ++report.untrustworthy;
      report.sample_seconds += r.wall;
      report.setup_seconds += r.setup;
    }
    if (!batch.empty() && std::chrono::duration<double>(Clock::now() - last_commit).count() >= 0.05) {
      file.commit();
      last_commit = Clock::now();
      if (progress) progress(report.skipped + written, samples);
    }
    if (running.load() == 0 && remote_busy == 0 && remote_stopped == remotes) {
      std::lock_guard<std::mutex> lock(mutex);
      if (finished.empty()) break;
    }
  }
  for (auto& t : pool) t.join();
  file.commit();
  report.run = written;
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

}  // namespace noether
