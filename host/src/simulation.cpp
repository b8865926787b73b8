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
      detect_conservation(state, forces);
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
          const Body &a = system_.body(static_cast<std::size_t>(i)), &b = system_.body(static_cast<std::size_t>(j));
          if (a.radius + b.radius > 0 && r - (a.radius + b.radius) < s_.min_gap) {
            s_.min_gap = r - (a.radius + b.radius);
            s_.min_gap_reach = a.radius + b.radius;
            s_.min_gap_pair = a.name + "–" + b.name;
          }
        }
    ++s_.frames;
    if (writer_) writer_->write_frame(integrator_ ? integrator_->work().steps : 0, state, d);
  }

 private:
  // The forces at t0 tell what the scene conserves: a net force or a net torque about the
  // origin larger than 10⁻⁶ of the sum of their parts is an external field.
  void detect_conservation(const State& state, const Forces& forces) {
    Vec3 F = Vec3::Zero(), T = Vec3::Zero();
    double F_parts = 0.0, T_parts = 0.0;
    for (Eigen::Index i = 0; i < forces.f.cols(); ++i) {
      const Vec3 f = forces.f.col(i), torque = Vec3(state.x.col(i)).cross(f);
      F += f, F_parts += f.norm();
      T += torque, T_parts += torque.norm();
    }
    for (Eigen::Index k = 0; k < forces.M.cols(); ++k) {
      T += state.R[static_cast<std::size_t>(k)] * Vec3(forces.M.col(k));  // d(R Π)/dt = R M
      T_parts += forces.M.col(k).norm();
    }
    s_.conserves_linear_momentum = F.norm() <= 1e-6 * F_parts;
    s_.conserves_angular_momentum = T.norm() <= 1e-6 * T_parts;
  }

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
  if (scene.units.declared) summary.units = scene.units.describe();

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

  // The loop stops on one flag: the caller's (a signal) or the wall-time budget's.
  volatile std::sig_atomic_t stop_flag = 0;
  bool budget_exhausted = false;
  Schedule schedule{scene.run.t_end, scene.run.output_every,
                    Events{scene.run.close_approach, scene.run.collisions},
                    {}, (options.interrupt || options.max_wall_seconds > 0.0) ? &stop_flag : nullptr};
  const auto start = Clock::now();
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
    if (options.interrupt && *options.interrupt) stop_flag = *options.interrupt;
    if (options.max_wall_seconds > 0.0 && (n & 15u) == 0 &&
        std::chrono::duration<double>(Clock::now() - start).count() > options.max_wall_seconds) {
      budget_exhausted = true;
      stop_flag = -1;
    }
  };
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
  if (budget_exhausted && stop.event == "interrupted") {
    std::ostringstream why;
    why.precision(10);
    why << "wall-time budget of " << options.max_wall_seconds << " s exhausted at t = " << stop.t;
    summary.stop_reason = why.str();
  }
  summary.interpolated_frames = stop.interpolated_frames;
  summary.final_state = std::move(state);
  summary.pair_models = pair_models();  // now with what the run saw
  judge(summary, scene);
  if (writer) {
    stream_step_series();
    writer->write_pair_models(summary.pair_models);
    std::string reasons;
    for (const auto& r : summary.verdict.reasons) reasons += (reasons.empty() ? "" : "; ") + r;
    writer->set_verdict(summary.verdict.trustworthy ? "trustworthy" : "untrustworthy", reasons,
                        summary.max_rel_energy_error, summary.energy_scale);
    writer->finish(summary.work, summary.wall_seconds,
                   summary.stop_reason.empty() ? "completed" : "stopped: " + summary.stop_reason);
  }
  return summary;
}

void judge(RunSummary& s, const Scene& scene) {
  const TrustThresholds& limit = scene.run.trust;
  const double T0 = s.initial.kinetic_translational + s.initial.kinetic_rotational;
  const double E0 = std::abs(s.initial.energy);
  s.energy_scale = E0 >= 1e-3 * T0 ? "|E0|" : "T0";
  const double scale = E0 >= 1e-3 * T0 ? E0 : T0;
  s.max_rel_energy_error = scale > 0 ? s.max_abs_energy_error / scale : s.max_abs_energy_error;
  Verdict& v = s.verdict;
  v = {};
  char why[256];
  if (s.max_rel_energy_error > limit.energy) {
    std::snprintf(why, sizeof why, "relative energy error %.2e (of %s) > %.0e", s.max_rel_energy_error,
                  s.energy_scale.c_str(), limit.energy);
    v.reasons.push_back(why);
  }
  if (s.conserves_linear_momentum && s.max_rel_linear_momentum_error > limit.momentum) {
    std::snprintf(why, sizeof why, "relative linear momentum error %.2e > %.0e", s.max_rel_linear_momentum_error,
                  limit.momentum);
    v.reasons.push_back(why);
  }
  if (s.conserves_angular_momentum && s.max_rel_angular_momentum_error > limit.momentum) {
    std::snprintf(why, sizeof why, "relative angular momentum error %.2e > %.0e", s.max_rel_angular_momentum_error,
                  limit.momentum);
    v.reasons.push_back(why);
  }
  if (s.max_orthogonality_error > limit.orthogonality) {
    std::snprintf(why, sizeof why, "attitudes left SO(3): ||I - R^T R|| = %.2e > %.0e", s.max_orthogonality_error,
                  limit.orthogonality);
    v.reasons.push_back(why);
  }
  // Bounding spheres inside each other by more than the event's root tolerance (a run stopped
  // by a collision ends at contact, to ~1e-10).
  if (s.min_gap < -1e-6 * s.min_gap_reach) {
    std::snprintf(why, sizeof why, "bodies %s overlapped (bounding spheres %.3g inside each other)",
                  s.min_gap_pair.c_str(), -s.min_gap);
    v.reasons.push_back(why);
  }
  v.trustworthy = v.reasons.empty();
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
  // Only what the scene conserves, and a closest approach only where there are two bodies.
  std::string optional;
  char line[256];
  if (s.conserves_linear_momentum) {
    std::snprintf(line, sizeof line, "max rel. linear momentum err  %.3e\n", s.max_rel_linear_momentum_error);
    optional += line;
  }
  if (s.conserves_angular_momentum) {
    std::snprintf(line, sizeof line, "max rel. angular momentum err %.3e\n", s.max_rel_angular_momentum_error);
    optional += line;
  }
  if (s.final_state.R.size() > 0) {
    std::snprintf(line, sizeof line, "max ||I - R^T R||_F           %.4e\n", s.max_orthogonality_error);
    optional += line;
  }
  if (std::isfinite(s.min_distance)) {
    std::snprintf(line, sizeof line, "closest approach              %.6f at t = %.4f\n", s.min_distance,
                  s.t_of_min_distance);
    optional += line;
  }
  // Frames between the method's steps are interpolated states, not the method's own: say so.
  const std::string where_energy =
      s.interpolated_frames > 0 ? ", " + std::to_string(s.interpolated_frames) + " of " + std::to_string(s.frames) +
                                      " interpolated between the method's steps"
                                : "";
  std::snprintf(
      buf, sizeof buf,
      "potential                     %s\n"
      "integrator                    %s\n"
      "E0                            %.10f\n"
      "max |E - E0|                  %.4e (relative to %s: %.2e; at the output frames%s)\n"
      "%s"
      "output frames                 %zu\n"
      "steps                         %lld\n"
      "potential evaluations         %lld\n"
      "Newton iterations per step    %.3f\n"
      "rejected steps                %s\n"
      "wall time                     %.3f s\n",
      s.potential.c_str(), s.integrator.c_str(), s.initial.energy, s.max_abs_energy_error,
      s.energy_scale.c_str(), s.max_rel_energy_error, where_energy.c_str(), optional.c_str(), s.frames,
      static_cast<long long>(s.work.steps), static_cast<long long>(s.work.potential_evaluations),
      static_cast<double>(s.work.newton_iterations) / steps,
      s.work.rejected_steps < 0 ? "not reported" : std::to_string(s.work.rejected_steps).c_str(),
      s.wall_seconds);
  std::string out = buf;
  if (!s.units.empty()) out.insert(out.find("E0 "), "units                         " + s.units + "\n");
  if (!s.stop_reason.empty()) out += "stopped early                 " + s.stop_reason + "\n";
  out += format_pair_models(s.pair_models);
  if (s.verdict.trustworthy) {
    out += "verdict                       trustworthy\n";
  } else {
    for (const auto& r : s.verdict.reasons) out += "verdict                       UNTRUSTWORTHY: " + r + "\n";
  }
  return out;
}

namespace {

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

}  // namespace

std::string format_summary_json(const RunSummary& s) {
  std::ostringstream out;
  auto field = [&out, first = true](const char* name, const std::string& value) mutable {
    out << (first ? "{\n  " : ",\n  ") << json_string(name) << ": " << value;
    first = false;
  };
  field("potential", json_string(s.potential));
  field("integrator", json_string(s.integrator));
  field("units", s.units.empty() ? "null" : json_string(s.units));
  field("E0", json_number(s.initial.energy));
  field("max_abs_energy_error", json_number(s.max_abs_energy_error));
  field("max_rel_energy_error", json_number(s.max_rel_energy_error));
  field("energy_scale", json_string(s.energy_scale));
  field("max_rel_linear_momentum_error",
        s.conserves_linear_momentum ? json_number(s.max_rel_linear_momentum_error) : "null");
  field("max_rel_angular_momentum_error",
        s.conserves_angular_momentum ? json_number(s.max_rel_angular_momentum_error) : "null");
  field("max_orthogonality_error", s.final_state.R.empty() ? "null" : json_number(s.max_orthogonality_error));
  field("closest_approach", json_number(s.min_distance));
  field("t_of_closest_approach", std::isfinite(s.min_distance) ? json_number(s.t_of_min_distance) : "null");
  field("output_frames", std::to_string(s.frames));
  field("interpolated_frames", std::to_string(s.interpolated_frames));
  field("final_time", json_number(s.final_state.t));
  field("stop_reason", s.stop_reason.empty() ? "null" : json_string(s.stop_reason));
  field("steps", std::to_string(s.work.steps));
  field("potential_evaluations", std::to_string(s.work.potential_evaluations));
  field("newton_iterations", std::to_string(s.work.newton_iterations));
  field("rejected_steps", s.work.rejected_steps < 0 ? "null" : std::to_string(s.work.rejected_steps));
  field("wall_seconds", json_number(s.wall_seconds));
  std::string models = "[";
  for (const auto& m : s.pair_models)
    models += std::string(models.size() > 1 ? ", " : "") + "{\"body_a\": " + json_string(m.body_a) +
              ", \"body_b\": " + json_string(m.body_b) + ", \"model\": " + json_string(m.model) +
              ", \"order\": " + std::to_string(m.order) + ", \"estimated_error\": " + json_number(m.estimated_error) +
              ", \"exceeded\": " + (m.exceeded ? "true" : "false") + "}";
  field("pair_models", models + "]");
  std::string reasons = "[";
  for (const auto& r : s.verdict.reasons) reasons += std::string(reasons.size() > 1 ? ", " : "") + json_string(r);
  field("verdict", std::string("{\"trustworthy\": ") + (s.verdict.trustworthy ? "true" : "false") +
                       ", \"reasons\": " + reasons + "]}");
  out << "\n}\n";
  return out.str();
}

}  // namespace noether
