#pragma once
// RunFeature: what a run carries beside the bodies' state, as one unit with hooks the
// Simulation calls (docs/architecture.md, "Run features"): its columns of the tangent and their
// start, what it does after each step, its checkpointed fields (declared by name, so that a
// continued or loaded run restores them with no code of its own: /checkpoint/run_features) and
// its part of the summary. After REBOUND's field tables and its post-timestep hooks. One file per
// feature (chaos_feature.cpp); Simulation::Impl holds the list.
#include <noether/simulation.hpp>
#include <noether/state.hpp>

#include <Eigen/Dense>

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace noether::detail {

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
  // After each step the integrator takes, at the state reached (its columns: `columns`).
  virtual void after_step(const State& reached, Eigen::Ref<const Eigen::MatrixXd> columns) = 0;
  // Its checkpointed fields, one name per number; save writes them where the run stands (its
  // tangent columns there: `columns`), restore puts the feature and its columns back.
  virtual std::vector<std::string> fields() const = 0;
  virtual void save(Eigen::Ref<const Eigen::MatrixXd> columns, std::span<double> out) const = 0;
  virtual void restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd> columns) = 0;
  // Its part of the run's summary.
  virtual void summarize(RunSummary& summary) const = 0;
};

}  // namespace noether::detail
