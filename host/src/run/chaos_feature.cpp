// The chaos indicators as a run feature (chaos_feature.hpp; docs/equations.md §23).
#include "run/chaos_feature.hpp"

#include <noether/error.hpp>

namespace noether::detail {

void ChaosFeature::start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) {
  indicators_ = std::make_unique<ChaosIndicators>(system_, state);
  columns.col(0) = indicators_->initial_deviation();
  indicators_->start(state.t, columns.col(0));
}

void ChaosFeature::after_step(const State& reached, Eigen::Ref<const Eigen::MatrixXd> columns) {
  indicators_->step(reached.t, columns.col(0));  // eqs. 23.2–23.5
}

std::vector<std::string> ChaosFeature::fields() const {
  std::vector<std::string> out = {"chaos.length_scale", "chaos.time_scale", "chaos.t0", "chaos.t",
                                  "chaos.log_norm", "chaos.log_norm0", "chaos.weighted_log_norm_integral",
                                  "chaos.y_integral", "chaos.y", "chaos.max_log10_growth", "chaos.megno",
                                  "chaos.megno_y", "chaos.fli", "chaos.lyapunov", "chaos.values_t",
                                  "chaos.overflowed"};
  const Eigen::Index rows = State::tangent_rows(system_);
  for (Eigen::Index r = 0; r < rows; ++r) out.push_back("chaos.deviation." + std::to_string(r));
  return out;
}

void ChaosFeature::save(Eigen::Ref<const Eigen::MatrixXd> columns, std::span<double> out) const {
  indicators_->save(out.data());
  const Eigen::VectorXd delta = columns.col(0);
  std::copy(delta.data(), delta.data() + delta.size(), out.data() + ChaosIndicators::kCheckpointSize);
}

void ChaosFeature::restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd> columns) {
  if (in.size() != ChaosIndicators::kCheckpointSize + static_cast<std::size_t>(columns.rows()))
    throw Error("chaos: a checkpoint of " + std::to_string(in.size()) + " numbers does not fit this system");
  if (!indicators_) indicators_ = std::make_unique<ChaosIndicators>(system_, State::zeros(system_));
  indicators_->restore(system_, in.data());
  columns.col(0) = Eigen::Map<const Eigen::VectorXd>(in.data() + ChaosIndicators::kCheckpointSize, columns.rows());
}

void ChaosFeature::summarize(RunSummary& summary) const {
  summary.chaos = true;
  summary.chaos_values = values();
}

void ChaosFeature::record(const State&, std::span<double> out) const {
  out[0] = indicators_->values().megno;
  out[1] = indicators_->values().fli;
}

void ChaosFeature::recorded(const io::RecordedFrame&, std::span<const double> fields, std::span<double> out) const {
  const ChaosValues v = values_of(fields);
  out[0] = v.megno;
  out[1] = v.fli;
}

ChaosValues ChaosFeature::values_of(std::span<const double> fields) {
  return fields.size() >= ChaosIndicators::kCheckpointSize ? ChaosIndicators::values_of(fields.data()) : ChaosValues{};
}

}  // namespace noether::detail
