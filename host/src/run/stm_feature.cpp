// The state-transition matrix as a run feature (stm_feature.hpp).
#include "run/stm_feature.hpp"

#include <noether/error.hpp>

namespace noether::detail {

void StmFeature::start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) {
  if (state.tangent.rows() == rows_ && state.tangent.cols() == rows_)
    columns = state.tangent;
  else
    columns.setIdentity();
}

void StmFeature::refuse_state(const State& state) const {
  const Eigen::MatrixXd& V = state.tangent;
  if (V.size() > 0 && (V.rows() != rows_ || V.cols() != rows_ || !V.allFinite()))
    throw Error("set_state: the tangent must be " + std::to_string(rows_) + " × " + std::to_string(rows_) +
                " (6 coordinates per body and 6 per rigid body, docs/equations.md eq. 21.1) and finite");
}

void StmFeature::read_frame(const io::RecordedFrame& frame, Eigen::Ref<Eigen::MatrixXd> columns) const {
  if (frame.stm.rows() != rows_ || frame.stm.cols() != rows_)
    throw Error("its frames do not hold the state-transition matrix the scene's run carries (run.stm)");
  columns = frame.stm;
}

}  // namespace noether::detail
