#include <noether/error.hpp>
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include "h5_helpers.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"
#include "io/read_probe.hpp"
#include "io/run_record.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
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

// The run's accounting at every frame: the summary's statistics, and the frame to the output.
class RunObserver final : public Observer {
 public:
  RunObserver(const System& system, RunSummary& summary, std::function<void(const State&, const Diagnostics&)> write)
      : system_(system), s_(summary), write_(std::move(write)) {}

  void observe(const State& state, const Forces& forces, bool interpolated) override {
    const Diagnostics d = account(state, forces);
    if (interpolated) ++s_.interpolated_frames;
    if (write_) write_(state, d);
  }

  // The statistics of one frame (also of the frames a continued run replays from its file).
  Diagnostics account(const State& state, const Forces& forces) {
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
      p_scale_ = L_scale_ = 0.0;
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
    return d;
  }

  // The scales of the relative momentum errors (a saved simulation keeps them).
  std::pair<double, double> scales() const { return {p_scale_, L_scale_}; }
  void set_scales(double p_scale, double L_scale) { p_scale_ = p_scale, L_scale_ = L_scale; }

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
  std::function<void(const State&, const Diagnostics&)> write_;
  double p_scale_ = 0.0, L_scale_ = 0.0;
};

// Work counters added up; −1 (not reported) stays −1.
WorkCounters operator+(const WorkCounters& a, const WorkCounters& b) {
  return WorkCounters{a.steps + b.steps, a.potential_evaluations + b.potential_evaluations,
                      a.newton_iterations + b.newton_iterations,
                      a.rejected_steps < 0 || b.rejected_steps < 0 ? -1 : a.rejected_steps + b.rejected_steps};
}

}  // namespace

std::shared_ptr<const Potential> make_scene_potential(const Scene& scene,
                                                      PluginRegistry& registry) {
  std::vector<std::shared_ptr<const Potential>> terms;
  for (const auto& p : scene.potentials)
    terms.push_back(registry.make_potential(p.plugin, scene.system, p.params));
  return terms.size() == 1 ? terms.front() : std::make_shared<SumPotential>(terms);
}

struct Simulation::Impl {
  Scene scene;
  RunOptions options;
  std::shared_ptr<const Potential> potential;
  std::shared_ptr<Integrator> integrator;
  std::unique_ptr<H5Writer> writer;
  RunSummary summary;
  std::unique_ptr<RunObserver> observer;
  State state;
  double t_origin = 0.0;            // the time of step 0 and frame 0
  std::int64_t steps_before = 0;    // fixed-step methods: steps from t_origin to state.t
  bool integrator_at_state = false; // the integrator stands at `state` (no start() needed)
  WorkCounters base_work{0, 0, 0, 0};  // work of the run this one continues
  double wall_seconds = 0.0;           // wall time spent integrating (and of the run continued)
  Clock::time_point call_start = Clock::now();
  bool in_call = false, finished = false;
  bool custom_potential = false;  // the potential was given in code, not made from the scene
  std::string failure;  // the error that ended the run, if any

  WorkCounters work() const { return base_work + integrator->work(); }
  double wall_now() const {
    return wall_seconds + (in_call ? std::chrono::duration<double>(Clock::now() - call_start).count() : 0.0);
  }
  std::vector<PairModel> pair_models() const {
    const PotentialEvaluator* evaluator = integrator->potential_evaluator();
    return evaluator ? evaluator->pair_models() : std::vector<PairModel>{};
  }
  // A new segment of statistics (set_state, and the replay of a resumed run): the next frame
  // observed gives the references (E0, the momentum scales, what the scene conserves).
  void new_segment() {
    RunSummary& s = summary;
    s.frames = 0;
    s.interpolated_frames = 0;
    s.max_abs_energy_error = s.max_rel_linear_momentum_error = 0.0;
    s.max_rel_angular_momentum_error = s.max_orthogonality_error = 0.0;
    s.min_gap = std::numeric_limits<double>::infinity();
    s.min_gap_reach = 0.0;
    s.min_gap_pair.clear();
  }
  void make_observer() {
    observer = std::make_unique<RunObserver>(scene.system, summary, [this](const State& s, const Diagnostics& d) {
      if (writer) writer->write_frame(s, d, work(), wall_now(), summary.interpolated_frames, integrator->checkpoint());
    });
  }
  // The output file's options; `continuation`: a resumed run's new file, which replaces the
  // old one once the recorded frames are in.
  OutputOptions output_options(bool continuation) const {
    const Scene& sc = scene;
    OutputOptions output;
    output.checkpoint_width = integrator->checkpoint().size();
    output.custom_potential = custom_potential;
    output.overwrite = continuation || options.overwrite;
    output.defer_publish = continuation;
    // t0, every output time, and one more for an event or an interrupt (the stepping loop).
    const double frames = 2.0 + std::ceil((sc.run.t_end - sc.initial.t) / sc.run.output_every);
    output.expected_frames = frames > 0 && frames < 1e18 ? static_cast<std::uint64_t>(frames) : 0;
    if (!continuation && !sc.file.empty() && std::filesystem::exists(sc.file)) output.inputs.push_back(sc.file);
    return output;
  }
  void finish_output(const std::string& outcome) {
    if (!writer) return;
    auto records = integrator->take_step_series();
    if (!records.empty()) writer->append_step_series(records);
    writer->write_pair_models(pair_models());
    RunSummary judged = summary;
    judged.work = work();
    judge(judged, scene);
    std::string reasons;
    for (const auto& r : judged.verdict.reasons) reasons += (reasons.empty() ? "" : "; ") + r;
    writer->set_verdict(judged.verdict.trustworthy ? "trustworthy" : "untrustworthy", reasons,
                        judged.max_rel_energy_error, judged.energy_scale);
    writer->finish(judged.work, wall_now(), outcome);
    writer.reset();
  }
};

Simulation::Simulation(Scene scene, PluginRegistry& registry, RunOptions options,
                       std::shared_ptr<const Potential> potential)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = std::move(scene);
  m.options = std::move(options);
  const Scene& sc = m.scene;
  if (potential) {
    m.potential = std::move(potential);
    m.custom_potential = true;
    m.summary.potential = "python";
  } else {
    for (const auto& p : sc.potentials) m.summary.potential += (m.summary.potential.empty() ? "" : "+") + p.plugin;
    m.potential = make_scene_potential(sc, registry);
  }
  m.integrator = registry.make_integrator(sc.integrator.plugin, sc.system, m.potential, sc.integrator.params);
  m.summary.integrator = sc.integrator.plugin;
  if (sc.units.declared) m.summary.units = sc.units.describe();
  m.summary.pair_models = m.pair_models();
  m.state = sc.initial;
  m.t_origin = sc.initial.t;
  m.make_observer();
  // Frame 0: the integrator started at the initial state (which also tells the size of its
  // checkpoint, for the output's layout), its forces there.
  Forces forces;
  forces.resize(sc.system);
  m.integrator->start(m.state);
  if (m.options.output) {
    m.writer = std::make_unique<H5Writer>(*m.options.output, sc, m.output_options(false));
    m.writer->write_pair_models(m.summary.pair_models);
  }
  // Wall time counts integrating and writing frames, not creating the file (as before there
  // was a Simulation: wall times stay comparable).
  m.call_start = Clock::now();
  m.in_call = true;
  try {
    m.integrator->current(m.state, forces);
    m.state.t = sc.initial.t;
    m.integrator_at_state = true;
    m.observer->observe(m.state, forces, false);
  } catch (const Error& e) {  // the output says why the run ended at t0
    m.wall_seconds = m.wall_now();
    m.in_call = false;
    m.finish_output(std::string("failed: ") + e.what());
    throw;
  }
  m.wall_seconds = m.wall_now();
  m.in_call = false;
}

std::unique_ptr<Simulation> Simulation::resume(const std::filesystem::path& file, PluginRegistry& registry,
                                               RunOptions options, double t_end) {
  // The file is read, verified frame by frame and copied into a new file that replaces it only
  // once every recorded frame is in (docs/user-guide.md, "Continuing a run"): a damaged file is
  // refused, and neither it nor an interrupted continuation is ever half-changed.
  // Every read below is made first in a child (io/read_probe.hpp): a damaged file must not crash
  // or hang this process.
  io::read_probe(file, [&file] {
    const io::RunRecord run(file);
    run.read(0, static_cast<std::size_t>(run.frames), [](std::size_t, const io::RecordedFrame&) {});
    run.read_step_records([](const StepSeries&) {});
  }, io::read_probe_seconds(file), options.interrupt);
  const io::RunRecord run(file);
  const std::string& outcome = run.outcome;
  std::vector<std::string> overrides = run.overrides;
  const bool extend = !std::isnan(t_end);
  if (extend) {
    std::ostringstream o;
    o.precision(17);
    o << "run.t_end=" << t_end;
    overrides.push_back(o.str());
  }
  if (run.custom_potential)
    throw Error(file.string() + ": the run's potential was given in code (a Python function), not by its scene, "
                "so it cannot be continued from the file alone; save() the Simulation and load() it with the potential");
  if (outcome.rfind("failed", 0) == 0)
    throw Error(file.string() + ": the run " + outcome +
                "; continuing it would fail again — change the scene and run it afresh");
  if (outcome.rfind("stopped: collision", 0) == 0 || outcome.rfind("stopped: close approach", 0) == 0)
    throw Error(file.string() + ": the run ended at an event (" + outcome.substr(9) + "); there is nothing to continue");
  if (!run.checksummed)
    spdlog::warn("{} was written by a noether without checksums: its frames are continued unverified (the "
                 "continued file has them)", file.string());
  Scene scene = parse_scene(run.scene_text, run.scene_path, overrides);
  if (scene.system.size() != run.bodies || scene.system.rigid_count() != run.rigid)
    throw Error(file.string() + ": its scene (" + run.scene_path + ") no longer gives the bodies the run had");
  const std::size_t last = static_cast<std::size_t>(run.frames - 1);
  io::RecordedFrame at_last;
  run.read(last, 1, [&at_last](std::size_t, const io::RecordedFrame& f) { at_last = f; });
  const double t_last = at_last.state.t;
  if (!(scene.run.t_end > t_last)) {
    std::ostringstream why;
    why.precision(10);
    why << file.string() << ": the run is already at t = " << t_last << ", its t_end"
        << (extend ? " is not later" : "; give a later --t-end to extend it");
    throw Error(why.str());
  }

  // The run rebuilt, its recorded frames replayed into the summary and copied into the new
  // file, block by block.
  const std::optional<std::filesystem::path> no_output;
  RunOptions rebuilt = options;
  rebuilt.output = no_output;
  auto sim = std::unique_ptr<Simulation>(new Simulation(std::move(scene), registry, rebuilt));
  Impl& m = *sim->impl_;
  m.new_segment();
  const Scene& sc = m.scene;
  OutputOptions output = m.output_options(true);
  char line[128];
  std::snprintf(line, sizeof line, "frame %zu at t = %.17g", last, t_last);
  output.resumed = run.resumed + (run.resumed.empty() ? "" : "\n") + line;
  m.writer = std::make_unique<H5Writer>(file, sc, output);
  Forces forces;
  forces.resize(sc.system);
  double t0 = 0.0;
  const bool complete = run.read(0, last + 1, [&](std::size_t k, const io::RecordedFrame& f) {
    if (k == 0) {  // frame 0 with its forces (what the scene conserves), the others with U alone
      auto workspace = m.potential->make_workspace();
      m.potential->evaluate(f.state, forces, *workspace);
      t0 = f.state.t;
    }
    forces.U = f.U;
    const Diagnostics d = m.observer->account(f.state, forces);
    m.writer->write_frame(f.state, d, f.work, f.wall_seconds, f.interpolated, f.integrator);
  }, options.interrupt);
  if (!complete) {
    m.writer.reset();  // the new file is dropped; the old one was only read
    throw Error(file.string() + " was being read back when the continuation was interrupted; it is unchanged");
  }
  run.read_step_records([&m](const StepSeries& records) { m.writer->append_step_series({records}); });
  m.writer->write_pair_models(m.summary.pair_models);
  m.writer->publish();

  m.summary.interpolated_frames = at_last.interpolated;
  m.state = at_last.state;
  m.t_origin = t0;
  const double h = m.integrator->fixed_step();
  m.steps_before = h > 0 && t_last > m.t_origin ? whole_steps(t_last - m.t_origin, h, "the recorded time") : 0;
  // The integrator continues from its own variables where it has any (relative frame,
  // Lagrangian forms), else from the state.
  if (at_last.integrator.size() != m.integrator->checkpoint().size())
    throw Error(file.string() + ": its integrator checkpoint does not fit the scene's integrator");
  const std::int64_t evaluations = m.integrator->work().potential_evaluations;
  m.integrator->restore(m.state, at_last.integrator);
  m.integrator_at_state = true;
  m.base_work = at_last.work + WorkCounters{0, -evaluations, 0, 0};
  m.wall_seconds = at_last.wall_seconds;
  m.options = std::move(options);
  m.options.output = file;
  return sim;
}

Simulation::~Simulation() {
  if (!impl_ || !impl_->writer) return;
  const Impl& m = *impl_;
  // Closed without finish() (a Python object collected): the outcome says where it stood.
  std::string outcome;
  if (!m.failure.empty())
    outcome = "failed: " + m.failure;
  else if (!m.summary.stop_reason.empty())
    outcome = "stopped: " + m.summary.stop_reason;
  else if (m.state.t >= m.scene.run.t_end)
    outcome = "completed";
  else
    outcome = "stopped: the simulation was closed at t = " + std::to_string(m.state.t) + ", before t_end";
  try {
    impl_->finish_output(outcome);
  } catch (...) {
  }
}

StopInfo Simulation::integrate(double t_end) {
  Impl& m = *impl_;
  if (m.finished) throw Error("the simulation is finished (finish() was called); make a new one");
  if (!m.failure.empty())
    throw Error("the simulation failed at t = " + std::to_string(m.state.t) + " (" + m.failure +
                "); set a state to continue from");
  if (!(t_end > m.state.t)) {
    std::ostringstream why;
    why.precision(17);
    why << "integrate(t): t = " << t_end << " is not after the current time " << m.state.t;
    throw Error(why.str());
  }
  const Scene& sc = m.scene;
  const RunOptions& options = m.options;
  if (const double h = m.integrator->fixed_step(); h > 0 && t_end != sc.run.t_end)
    whole_steps(t_end - m.t_origin, h, "integrate(t): t − t0");  // a fixed-step method lands on its grid only
  Progress progress(options.progress, m.state.t, t_end);

  // The loop stops on one flag: the caller's (a signal) or the wall-time budget's.
  volatile std::sig_atomic_t stop_flag = 0;
  bool budget_exhausted = false;
  Schedule schedule{t_end, sc.run.output_every, Events{sc.run.close_approach, sc.run.collisions},
                    {}, (options.interrupt || options.max_wall_seconds > 0.0) ? &stop_flag : nullptr};
  schedule.t_origin = m.t_origin;
  schedule.steps_before = m.steps_before;
  schedule.observe_start = false;
  schedule.integrator_at_state = m.integrator_at_state;
  m.call_start = Clock::now();
  m.in_call = true;
  const auto start = m.call_start;
  // An integrator's per-step records go to the output every 1024 steps (and are dropped
  // without one), so they never accumulate in memory.
  auto stream_step_series = [&m] {
    auto records = m.integrator->take_step_series();
    if (m.writer && !records.empty()) m.writer->append_step_series(records);
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
    stop = noether::integrate(*m.integrator, *m.potential, sc.system, m.state, schedule, *m.observer);
  } catch (const Error& e) {
    m.wall_seconds = m.wall_now();
    m.in_call = false;
    m.integrator_at_state = false;
    m.failure = e.what();
    m.finish_output(std::string("failed: ") + e.what());
    throw;
  }
  m.wall_seconds = m.wall_now();
  m.in_call = false;
  m.integrator_at_state = true;
  m.steps_before = stop.steps;
  m.summary.stop_reason = stop.reason;
  if (budget_exhausted && stop.event == "interrupted") {
    std::ostringstream why;
    why.precision(10);
    why << "wall-time budget of " << options.max_wall_seconds << " s exhausted at t = " << stop.t;
    m.summary.stop_reason = stop.reason = why.str();
  }
  if (!stop.event.empty() && stop.event != "interrupted") {
    // An event ends on a shortened step, off the step grid: a further call starts afresh there.
    m.integrator_at_state = false;
    m.t_origin = m.state.t;
    m.steps_before = 0;
  }
  return stop;
}

double Simulation::time() const { return impl_->state.t; }
const State& Simulation::state() const { return impl_->state; }
const Scene& Simulation::scene() const { return impl_->scene; }
const Potential& Simulation::potential() const { return *impl_->potential; }

void Simulation::set_state(const State& s) {
  Impl& m = *impl_;
  if (m.finished) throw Error("the simulation is finished (finish() was called); make a new one");
  const System& sys = m.scene.system;
  const auto nb = static_cast<Eigen::Index>(sys.size()), nr = static_cast<Eigen::Index>(sys.rigid_count());
  if (s.x.cols() != nb || s.p.cols() != nb || s.Pi.cols() != nr || s.R.size() != sys.rigid_count())
    throw Error("set_state: the state has the wrong shape: " + std::to_string(nb) + " bodies and " +
                std::to_string(nr) + " rigid bodies expected");
  if (!std::isfinite(s.t) || !s.x.allFinite() || !s.p.allFinite() || !s.Pi.allFinite())
    throw Error("set_state: the state has non-finite values");
  for (std::size_t k = 0; k < s.R.size(); ++k) {
    const double orth = (Mat3::Identity() - s.R[k].transpose() * s.R[k]).norm();
    if (!s.R[k].allFinite() || orth > 1e-10 || !(s.R[k].determinant() > 0)) {
      std::ostringstream why;
      why << "set_state: the attitude of '" << sys.body(sys.body_of_rigid(k)).name
          << "' is not a rotation (||I - R^T R|| = " << orth << ", det R = " << s.R[k].determinant()
          << "; a rotation has 0 and +1)";
      throw Error(why.str());
    }
  }
  m.state = s;
  m.failure.clear();
  m.t_origin = s.t;
  m.steps_before = 0;
  m.integrator_at_state = false;
  m.new_segment();  // its first frame, below, gives the references
  Forces forces;
  forces.resize(sys);
  m.integrator->start(m.state);
  m.integrator->current(m.state, forces);
  m.state.t = s.t;
  m.integrator_at_state = true;
  m.observer->observe(m.state, forces, false);
}

RunSummary Simulation::summary() const {
  const Impl& m = *impl_;
  RunSummary s = m.summary;
  s.work = m.work();
  s.wall_seconds = m.wall_now();
  s.final_state = m.state;
  s.pair_models = m.pair_models();
  judge(s, m.scene);
  return s;
}

RunSummary Simulation::finish() {
  Impl& m = *impl_;
  RunSummary s = summary();
  if (!m.finished && m.writer)
    m.finish_output(m.failure.empty() ? (s.stop_reason.empty() ? "completed" : "stopped: " + s.stop_reason)
                                      : "failed: " + m.failure);
  m.finished = true;
  return s;
}

// Saving and loading ------------------------------------------------------------------------
// A checkpoint file: the scene as given, the exact state, where the run stands (t0, steps), its
// work and the summary's running values, so that a loaded simulation continues as this one would.
namespace {

using namespace noether::h5;

// A dataset of doubles with the checksum of its values (attribute "checksum").
void write_doubles(hid_t parent, const char* name, const double* data, std::vector<hsize_t> dims) {
  const io::H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  const io::H5Handle d(
      check_id(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name));
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  if (n) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), name);
  numeric_attribute<std::uint64_t>(d, "checksum", H5T_NATIVE_UINT64, {io::checksum64(data, n * sizeof(double))});
}

// The checkpoint `file` is damaged: `what` names where.
[[noreturn]] void damaged_checkpoint(const std::filesystem::path& file, const std::string& what) {
  throw OutputError(file.string() + " is damaged: " + what + "; it was only read, not changed");
}

// Reads a dataset written by write_doubles, verifying its checksum when it has one (a
// checkpoint from an older noether has none).
std::vector<double> read_doubles(const std::filesystem::path& file, hid_t parent, const char* group, const char* name,
                                 std::size_t expected) {
  const io::H5Handle d = io::open_dataset(parent, name);
  if (!d.valid()) throw OutputError(std::string("the checkpoint has no ") + name);
  const io::H5Handle space(H5Dget_space(d));
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  if (n != expected)
    throw OutputError(std::string("the checkpoint's ") + name + " has " + std::to_string(n) + " numbers, the scene needs " +
                      std::to_string(expected));
  std::vector<double> out(n);
  const std::string where = std::string("/") + group + "/" + name;
  if (n && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    damaged_checkpoint(file, where + " does not read");
  if (H5Aexists(d, "checksum") > 0) {
    std::uint64_t sum = 0;
    const io::H5Handle a(H5Aopen(d, "checksum", H5P_DEFAULT));
    if (H5Aread(a, H5T_NATIVE_UINT64, &sum) < 0 || sum != io::checksum64(out.data(), n * sizeof(double)))
      damaged_checkpoint(file, where + " does not match its checksum");
  }
  return out;
}

// The checksum of a group's text attributes (strings live outside the checksummed object
// headers, in HDF5's global heap).
std::uint64_t texts_checksum(std::initializer_list<const std::string*> texts) { return io::checksum_of_texts(texts); }

double read_scalar(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) throw OutputError(std::string("the checkpoint has no attribute ") + name);
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t space = H5Aget_space(a);
  std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(1, H5Sget_simple_extent_npoints(space))));
  H5Sclose(space);
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Aclose(a);
  return v[0];
}

std::vector<double> read_vector(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) throw OutputError(std::string("the checkpoint has no attribute ") + name);
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t space = H5Aget_space(a);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Sclose(space);
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Aclose(a);
  return v;
}

// The diagnostics as 13 numbers and back.
std::vector<double> pack(const Diagnostics& d) {
  return {d.kinetic_translational, d.kinetic_rotational, d.potential, d.energy, d.linear_momentum.x(),
          d.linear_momentum.y(), d.linear_momentum.z(), d.angular_momentum.x(), d.angular_momentum.y(),
          d.angular_momentum.z(), d.orthogonality_error};
}
Diagnostics unpack(const std::vector<double>& v) {
  if (v.size() != 11) throw OutputError("the checkpoint's diagnostics have the wrong size");
  Diagnostics d;
  d.kinetic_translational = v[0], d.kinetic_rotational = v[1], d.potential = v[2], d.energy = v[3];
  d.linear_momentum = Vec3(v[4], v[5], v[6]);
  d.angular_momentum = Vec3(v[7], v[8], v[9]);
  d.orthogonality_error = v[10];
  return d;
}

}  // namespace

void Simulation::save(const std::filesystem::path& path) const {
  const Impl& m = *impl_;
  if (m.scene.text.empty())
    throw Error("save: this simulation's scene has no text to save (it was not read from YAML)");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  // Written under a temporary name and renamed: a kill while saving leaves the previous file.
  const std::filesystem::path partial = path.string() + ".partial";
  hid_t file = H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, io::file_access(0));
  if (file < 0) throw OutputError("cannot create " + path.string() + system_reason());
  try {
    string_attribute(file, "format", "noether simulation checkpoint 1");
    numeric_attribute<int>(file, "custom_potential", H5T_NATIVE_INT, {m.custom_potential ? 1 : 0});
    hid_t g = make_group(file, "parameters");
    string_dataset(g, "scene", m.scene.text, "the scene file's text, as given");
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(m.scene.file, ec);
    const std::string scene_path = ec ? m.scene.file : absolute.string();
    string_attribute(g, "scene_path", scene_path);
    std::string overrides;
    for (const auto& o : m.scene.overrides) overrides += (overrides.empty() ? "" : "\n") + o;
    string_attribute(g, "overrides", overrides);
    numeric_attribute<std::uint64_t>(g, "checksum", H5T_NATIVE_UINT64,
                                     {io::scene_checksum(m.scene.text, scene_path, overrides, m.custom_potential)});
    H5Gclose(g);
    const State& st = m.state;
    const hsize_t nb = static_cast<hsize_t>(st.x.cols()), nr = st.R.size();
    g = make_group(file, "state");
    scalar_attribute(g, "t", st.t);
    write_doubles(g, "x", st.x.data(), {nb, 3});
    write_doubles(g, "p", st.p.data(), {nb, 3});
    std::vector<double> R;
    for (const auto& Rk : st.R)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R.push_back(Rk(r, c));
    write_doubles(g, "R", R.data(), {nr, 3, 3});
    write_doubles(g, "Pi", st.Pi.data(), {nr, 3});
    const std::vector<double> own = m.integrator->checkpoint();  // Integrator::checkpoint
    write_doubles(g, "integrator", own.data(), {own.size()});
    H5Gclose(g);
    g = make_group(file, "run");
    scalar_attribute(g, "t_origin", m.t_origin);
    scalar_attribute(g, "steps_before", static_cast<double>(m.steps_before));
    const WorkCounters w = m.work();
    numeric_attribute<double>(g, "work", H5T_NATIVE_DOUBLE,
                              {static_cast<double>(w.steps), static_cast<double>(w.potential_evaluations),
                               static_cast<double>(w.newton_iterations), static_cast<double>(w.rejected_steps)});
    scalar_attribute(g, "wall_seconds", m.wall_now());
    const RunSummary& s = m.summary;
    numeric_attribute<double>(g, "initial", H5T_NATIVE_DOUBLE, pack(s.initial));
    numeric_attribute<double>(g, "final", H5T_NATIVE_DOUBLE, pack(s.final));
    const auto [p_scale, L_scale] = m.observer->scales();
    numeric_attribute<double>(g, "statistics", H5T_NATIVE_DOUBLE,
                              {s.max_abs_energy_error, s.max_rel_linear_momentum_error, s.max_rel_angular_momentum_error,
                               s.max_orthogonality_error, s.conserves_linear_momentum ? 1.0 : 0.0,
                               s.conserves_angular_momentum ? 1.0 : 0.0, s.min_gap, s.min_gap_reach, s.min_distance,
                               s.t_of_min_distance, static_cast<double>(s.frames),
                               static_cast<double>(s.interpolated_frames), p_scale, L_scale});
    string_attribute(g, "min_gap_pair", s.min_gap_pair);
    string_attribute(g, "stop_reason", s.stop_reason);
    numeric_attribute<std::uint64_t>(g, "checksum", H5T_NATIVE_UINT64, {texts_checksum({&s.min_gap_pair, &s.stop_reason})});
    H5Gclose(g);
  } catch (...) {
    H5Fclose(file);
    std::filesystem::remove(partial);
    throw;
  }
  check(H5Fclose(file), "closing the checkpoint");
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) throw OutputError("cannot write " + path.string() + ": " + ec.message());
}

namespace {

// What Simulation::save wrote, read back and verified.
struct SavedSimulation {
  Scene scene;  // its initial state is where the saved simulation stood
  std::vector<double> integrator, work, stats;
  double t_origin = 0.0, steps_before = 0.0, wall = 0.0;
  Diagnostics initial, final_;
  std::string min_gap_pair, stop_reason;
};

SavedSimulation read_saved_simulation(const std::filesystem::path& path, bool potential_given) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  const io::H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, io::file_access(0)));
  if (!file.valid())
    throw OutputError(path.string() + " is not an HDF5 file" + system_reason() +
                      " (or its first bytes, the HDF5 superblock, are damaged)");
  if (read_string(file, "format", false) != "noether simulation checkpoint 1")
    throw OutputError(path.string() + " is not a checkpoint saved by Simulation.save (an output file continues "
                                      "with `noether run --resume`)");
  const bool custom = read_scalar(file, "custom_potential") != 0;
  if (custom && !potential_given)
    throw Error(path.string() + " was saved from a simulation whose potential was given in code (a Python "
                                "function), not by the scene: pass the same potential to load it");
  // A checksum attribute, verified when the checkpoint has one (an older noether's has none).
  const auto verify = [&path](hid_t group, const char* where, std::uint64_t expected) {
    if (H5Aexists(group, "checksum") <= 0) return;
    std::uint64_t sum = 0;
    const io::H5Handle a(H5Aopen(group, "checksum", H5P_DEFAULT));
    if (H5Aread(a, H5T_NATIVE_UINT64, &sum) < 0 || sum != expected)
      damaged_checkpoint(path, std::string(where) + " does not match its checksum");
  };
  const auto open_group = [&path, &file](const char* name) {
    io::H5Handle g(H5Gopen2(file, name, H5P_DEFAULT));
    if (!g.valid()) damaged_checkpoint(path, std::string("/") + name + " does not open");
    return g;
  };
  SavedSimulation saved;
  {
    const io::H5Handle g = open_group("parameters");
    const std::string text = read_string(g, "scene", true), scene_path = read_string(g, "scene_path", false),
                      joined = read_string(g, "overrides", false);
    verify(g, "/parameters (the scene's text, its path or the overrides)",
           io::scene_checksum(text, scene_path, joined, custom));
    saved.scene = parse_scene(text, scene_path, lines_of(joined));
  }
  const std::size_t nb = saved.scene.system.size(), nr = saved.scene.system.rigid_count();
  State st = State::zeros(saved.scene.system);
  {
    const io::H5Handle g = open_group("state");
    st.t = read_scalar(g, "t");
    const auto x = read_doubles(path, g, "state", "x", 3 * nb), p = read_doubles(path, g, "state", "p", 3 * nb),
               R = read_doubles(path, g, "state", "R", 9 * nr), Pi = read_doubles(path, g, "state", "Pi", 3 * nr);
    std::size_t own_size = 0;
    if (const io::H5Handle own = io::open_dataset(g, "integrator"); own.valid()) {
      const io::H5Handle space(H5Dget_space(own));
      own_size = static_cast<std::size_t>(std::max<hssize_t>(0, H5Sget_simple_extent_npoints(space)));
    }
    saved.integrator = read_doubles(path, g, "state", "integrator", own_size);
    st.x = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, static_cast<Eigen::Index>(nb));
    st.p = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, static_cast<Eigen::Index>(nb));
    st.Pi = Eigen::Map<const Eigen::Matrix3Xd>(Pi.data(), 3, static_cast<Eigen::Index>(nr));
    for (std::size_t k = 0; k < nr; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) st.R[k](r, c) = R[9 * k + static_cast<std::size_t>(3 * r + c)];
  }
  saved.scene.initial = st;  // frame 0 of the loaded simulation is where the saved one stood
  {
    const io::H5Handle g = open_group("run");
    saved.t_origin = read_scalar(g, "t_origin");
    saved.steps_before = read_scalar(g, "steps_before");
    saved.wall = read_scalar(g, "wall_seconds");
    saved.work = read_vector(g, "work");
    saved.stats = read_vector(g, "statistics");
    saved.initial = unpack(read_vector(g, "initial"));
    saved.final_ = unpack(read_vector(g, "final"));
    saved.min_gap_pair = read_string(g, "min_gap_pair", false);
    saved.stop_reason = read_string(g, "stop_reason", false);
    verify(g, "/run's texts", texts_checksum({&saved.min_gap_pair, &saved.stop_reason}));
  }
  if (saved.work.size() != 4 || saved.stats.size() != 14) damaged_checkpoint(path, "/run's work or statistics");
  return saved;
}

}  // namespace

std::unique_ptr<Simulation> Simulation::load(const std::filesystem::path& path, PluginRegistry& registry,
                                             RunOptions options, std::shared_ptr<const Potential> potential) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw OutputError(path.string() + ": no such file");
  SavedSimulation saved;
  try {  // read in a child first: a damaged file must not crash or hang this process (io/read_probe.hpp)
    const bool given = potential != nullptr;
    io::read_probe(path, [&path, given] { read_saved_simulation(path, given); }, io::read_probe_seconds(path),
                   options.interrupt);
    saved = read_saved_simulation(path, given);
  } catch (const OutputError& e) {  // every refusal names the file
    const std::string what = e.what();
    if (what.rfind(path.string(), 0) == 0) throw;
    throw OutputError(path.string() + ": " + what + " (a damaged checkpoint, or not one that Simulation.save wrote)");
  }
  const std::vector<double>& stats = saved.stats;
  const bool with_output = options.output.has_value();
  auto sim = std::make_unique<Simulation>(std::move(saved.scene), registry, options, std::move(potential));
  Impl& m = *sim->impl_;
  RunSummary& s = m.summary;
  if (!with_output) {  // the frame the constructor observed is the saved state's: not counted again
    s.initial = saved.initial;
    s.final = saved.final_;
    s.max_abs_energy_error = stats[0], s.max_rel_linear_momentum_error = stats[1];
    s.max_rel_angular_momentum_error = stats[2], s.max_orthogonality_error = stats[3];
    s.conserves_linear_momentum = stats[4] != 0, s.conserves_angular_momentum = stats[5] != 0;
    s.min_gap = stats[6], s.min_gap_reach = stats[7], s.min_distance = stats[8], s.t_of_min_distance = stats[9];
    s.frames = static_cast<std::size_t>(stats[10]);
    s.interpolated_frames = static_cast<std::int64_t>(stats[11]);
    m.observer->set_scales(stats[12], stats[13]);
    s.min_gap_pair = saved.min_gap_pair;
    s.stop_reason = saved.stop_reason;
  }
  const std::vector<double>& work = saved.work;
  m.t_origin = saved.t_origin;
  m.steps_before = static_cast<std::int64_t>(saved.steps_before);
  m.base_work = WorkCounters{static_cast<std::int64_t>(work[0]),
                             static_cast<std::int64_t>(work[1]) - m.integrator->work().potential_evaluations,
                             static_cast<std::int64_t>(work[2]), static_cast<std::int64_t>(work[3])};
  m.wall_seconds = saved.wall;
  // The integrator continues from its own variables where it has any, else from the state.
  if (saved.integrator.size() != m.integrator->checkpoint().size())
    throw OutputError(path.string() + ": its integrator checkpoint does not fit the scene's integrator");
  m.integrator->restore(m.state, saved.integrator);
  m.integrator_at_state = true;
  return sim;
}

RunSummary run_scene(const Scene& scene, PluginRegistry& registry, const RunOptions& options) {
  Simulation sim(scene, registry, options);
  sim.integrate(scene.run.t_end);
  return sim.finish();
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
