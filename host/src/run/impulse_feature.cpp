// The scene's impulses as a run feature (impulse_feature.hpp).
#include "run/impulse_feature.hpp"

#include <noether/error.hpp>

#include <algorithm>
#include <cmath>

namespace noether::detail {

ImpulseFeature::ImpulseFeature(const std::vector<Impulse>& impulses) : impulses_(impulses), order_(impulses.size()) {
  for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = k;
  std::stable_sort(order_.begin(), order_.end(),
                   [this](std::size_t a, std::size_t b) { return impulses_[a].time < impulses_[b].time; });
}

void ImpulseFeature::start(const State& state, Eigen::Ref<Eigen::MatrixXd>) {
  applied_ = 0;
  while (applied_ < order_.size() && impulses_[order_[applied_]].time <= state.t) ++applied_;
}

void ImpulseFeature::save(Eigen::Ref<const Eigen::MatrixXd>, std::span<double> out) const {
  out[0] = static_cast<double>(applied_);
}

void ImpulseFeature::restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd>) {
  if (in.size() != 1 || !(in[0] >= 0.0 && in[0] <= static_cast<double>(order_.size())) || in[0] != std::floor(in[0]))
    throw Error("impulses: a checkpoint's count of applied impulses does not fit the scene's " +
                std::to_string(order_.size()));
  applied_ = static_cast<std::size_t>(in[0]);
}

std::optional<std::size_t> ImpulseFeature::next() const {
  if (applied_ >= order_.size()) return std::nullopt;
  return order_[applied_];
}

}  // namespace noether::detail
