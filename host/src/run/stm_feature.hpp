#pragma once
// The state-transition matrix as a run feature (run.stm, --stm; docs/derivatives.md,
// "State-transition matrix"): the tangent's first N columns, N = 6 per body and 6 per rigid
// body (docs/equations.md eq. 21.1), which the integrator's tangent map carries step by step.
// It starts at the identity — or at the matrix a state set from outside carries — and each frame
// writes it to /derivatives/stm, from which a continued run reads it back (checksummed).
#include "io/frame_schema.hpp"
#include "run/run_feature.hpp"

namespace noether::detail {

class StmFeature final : public RunFeature {
 public:
  explicit StmFeature(Eigen::Index rows) : rows_(rows) {}
  std::string_view name() const override { return "stm"; }
  Eigen::Index tangent_columns() const override { return rows_; }
  // The identity, or the N × N matrix `state` carries (Simulation::set_state given one).
  void start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) override;
  // Error unless a state's tangent is empty or N × N and finite.
  void refuse_state(const State& state) const override;
  void read_frame(const io::RecordedFrame& frame, Eigen::Ref<Eigen::MatrixXd> columns) const override;

 private:
  Eigen::Index rows_;
};

}  // namespace noether::detail
