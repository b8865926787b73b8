#include <noether/error.hpp>
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <unistd.h>

namespace noether {

namespace {

using Clock = std::chrono::steady_clock;

// Prints "t = … / t_end (…%)" on stderr once a run has taken a few seconds: in place on a
// terminal, as a line every ten seconds otherwise.
class Progress {
 public:
  Progress(bool enabled, double t0, double t_end)
      : enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0), t0_(t0), t_end_(t_end) {}
  void update(double t) {
    if (!enabled_) return;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double interval = tty_ ? 0.5 : 10.0;
    if (elapsed < 3.0 || std::chrono::duration<double>(now - last_).count() < interval) return;
    last_ = now;
    const double fraction = (t - t0_) / (t_end_ - t0_);
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "%st = %.6g / %.6g (%3.0f%%), %.1f s elapsed, about %.1f s left%s",
                 tty_ ? "\r" : "", t, t_end_, 100.0 * fraction, elapsed, eta, tty_ ? "" : "\n");
    printed_ = true;
  }
  ~Progress() {
    if (printed_ && tty_) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_, tty_;
  double t0_, t_end_;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
  bool printed_ = false;
};

class RunObserver final : public Observer {
 public:
  RunObserver(const System& system, RunSummary& summary, H5Writer* writer,
              const Integrator*& integrator)
      : system_(system), s_(summary), writer_(writer), integrator_(integrator) {}

  void observe(const State& state, const Forces& forces) override {
    const Diagnostics d = diagnose(system_, state, forces.U);
    // A non-finite energy or state is a failure, never a number in the summary (std::max
    // would drop a NaN silently).
    if (!std::isfinite(d.energy) || !state.x.allFinite() || !state.p.allFinite() || !state.Pi.allFinite()) {
      std::ostringstream msg;
      msg << "the " << (std::isfinite(d.energy) ? "state" : "energy") << " became non-finite at t = " << state.t
          << " (the integrator diverged: a smaller step or tolerance?)";
      throw IntegrationError(msg.str(), state.t);
    }
    if (s_.frames == 0) {
      s_.initial = d;
      // Scales for the relative momentum errors: the sum of the magnitudes of the parts.
      for (Eigen::Index i = 0; i < state.p.cols(); ++i) {
        p_scale_ += state.p.col(i).norm();
        L_scale_ += Vec3(state.x.col(i)).cross(Vec3(state.p.col(i))).norm();
      }
      for (Eigen::Index k = 0; k < state.Pi.cols(); ++k) L_scale_ += state.Pi.col(k).norm();
      s_.min_distance = std::numeric_limits<double>::infinity();
    }
    s_.final = d;
    s_.max_abs_energy_error = std::max(s_.max_abs_energy_error, std::abs(d.energy - s_.initial.energy));
    if (p_scale_ > 0)
      s_.max_rel_linear_momentum_error = std::max(
          s_.max_rel_linear_momentum_error, (d.linear_momentum - s_.initial.linear_momentum).norm() / p_scale_);
    if (L_scale_ > 0)
      s_.max_rel_angular_momentum_error =
          std::max(s_.max_rel_angular_momentum_error,
                   (d.angular_momentum - s_.initial.angular_momentum).norm() / L_scale_);
    s_.max_orthogonality_error = std::max(s_.max_orthogonality_error, d.orthogonality_error);
    if (state.x.cols() <= 64)  // closest approach of centres, O(n²): small scenes only
      for (Eigen::Index i = 0; i < state.x.cols(); ++i)
        for (Eigen::Index j = i + 1; j < state.x.cols(); ++j) {
          const double r = (state.x.col(i) - state.x.col(j)).norm();
          if (r < s_.min_distance) {
            s_.min_distance = r;
            s_.t_of_min_distance = state.t;
          }
        }
    ++s_.frames;
    if (writer_) writer_->write_frame(integrator_ ? integrator_->work().steps : 0, state, d);
  }

 private:
  const System& system_;
  RunSummary& s_;
  H5Writer* writer_;
  const Integrator*& integrator_;
  double p_scale_ = 0.0, L_scale_ = 0.0;
};

}  // namespace

std::shared_ptr<const Potential> make_scene_potential(const Scene& scene,
                                                      PluginRegistry& registry) {
  std::vector<std::shared_ptr<const Potential>> terms;
  for (const auto& p : scene.potentials)
    terms.push_back(registry.make_potential(p.plugin, scene.system, p.params));
  return terms.size() == 1 ? terms.front() : std::make_shared<SumPotential>(terms);
}

RunSummary run_scene(const Scene& scene, PluginRegistry& registry, const RunOptions& options) {
  RunSummary summary;
  for (const auto& p : scene.potentials)
    summary.potential += (summary.potential.empty() ? "" : "+") + p.plugin;
  const auto potential = make_scene_potential(scene, registry);
  auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, potential,
                                             scene.integrator.params);
  summary.integrator = scene.integrator.plugin;

  // What the potential chose per pair, as the integrator's evaluations saw it.
  auto pair_models = [&integrator] {
    const PotentialEvaluator* evaluator = integrator->potential_evaluator();
    return evaluator ? evaluator->pair_models() : std::vector<PairModel>{};
  };
  summary.pair_models = pair_models();
  std::unique_ptr<H5Writer> writer;
  if (options.output) {
    OutputOptions output;
    output.overwrite = options.overwrite;
    // t0, every output time, and one more for an event or an interrupt (the stepping loop).
    const double frames = 2.0 + std::ceil((scene.run.t_end - scene.initial.t) / scene.run.output_every);
    output.expected_frames = frames > 0 && frames < 1e18 ? static_cast<std::uint64_t>(frames) : 0;
    if (!scene.file.empty() && std::filesystem::exists(scene.file)) output.inputs.push_back(scene.file);
    writer = std::make_unique<H5Writer>(*options.output, scene, output);
  }
  if (writer) writer->write_pair_models(summary.pair_models);
  State state = scene.initial;
  const Integrator* current = integrator.get();
  Progress progress(options.progress, state.t, scene.run.t_end);
  RunObserver observer(scene.system, summary, writer.get(), current);

  Schedule schedule{scene.run.t_end, scene.run.output_every,
                    Events{scene.run.close_approach, scene.run.collisions},
                    {}, options.interrupt};
  // An integrator's per-step records go to the output every 1024 steps (and are dropped
  // without one), so they never accumulate in memory.
  auto stream_step_series = [&integrator, &writer] {
    auto records = integrator->take_step_series();
    if (writer && !records.empty()) writer->append_step_series(records);
  };
  schedule.on_step = [&, n = 0u](double t) mutable {
    ++n;
    if (options.progress && (n & 15u) == 0) progress.update(t);  // the clock read every 16 steps only
    if ((n & 1023u) == 0) stream_step_series();
  };
  const auto start = Clock::now();
  StopInfo stop;
  try {
    stop = integrate(*integrator, *potential, scene.system, state, schedule, observer);
  } catch (const Error& e) {
    summary.work = integrator->work();
    summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (writer) {
      stream_step_series();
      writer->write_pair_models(pair_models());
      writer->finish(summary.work, summary.wall_seconds, std::string("failed: ") + e.what());
    }
    throw;
  }
  summary.work = integrator->work();
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  summary.stop_reason = stop.reason;
  summary.final_state = std::move(state);
  summary.pair_models = pair_models();  // now with what the run saw
  if (writer) {
    stream_step_series();
    writer->write_pair_models(summary.pair_models);
    writer->finish(summary.work, summary.wall_seconds,
                   summary.stop_reason.empty() ? "completed" : "stopped: " + summary.stop_reason);
  }
  return summary;
}

std::string format_pair_models(const std::vector<PairModel>& models) {
  std::string out;
  char line[512];
  for (const auto& m : models) {
    const std::string pair = "pair " + m.body_a + "–" + m.body_b;
    std::snprintf(line, sizeof line, "%-31s %s, estimated error %.1e at separation %.6g (tolerance %.0e)\n",
                  pair.c_str(), m.model.c_str(), m.estimated_error, m.separation, m.tolerance);
    out += line;
    if (m.exceeded) {
      std::snprintf(line, sizeof line,
                    "%-31s EXCEEDED at t = %.6g: separation %.6g, estimated error %.1e > tolerance %.0e\n", "",
                    m.exceeded_time, m.exceeded_separation, m.exceeded_error, m.tolerance);
      out += line;
    }
  }
  return out;
}

std::string format_summary(const RunSummary& s) {
  char buf[2048];
  const double steps = static_cast<double>(std::max<std::int64_t>(1, s.work.steps));
  std::snprintf(
      buf, sizeof buf,
      "potential                     %s\n"
      "integrator                    %s\n"
      "E0                            %.10f\n"
      "max |E - E0|                  %.4e\n"
      "max rel. linear momentum err  %.3e\n"
      "max rel. angular momentum err %.3e\n"
      "max ||I - R^T R||_F           %.4e\n"
      "closest approach              %.6f at t = %.4f\n"
      "output frames                 %zu\n"
      "steps                         %lld\n"
      "potential evaluations         %lld\n"
      "Newton iterations per step    %.3f\n"
      "rejected steps                %s\n"
      "wall time                     %.3f s\n",
      s.potential.c_str(), s.integrator.c_str(), s.initial.energy, s.max_abs_energy_error,
      s.max_rel_linear_momentum_error, s.max_rel_angular_momentum_error,
      s.max_orthogonality_error, s.min_distance, s.t_of_min_distance, s.frames,
      static_cast<long long>(s.work.steps), static_cast<long long>(s.work.potential_evaluations),
      static_cast<double>(s.work.newton_iterations) / steps,
      s.work.rejected_steps < 0 ? "not reported" : std::to_string(s.work.rejected_steps).c_str(),
      s.wall_seconds);
  std::string out = buf;
  if (!s.stop_reason.empty()) out += "stopped early                 " + s.stop_reason + "\n";
  out += format_pair_models(s.pair_models);
  return out;
}

}  // namespace noether
