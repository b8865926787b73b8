#pragma once
// RunFeature: what a run carries beside the bodies' state, as one unit with hooks the
// Simulation calls (docs/architecture.md, "Run features"): its columns of the tangent and their
// start, what it does before and after each step, at each frame, at a state set from outside and
// at the times it changes the state itself (impulses); its checkpointed fields (declared by name,
// so that a continued or loaded run restores them with no code of its own:
// /checkpoint/run_features), its running statistics in a saved simulation, and its part of the
// summary; and its own series of the output file. After REBOUND's field tables and its
// pre-/post-timestep hooks. One file per feature
// (chaos_feature.cpp, particle_feature.cpp, …); run_features.cpp is the one list of them.
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/state.hpp>
#include <noether/stepping.hpp>

#include <Eigen/Dense>

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace noether {
struct ParameterDerivatives;
}  // namespace noether
namespace noether::io {
struct RecordedFrame;
class RunRecord;
}  // namespace noether::io

namespace noether::detail {

struct SavedSummary;

// What a feature's jump (RunFeature::jump) may read and change: the state where the run stands,
// at the jump's time, its tangent laid out as [STM | the features' columns | sensitivities].
struct StateJump {
  State& state;
  const std::vector<std::string>& sensitivity_names;   // the tangent's last columns
  const ParameterDerivatives* parameters;               // the dynamics' parameters among them (last)
  std::function<void(const State&, Forces&)> forces_at;  // the potential's forces, by the run's evaluator
};

class RunFeature {
 public:
  virtual ~RunFeature() = default;
  // Its name, which prefixes its fields' ("chaos.t0").
  virtual std::string_view name() const = 0;
  // How many columns of State::tangent it carries.
  virtual Eigen::Index tangent_columns() const { return 0; }
  // Starts it where the run stands (t0, or a new segment: Simulation::set_state), its tangent
  // columns' values there written into `columns`.
  virtual void start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) = 0;
  // A state set from outside (Simulation::set_state) before the run takes it: every feature may
  // refuse it first (throws Error, nothing changed), then each moves what it holds there; then
  // clears what `state` carries for the feature's new segment (the forces' balance).
  virtual void refuse_state(const State&) const {}
  virtual void accept_state(const State&) {}
  virtual void begin_segment(State&) {}
  // Before the steps of a call to integrate, from the state the run stands at.
  virtual void before_steps(const State&) {}
  // After each step the integrator takes, at the state reached (its columns: `columns`).
  virtual void after_step(const State&, Eigen::Ref<const Eigen::MatrixXd>) {}
  // Each frame the run observes (also the recorded frames a continued run replays);
  // `first_of_segment` at a segment's first. It may keep running statistics in `summary`.
  virtual void observe_frame(const State&, bool /*first_of_segment*/, RunSummary&) {}
  // What cuts the steps the run takes where the feature says (the events: the stepping loop's
  // StepCut), ending the run there; null: none.
  virtual StepCut* step_cut() { return nullptr; }
  // Its series of the output file: rows of the frame schema that a feature fills
  // (io/frame_schema.cpp, kByFeature), each with the shape of its frame. Their numbers, in that
  // order and row-major: `record`, at each frame the run writes (the frame's state); `recorded`,
  // at a recorded frame a continued run copies, from its fields there (`fields`) or, by default,
  // from the series read back (Error when the frame lacks one).
  virtual std::vector<FeatureSeries> series() const { return {}; }
  virtual void record(const State&, std::span<double> /*out*/) const {}
  virtual void recorded(const io::RecordedFrame& frame, std::span<const double> fields, std::span<double> out) const;
  // A change the feature makes to the state at a time of its own (an impulse): the next such
  // time, if any; the change, made there (the run then starts its integrator again and
  // observes the frame after it); and how many it had made at a frame, from the frame's fields.
  virtual std::optional<double> next_jump() const { return std::nullopt; }
  virtual void jump(StateJump&) {}
  virtual std::size_t jumps_in(std::span<const double> /*fields*/) const { return 0; }
  // After any feature's jump, from the state before it to the state after (also one a continued
  // run's replayed frames show): what the feature measures from a segment's start starts again
  // there (the mutual orbit); what the jump did is judged (an impulse that unbinds a pair).
  virtual void after_jump(const State& /*before*/, const State& /*after*/) {}
  // Its tangent columns as a recorded frame holds them in series of their own (the STM's,
  // the sensitivities'; Error when the frame does not hold them); features whose columns are
  // among their fields leave them (restore puts them back).
  virtual void read_frame(const io::RecordedFrame&, Eigen::Ref<Eigen::MatrixXd>) const {}
  // Its checkpointed fields, one name per number; save writes them where the run stands (its
  // tangent columns there: `columns`), restore puts the feature and its columns back.
  virtual std::vector<std::string> fields() const { return {}; }
  virtual void save(Eigen::Ref<const Eigen::MatrixXd>, std::span<double>) const {}
  virtual void restore(std::span<const double>, Eigen::Ref<Eigen::MatrixXd>) {}
  // What it keeps in the output file beside its fields, too large for every frame (the
  // particles: /checkpoint/particles): kept with the blocks of a file the run writes from now on
  // (`keep_with`, at each new file), written where the run stands as a file's frame `frame`
  // (`save_into`: a saved simulation's, a continued run's new file; `refuse_save` first, Error
  // when it cannot be), and read back where a continued or loaded run stood at
  // its last frame (`continue_from`: Error naming what the file lacks). `finish`: its tables,
  // written when the run ends (/test_particles).
  virtual void keep_with(H5Writer&) {}
  virtual void refuse_save(const State&) const {}
  virtual void save_into(H5Writer&, std::int64_t /*frame*/) const {}
  virtual void continue_from(const io::RunRecord&, std::size_t /*last*/, double /*t_last*/) {}
  virtual void finish(H5Writer&, const Scene&) const {}
  // Its running statistics in a saved simulation (/checkpoint/summary), and back; restore
  // throws Error naming what the checkpoint lacks.
  virtual void save_running(SavedSummary&) const {}
  virtual void restore_running(const SavedSummary&) {}
  // Its part of the run's summary, where the run stands (summary.final_state is set).
  virtual void summarize(RunSummary&) const {}
};

}  // namespace noether::detail
