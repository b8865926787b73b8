// Simulation: a run held open — made from a scene, integrated in calls, its state read and
// set, finished (docs/user-guide.md; continuation.cpp resumes, saves and loads one).
#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include "scene/start_apart.hpp"
#include "run/refined_run.hpp"
#include "run/simulation_impl.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace noether {

std::shared_ptr<const Potential> make_scene_potential(const Scene& scene,
                                                      PluginRegistry& registry) {
  std::vector<std::shared_ptr<const Potential>> terms;
  for (const auto& p : scene.potentials)
    terms.push_back(registry.make_potential(p.plugin, scene.system, p.params, &scene.models_state()));
  return terms.size() == 1 ? terms.front() : std::make_shared<SumPotential>(terms);
}
namespace {

// RunOptions::threads, or (0) NOETHER_THREADS from the environment, else 1.
int evaluation_threads_of(const RunOptions& options) {
  if (options.threads < 0)
    throw SceneError("threads must be a positive whole number (or 0: NOETHER_THREADS, else 1), not " +
                     std::to_string(options.threads));
  if (options.threads > 0) return options.threads;
  const char* given = std::getenv("NOETHER_THREADS");
  if (!given || !*given) return 1;
  char* end = nullptr;
  const long n = std::strtol(given, &end, 10);
  if (*end != '\0' || n < 1 || n > 1024)
    throw SceneError(std::string("NOETHER_THREADS=") + given + " is not a number of threads (a whole number 1..1024)");
  return static_cast<int>(n);
}

}  // namespace

std::shared_ptr<const Forcing> make_scene_forcing(const Scene& scene, PluginRegistry& registry) {
  auto forcing = std::make_shared<Forcing>();
  for (const auto& f : scene.forces) {
    // "tides alpha", "prescribed-body earth": the plugin and what the entry is about.
    const char* key = f.params.has("name") ? "name" : f.params.has("body") ? "body" : nullptr;
    const std::string base = f.plugin + (key ? " " + f.params.at(key).as_string() : std::string());
    std::string name = base;
    for (int k = 2; std::any_of(forcing->begin(), forcing->end(), [&](const ForceTerm& t) { return t.name == name; }); ++k)
      name = base + " " + std::to_string(k);
    forcing->push_back({name, registry.make_force(f.plugin, scene.system, f.params, &scene.models_state())});
  }
  return forcing;
}

Simulation::Simulation(Scene scene, PluginRegistry& registry, RunOptions options,
                       std::shared_ptr<const Potential> potential)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = std::move(scene);
  m.registry = &registry;
  m.options = std::move(options);
  m.threads = m.summary.threads = evaluation_threads_of(m.options);
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
  std::shared_ptr<const Forcing>& forcing = m.forcing;
  if (!sc.forces.empty()) {  // forces beyond the potential (docs/forces.md)
    forcing = make_scene_forcing(sc, registry);
    if (const std::string why = m.integrator->add_forcing(forcing); !why.empty())
      throw SceneError(sc.root.at("forces").here() + "forces: integrator '" + sc.integrator.plugin +
                       "' cannot take them: " + why);
    for (const auto& term : *forcing) m.summary.forces.push_back({term.name});
  }
  if (sc.units.declared) m.summary.units = sc.units.describe();
  m.summary.time_unit = sc.units.of_time();
  if (sc.units.declared) {
    m.summary.energy_unit = sc.units.of_energy();
    m.summary.length_unit = sc.units.of_length();
    m.summary.angular_momentum_unit = sc.units.of_angular_momentum();
  }
  m.summary.pair_models = m.pair_models();
  m.state = sc.initial;
  if (m.carries_tangent()) {
    const char* key = sc.run.stm ? "stm" : sc.run.chaos ? "chaos" : "sensitivities";
    if (const std::string why = m.integrator->tangent_map_unavailable(); !why.empty())
      throw SceneError((sc.root.at("run").has(key) ? sc.root.at("run").at(key).here() : std::string()) + "run." +
                       key + ": integrator '" + sc.integrator.plugin + "' cannot carry " +
                       (sc.run.stm    ? "the state-transition matrix"
                        : sc.run.chaos ? "the deviation vector of the chaos indicators"
                                       : "sensitivities") +
                       ": " + why);
  }
  // The run features, started at t0 (the tangent: [I | their columns | ∂z(t0)/∂keys]).
  m.make_features();
  m.start_features_here();
  m.t_origin = sc.initial.t;
  m.make_observer();
  // Frame 0: the integrator started at the initial state (which also tells the size of its
  // checkpoint, for the output's layout), its forces there.
  Forces forces;
  forces.resize(sc.system);
  std::string start_failure;
  try {
    m.integrator->start(m.state);
  } catch (const Error& e) {  // e.g. a potential that is not finite at t0: the output says so
    if (!m.options.output) throw;
    start_failure = e.what();
  }
  if (m.options.output) {
    m.writer = std::make_unique<H5Writer>(*m.options.output, sc, m.output_options(false));
    m.writer->write_pair_models(m.summary.pair_models);
    m.keep_features_with_writer();
  }
  if (!start_failure.empty()) {
    m.finish_output("failed: " + start_failure);  // no frame: the initial state is not valid
    throw IntegrationError(start_failure, sc.initial.t);
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

namespace {

// Integrates from where the run stands to t_end, with no impulse in between (the stepping loop
// with the output, the statistics, signals and the wall-time budget).
StopInfo integrate_to(Simulation::Impl& m, double t_end) {
  const Scene& sc = m.scene;
  const RunOptions& options = m.options;
  if (const double h = m.integrator->fixed_step(); h > 0 && t_end != sc.run.t_end)
    whole_steps(t_end - m.t_origin, h, "integrate(t): t − t0");  // a fixed-step method lands on its grid only
  const double t_begin = m.state.t;

  // The loop stops on one flag: the caller's (a signal) or the wall-time budget's.
  volatile std::sig_atomic_t stop_flag = 0;
  bool budget_exhausted = false;
  // The events are a feature's cut of the steps (run/event_feature.hpp), not the schedule's.
  Schedule schedule{t_end, sc.run.output_every, Events{0.0, false, {}}, {},
                    (options.interrupt || options.max_wall_seconds > 0.0) ? &stop_flag : nullptr};
  for (const auto& f : m.features)
    if (StepCut* cut = f->step_cut()) schedule.cuts.push_back(cut);
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
    if (options.progress && (n & 15u) == 0) options.progress(t, t_begin, t_end);  // every 16 steps
    if ((n & 1023u) == 0) stream_step_series();
    if (options.interrupt && *options.interrupt) stop_flag = *options.interrupt;
    if (options.max_wall_seconds > 0.0 && (n & 15u) == 0 &&
        std::chrono::duration<double>(Clock::now() - start).count() > options.max_wall_seconds) {
      budget_exhausted = true;
      stop_flag = -1;
    }
  };
  // The run features follow every step (chaos: eqs. 23.2–23.5; the particles: eq. 38.3).
  for (const auto& f : m.features) f->before_steps(m.state);
  if (!m.features.empty()) schedule.after_step = [&m](const State& reached) { m.features_after_step(reached); };
  StopInfo stop;
  const EvaluationThreads evaluation_threads(m.threads);  // the potential's, on this thread, while it integrates
  try {
    stop = advance(*m.integrator, *m.potential, sc.system, m.state, schedule, *m.observer);
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

// The jump of `feature` where the run stands, at its time t (an impulse, docs/equations.md §24):
// the feature changes the state and its tangent, the integrator starts afresh there, and the
// frame after the jump is observed with the statistics' references moved by it.
void jump(Simulation::Impl& m, detail::RunFeature& feature, double t) {
  const State before = m.state;
  detail::StateJump at{m.state, m.sensitivity_names, m.parameters.get(), [&m](const State& s, Forces& f) {
    if (PotentialEvaluator* evaluate = m.integrator->potential_evaluator())
      (*evaluate)(s, f);  // the run's own evaluator (its workspace: the orders it chose)
    else
      f = m.forces_at(s);
  }};
  feature.jump(at);
  const Forces forces = m.start_here(t);
  m.jumped(before, m.state, forces.U);
  m.observer->observe(m.state, forces, false);
}

}  // namespace

StopInfo Simulation::integrate(double t_end, bool impulse_at_t) {
  Impl& m = *impl_;
  if (m.finished) throw Error("the simulation is finished (finish() was called); make a new one");
  if (!m.failure.empty())
    throw Error("the simulation failed at t = " + std::to_string(m.state.t) + " (" + m.failure +
                "); set a state to continue from");
  const auto [next, t_next] = m.next_jump();
  const bool pending_now = next && t_next == m.state.t;
  if (!(t_end > m.state.t) && !(t_end == m.state.t && pending_now && impulse_at_t)) {
    std::ostringstream why;
    why.precision(17);
    why << "integrate(t): t = " << t_end << " is not after the current time " << m.state.t;
    throw Error(why.str());
  }
  // Up to each jump (impulse) before t_end, the jump, and on (an event before one stops there).
  for (;;) {
    const auto [feature, t_jump] = m.next_jump();
    if (!feature || t_jump > t_end || (t_jump == t_end && !impulse_at_t)) break;
    if (t_jump > m.state.t) {
      const StopInfo stop = integrate_to(m, t_jump);
      if (!stop.event.empty()) return stop;
    }
    jump(m, *feature, t_jump);
    if (t_jump == t_end) {
      StopInfo stop;
      stop.t = t_end;
      stop.steps = m.steps_before;
      return stop;
    }
  }
  return integrate_to(m, t_end);
}

double Simulation::time() const { return impl_->state.t; }
double Simulation::fixed_step() const { return impl_->integrator->fixed_step(); }
const State& Simulation::state() const { return impl_->state; }
const Scene& Simulation::scene() const { return impl_->scene; }
const std::vector<std::string>& Simulation::sensitivity_names() const { return impl_->sensitivity_names; }

Eigen::MatrixXd Simulation::mass_sensitivities() const {
  const Impl& m = *impl_;
  const auto columns = static_cast<Eigen::Index>(m.sensitivity_names.size());
  Eigen::MatrixXd dm = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m.scene.system.size()), columns);
  if (m.parameters) {  // the parameters of the dynamics are the last columns
    const auto P = static_cast<Eigen::Index>(m.parameters->size());
    for (Eigen::Index j = 0; j < P; ++j) dm.col(columns - P + j) = m.parameters->parameters[static_cast<std::size_t>(j)].mass;
  }
  return dm;
}
const Potential& Simulation::potential() const { return *impl_->potential; }
const ParticleSwarm* Simulation::particles() const { return impl_->particles; }

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
  if (const auto conflict = detail::start_conflict(sys, s, m.scene.run.collisions))
    throw Error("set_state: " + conflict->what);
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
  // The features may refuse the new state (the sensitivities do; the STM one whose tangent does
  // not fit) before anything changes, then take it (the particles move into the new bodies'
  // field); what they carry in it starts a new segment (the forces' balance).
  for (const auto& f : m.features) f->refuse_state(s);
  if (s.tangent.size() > 0 && !m.scene.run.stm)
    throw Error("set_state: the state carries a tangent but the run does not carry one (run.stm is off)");
  for (const auto& f : m.features) f->accept_state(s);
  m.state = s;
  for (const auto& f : m.features) f->begin_segment(m.state);
  // A new segment: the features start again there (the state-transition matrix at the identity
  // unless one is given, the chaos indicators from δ0; the impulses after the new state's time
  // are still to come).
  m.start_features_here();
  m.failure.clear();
  m.scene_trajectory = false;
  m.t_origin = s.t;
  m.steps_before = 0;
  m.integrator_at_state = false;
  m.new_segment();  // its first frame, below, gives the references
  const Forces forces = m.start_here(s.t);
  m.observer->observe(m.state, forces, false);
}

RunSummary Simulation::summary() const { return impl_->summary_now(); }

RunSummary Simulation::finish() {
  Impl& m = *impl_;
  if (!m.finished && m.failure.empty()) {  // the checks on one run repeated finer
    const RunSummary judged = summary();
    RefinedRun refined(m, judged);
    m.summary.resolution = check_resolution(m, judged, refined);
    m.derived = check_derived(judged, refined);
  }
  RunSummary s = summary();
  if (!m.finished && m.writer)
    m.finish_output(m.failure.empty() ? (s.stop_reason.empty() ? "completed" : "stopped: " + s.stop_reason)
                                      : "failed: " + m.failure);
  m.finished = true;
  return s;
}
RunSummary run_scene(const Scene& scene, PluginRegistry& registry, const RunOptions& options) {
  Simulation sim(scene, registry, options);
  sim.integrate(scene.run.t_end);
  return sim.finish();
}
}  // namespace noether
