#pragma once
// Simulation::Impl: what a run held open consists of (internal to libnoether; simulation.cpp
// drives it, continuation.cpp resumes, saves and loads it).
#include <noether/output.hpp>
#include <noether/particles.hpp>
#include <noether/simulation.hpp>

#include "run/particle_feature.hpp"
#include "run/run_features.hpp"
#include "run/sensitivity_feature.hpp"
#include "io/frame_schema.hpp"
#include "run/run_statistics.hpp"

#include <chrono>
#include <cmath>
#include <memory>

namespace noether {

using Clock = std::chrono::steady_clock;
using detail::operator+;

// The errors a finished run estimated for the numbers it derives (`from`: check_derived's
// summary) put on the same numbers of `into` — the mutual period, each period change (by its
// time), each libration (by its body) — however the features rebuilt them (derived_check.cpp).
void with_derived_errors(const RunSummary& from, RunSummary& into);

struct Simulation::Impl {
  Scene scene;
  PluginRegistry* registry = nullptr;  // what made the plugins (the resolution check makes more)
  RunOptions options;
  int threads = 1;  // RunOptions::threads resolved (the environment's when 0)
  std::shared_ptr<const Potential> potential;
  std::shared_ptr<const Forcing> forcing;  // the scene's forces (none: null)
  std::vector<PairModel> pair_models_before;  // a continued run's file's (RunRecord::pair_models)
  std::shared_ptr<Integrator> integrator;
  std::unique_ptr<H5Writer> writer;
  RunSummary summary;
  std::unique_ptr<detail::RunStatistics> observer;
  State state;
  double t_origin = 0.0;            // the time of step 0 and frame 0
  std::int64_t steps_before = 0;    // fixed-step methods: steps from t_origin to state.t
  bool integrator_at_state = false; // the integrator stands at `state` (no start() needed)
  WorkCounters base_work{0, 0, 0, 0};  // work of the run this one continues
  double wall_seconds = 0.0;           // wall time spent integrating (and of the run continued)
  Clock::time_point call_start = Clock::now();
  bool in_call = false, finished = false;
  // The run is the scene's own trajectory from its initial state (no state set from outside, not
  // loaded from a file): what the step-halving checks repeat.
  bool scene_trajectory = true;
  // The finished run's summary with the errors of its derived numbers (check_derived), which
  // every later summary carries (with_derived_errors).
  std::optional<RunSummary> derived;
  bool custom_potential = false;  // the potential was given in code, not made from the scene
  std::string failure;  // the error that ended the run, if any
  // The run features (run_features.cpp's list), in the order of their tangent columns: the
  // tangent is [STM | chaos δ | sensitivities]. The sensitivities' keys and parameters name the
  // output's and the impulses' columns (null, empty without them).
  std::vector<std::unique_ptr<detail::RunFeature>> features;
  // Feature k's columns of the tangent are [column_begin[k], column_begin[k + 1]), its
  // checkpointed fields [field_begin[k], field_begin[k + 1]) of a frame's, the numbers of its
  // series [series_begin[k], series_begin[k + 1]) of a frame's (one entry more than features:
  // the ends).
  std::vector<Eigen::Index> column_begin{0};
  std::vector<std::size_t> field_begin{0}, series_begin{0};
  // The keys of run.sensitivities (the tangent's last columns: ∂z/∂key), the parameters of the
  // dynamics among them (the last of those).
  std::vector<std::string> sensitivity_names;
  std::shared_ptr<const ParameterDerivatives> parameters;
  // The scene's massless particles (particles.hpp), which their feature carries.
  ParticleSwarm* particles = nullptr;

  bool carries_tangent() const { return scene.run.carries_tangent(); }
  // The scene's run features, at the initial state (before the tangent is made: their columns
  // are in it).
  void make_features() {
    features = detail::make_run_features({scene, *integrator, state, *potential, *registry, custom_potential, forcing, threads});
    for (const auto& f : features) {
      column_begin.push_back(column_begin.back() + f->tangent_columns());
      field_begin.push_back(field_begin.back() + f->fields().size());
      std::size_t numbers = 0;
      for (const FeatureSeries& s : f->series()) numbers += s.size();
      series_begin.push_back(series_begin.back() + numbers);
      if (auto* p = dynamic_cast<detail::ParticleFeature*>(f.get())) particles = &p->swarm();
      if (auto* s = dynamic_cast<detail::SensitivityFeature*>(f.get())) {
        sensitivity_names = s->names();
        parameters = s->parameters();
      }
    }
  }
  // The feature whose jump comes first, and its time (equal times: the list's order), if any.
  std::pair<detail::RunFeature*, double> next_jump() const {
    std::pair<detail::RunFeature*, double> first{nullptr, 0.0};
    for (const auto& f : features)
      if (const std::optional<double> t = f->next_jump(); t && (!first.first || *t < first.second)) first = {f.get(), *t};
    return first;
  }
  // Feature k's columns of V (a tangent), and its fields among a frame's.
  template <class Matrix>
  auto columns_of(std::size_t k, Matrix& V) const {
    return V.middleCols(column_begin[k], column_begin[k + 1] - column_begin[k]);
  }
  std::span<const double> fields_of(std::size_t k, std::span<const double> fields) const {
    return fields.subspan(field_begin[k], field_begin[k + 1] - field_begin[k]);
  }
  // The features' series (the output file's rows they fill) and their numbers at a frame the
  // run writes, or at a recorded frame a continued run copies (from its fields, when it holds
  // them: a file from before they were kept does not, which restore_features refuses by name).
  std::vector<FeatureSeries> feature_series() const {
    std::vector<FeatureSeries> out;
    for (const auto& f : features)
      for (FeatureSeries& s : f->series()) out.push_back(std::move(s));
    return out;
  }
  std::span<double> series_of(std::size_t k, std::vector<double>& numbers) const {
    return std::span<double>(numbers).subspan(series_begin[k], series_begin[k + 1] - series_begin[k]);
  }
  std::vector<double> series_values(const State& at) const {
    std::vector<double> out(series_begin.back());
    for (std::size_t k = 0; k < features.size(); ++k) features[k]->record(at, series_of(k, out));
    return out;
  }
  std::vector<double> recorded_series(const io::RecordedFrame& f) const {
    std::vector<double> out(series_begin.back());
    const bool fields = f.features.size() == field_begin.back();
    for (std::size_t k = 0; k < features.size(); ++k)
      features[k]->recorded(f, fields ? fields_of(k, f.features) : std::span<const double>{}, series_of(k, out));
    return out;
  }
  // The features started where the run stands, their columns of V filled.
  void start_features(Eigen::MatrixXd& V) {
    for (std::size_t k = 0; k < features.size(); ++k)
      features[k]->start(state, columns_of(k, V));
  }
  // The features started where the run stands (t0, a new segment): the tangent made of their
  // columns — [STM | the others' | sensitivities] — when the run carries one.
  void start_features_here() {
    const Eigen::Index N = State::tangent_rows(scene.system);
    if (!carries_tangent()) {
      Eigen::MatrixXd none(N, 0);
      start_features(none);
      return;
    }
    Eigen::MatrixXd V = Eigen::MatrixXd::Zero(N, column_begin.back());
    start_features(V);
    state.tangent = std::move(V);
  }
  // After each step (the stepping loop's Schedule::after_step).
  void features_after_step(const State& reached) {
    for (std::size_t k = 0; k < features.size(); ++k)
      features[k]->after_step(reached, columns_of(k, reached.tangent));
  }
  // The features' checkpointed fields: their names, and their values where the run stands (its
  // tangent columns: `at`'s, the state a frame holds).
  std::vector<std::string> feature_fields() const {
    std::vector<std::string> out;
    for (const auto& f : features)
      for (std::string& name : f->fields()) out.push_back(std::move(name));
    return out;
  }
  std::vector<double> feature_values(const State& at) const {
    std::vector<double> out(field_begin.back());
    for (std::size_t k = 0; k < features.size(); ++k)
      features[k]->save(columns_of(k, at.tangent),
                        std::span<double>(out).subspan(field_begin[k], field_begin[k + 1] - field_begin[k]));
    return out;
  }
  // The tangent a recorded frame holds — [STM | the features' columns | sensitivities] —, the
  // columns of features that keep them among their fields zero (restore_features puts them
  // back); empty without a tangent.
  Eigen::MatrixXd recorded_tangent(const io::RecordedFrame& at, const std::filesystem::path& file) const {
    const bool stm = scene.run.stm, sensitivities = !sensitivity_names.empty();
    if ((!stm && at.stm.size() > 0) || (!sensitivities && at.sensitivity.size() > 0))
      throw Error(file.string() + ": its frames hold a tangent the scene's run does not carry (run.stm, run.sensitivities)");
    if (!carries_tangent()) return {};
    Eigen::MatrixXd V = Eigen::MatrixXd::Zero(State::tangent_rows(scene.system), column_begin.back());
    try {
      for (std::size_t k = 0; k < features.size(); ++k) features[k]->read_frame(at, columns_of(k, V));
    } catch (const Error& e) {
      throw Error(file.string() + ": " + e.what());
    }
    return V;
  }
  // The features put back where a frame's fields say they stood, their columns of V too.
  void restore_features(const std::vector<double>& fields, Eigen::MatrixXd& V, const std::filesystem::path& file) {
    if (fields.size() != field_begin.back())
      throw Error(file.string() + ": its frames do not hold the fields of the run's features (" +
                  std::to_string(fields.size()) + " numbers; /checkpoint/run_features)");
    for (std::size_t k = 0; k < features.size(); ++k) features[k]->restore(fields_of(k, fields), columns_of(k, V));
  }
  // A jump (an impulse) took the run from `before` to `after` at the same positions (potential
  // energy U): the statistics' references move by it (RunStatistics::impulse), the features
  // measure afresh from `after`.
  void jumped(const State& before, const State& after, double U) {
    observer->impulse(before, after, U);
    for (const auto& f : features) f->after_jump(before, after);
  }
  // How many jumps (impulses) a recorded frame says the features had made.
  // (A frame without the features' fields — a file from before they were kept — holds none.)
  std::size_t jumps_in(const io::RecordedFrame& f) const {
    if (f.features.size() != field_begin.back()) return 0;
    std::size_t jumps = 0;
    for (std::size_t k = 0; k < features.size(); ++k) jumps += features[k]->jumps_in(fields_of(k, f.features));
    return jumps;
  }

  // Starts the integrator afresh at `state` (a new segment, an impulse), which stands at time t;
  // the forces there.
  Forces start_here(double t) {
    Forces forces;
    forces.resize(scene.system);
    integrator->start(state);
    integrator->current(state, forces);
    state.t = t;
    integrator_at_state = true;
    return forces;
  }

  WorkCounters work() const { return base_work + integrator->work(); }
  // The potential's forces and U at `at`, outside the integration (no work counted): a frame
  // the run did not step to (a saved one, a loaded one, a replayed frame 0).
  Forces forces_at(const State& at) const {
    Forces forces;
    forces.resize(scene.system);
    potential->evaluate(at, forces, *potential->make_workspace());
    return forces;
  }
  // The summary where the run stands, with every feature's part, judged (Simulation::summary, and
  // the verdict the output file keeps).
  RunSummary summary_now() const {
    RunSummary s = summary;
    s.work = work();
    s.wall_seconds = wall_now();
    s.final_state = state;
    s.pair_models = pair_models();
    s.warnings = scene.warnings;  // the scene's input warnings, then the features' (an impulse's)
    for (const auto& feature : features) feature->summarize(s);
    if (derived) with_derived_errors(*derived, s);
    judge(s, scene);
    return s;
  }
  double wall_now() const {
    return wall_seconds + (in_call ? std::chrono::duration<double>(Clock::now() - call_start).count() : 0.0);
  }
  // What the tolerance-driven models chose: the potential's pairs (with what the steps saw), then
  // each force's bodies, named by the force; a tolerance exceeded before a continued run's file
  // ended stays reported (the first time it was).
  std::vector<PairModel> pair_models() const {
    const PotentialEvaluator* evaluator = integrator->potential_evaluator();
    std::vector<PairModel> out = evaluator ? evaluator->pair_models() : std::vector<PairModel>{};
    if (forcing)
      for (const ForceTerm& term : *forcing)
        for (PairModel model : term.model->pair_models()) {
          model.body_b = term.name;
          out.push_back(std::move(model));
        }
    for (PairModel& model : out)
      for (const PairModel& before : pair_models_before)
        if (before.exceeded && before.body_a == model.body_a && before.body_b == model.body_b) {
          model.exceeded = true;
          model.exceeded_time = before.exceeded_time;
          model.exceeded_separation = before.exceeded_separation;
          model.exceeded_error = before.exceeded_error;
        }
    return out;
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
    s.impulses = 0;
    s.impulse_energy = 0.0;
  }
  // Stands at a recorded frame: its state, the integrator's own variables, the work and wall
  // time spent to reach it (a continued or loaded run).
  void restore(const io::RecordedFrame& at, const std::filesystem::path& file) {
    state = at.state;
    state.tangent = recorded_tangent(at, file);
    restore_features(at.features, state.tangent, file);
    if (at.integrator.size() != integrator->checkpoint().size())
      throw Error(file.string() + ": its integrator checkpoint does not fit the scene's integrator");
    const std::int64_t evaluations = integrator->work().potential_evaluations;
    integrator->restore(state, at.integrator);  // its own variables where it has any, else the state
    integrator_at_state = true;
    base_work = at.work + WorkCounters{0, -evaluations, 0, 0};
    wall_seconds = at.wall_seconds;
  }
  // A new output file of the run's: the features keep what they keep beside their fields with
  // its blocks (the particles' checkpoint).
  void keep_features_with_writer() {
    if (!writer) return;
    for (const auto& f : features) f->keep_with(*writer);
  }
  void make_observer() {
    observer = std::make_unique<detail::RunStatistics>(
        scene.system, summary,
        [this](const State& s, const Diagnostics& d) {
          if (!writer) return;
          const std::vector<double> fields = features.empty() ? std::vector<double>{} : feature_values(s);
          writer->write_frame(s, d, work(), wall_now(), summary.interpolated_frames, integrator->checkpoint(),
                              series_values(s), fields);
        },
        [this](const State& s, bool first_of_segment) {
          for (const auto& f : features) f->observe_frame(s, first_of_segment, summary);
        });
  }
  // The output file's options; `continuation`: a resumed run's new file, which replaces the
  // old one once the recorded frames are in.
  OutputOptions output_options(bool continuation) const {
    const Scene& sc = scene;
    OutputOptions output;
    try {
      output.checkpoint_width = integrator->checkpoint().size();
    } catch (const Error&) {  // an integrator that could not start has no checkpoint
      output.checkpoint_width = 0;
    }
    output.stm_columns = scene.run.stm ? static_cast<std::size_t>(State::tangent_rows(scene.system)) : 0;
    output.sensitivity_names = sensitivity_names;
    output.feature_fields = feature_fields();
    output.feature_series = feature_series();
    for (const auto& f : summary.forces) output.force_names.push_back(f.name);
    output.custom_potential = custom_potential;
    output.t_origin = t_origin;
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
    for (const auto& f : features) f->finish(*writer, scene);
    const RunSummary judged = summary_now();  // the file's verdict is the summary's
    std::string reasons;
    for (const auto& r : judged.verdict.reasons) reasons += (reasons.empty() ? "" : "; ") + r;
    writer->set_verdict(judged.verdict.trustworthy ? "trustworthy" : "untrustworthy", reasons,
                        judged.max_rel_energy_error, judged.energy_scale);
    writer->finish(judged.work, wall_now(), outcome);
    writer.reset();
  }
};

// The resolution check of the smallest orbit, when the energy cannot certify it
// (resolution_check.cpp); `judged` is the summary so far. `refined`: the run repeated finer (at
// half its step, or at a tenfold tighter tolerance), made at most once for both checks.
class RefinedRun;
ResolutionCheck check_resolution(const Simulation::Impl& m, const RunSummary& judged, RefinedRun& refined);

// The errors of the numbers the run derives from its trajectory (the mutual period, the period
// changes, the libration, the rotation periods, the encounters, an event's time), by the run
// repeated finer (derived_check.cpp): `judged`, the summary so far, with them.
RunSummary check_derived(const RunSummary& judged, RefinedRun& refined);

}  // namespace noether
