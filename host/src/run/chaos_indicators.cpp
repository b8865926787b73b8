// MEGNO (Cincotta & Simó 2000) and the fast Lyapunov indicator (Froeschlé, Lega & Gonczi 1997)
// from one deviation vector of the tangent map: docs/equations.md §23.
#include "run/chaos_indicators.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace noether {

ChaosIndicators::ChaosIndicators(const System& system, const State& initial) {
  const auto n = static_cast<Eigen::Index>(system.size());
  double L = 0.0, M = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    M += system.body(static_cast<std::size_t>(i)).mass;
    for (Eigen::Index j = i + 1; j < n; ++j) L = std::max(L, (initial.x.col(i) - initial.x.col(j)).norm());
  }
  const double length = L > 0.0 && std::isfinite(L) ? L : 1.0;
  const double GM = system.G() * M;
  const double T = GM > 0.0 && std::isfinite(GM) ? std::sqrt(length * length * length / GM) : 1.0;  // the dynamical time
  set_scales(system, length, T);
}

void ChaosIndicators::set_scales(const System& system, double L, double T) {
  const auto n = static_cast<Eigen::Index>(system.size()), m = static_cast<Eigen::Index>(system.rigid_count());
  L_ = L;
  T_ = T;
  // Eq. 23.1: z = (x, θ, γ, Π) (eq. 21.1), each coordinate divided by its scale.
  weights_.resize(6 * (n + m));
  weights_.segment(0, 3 * n).setConstant(1.0 / L_);
  weights_.segment(3 * n, 3 * m).setConstant(1.0);
  for (Eigen::Index i = 0; i < n; ++i)
    weights_.segment(3 * (n + m) + 3 * i, 3).setConstant(T_ / (system.body(static_cast<std::size_t>(i)).mass * L_));
  for (Eigen::Index k = 0; k < m; ++k) {
    const double J = system.body(system.body_of_rigid(static_cast<std::size_t>(k))).inertia.trace() / 3.0;
    weights_.segment(6 * n + 3 * m + 3 * k, 3).setConstant(T_ / J);
  }
}

Eigen::VectorXd ChaosIndicators::initial_deviation() const {
  // A fixed seed and the generator's own bits (std::mt19937_64 is the same everywhere; the
  // standard's distributions are not), so that every run of a system starts from the same δ0.
  std::mt19937_64 bits(0x6d65676e6f);  // "megno"
  Eigen::VectorXd d(weights_.size());
  for (Eigen::Index r = 0; r < d.size(); ++r) d(r) = 2.0 * static_cast<double>(bits() >> 11) * 0x1p-53 - 1.0;
  d = d.cwiseQuotient(weights_);
  return d / norm(d);
}

void ChaosIndicators::start(double t0, const Eigen::VectorXd& delta0) {
  t0_ = t_ = t0;
  log_norm_ = log_norm0_ = std::log(norm(delta0));
  weighted_sum_ = y_integral_ = y_ = 0.0;
  max_log10_ = 0.0;
  values_ = ChaosValues{};
  values_.t = t0;
}

void ChaosIndicators::step(double t, const Eigen::VectorXd& delta) {
  if (values_.overflowed || !(t > t_)) return;
  const double log_norm = std::log(norm(delta));
  if (!std::isfinite(log_norm)) {
    values_.overflowed = true;
    return;
  }
  const double s_prev = t_ - t0_, s = t - t0_;
  // Eq. 23.2 on the step [s_prev, s]: ∫ s d ln‖δ‖ by the midpoint of s (exact for ln‖δ‖ linear
  // in s: an exponential growth gives Y = λ s exactly).
  weighted_sum_ += 0.5 * (s_prev + s) * (log_norm - log_norm_);
  const double y = 2.0 * weighted_sum_ / s;
  y_integral_ += 0.5 * (y_ + y) * (s - s_prev);  // eq. 23.3, trapezoidal
  y_ = y;
  log_norm_ = log_norm;
  t_ = t;
  max_log10_ = std::max(max_log10_, (log_norm - log_norm0_) / std::log(10.0));
  values_.megno = y_integral_ / s;
  values_.megno_y = y;
  values_.fli = max_log10_;
  values_.lyapunov = (log_norm - log_norm0_) / s;
  values_.t = t;
}

void ChaosIndicators::save(double* out) const {
  const double numbers[kCheckpointSize] = {L_, T_, t0_, t_, log_norm_, log_norm0_, weighted_sum_, y_integral_, y_,
                                           max_log10_, values_.megno, values_.megno_y, values_.fli, values_.lyapunov,
                                           values_.t, values_.overflowed ? 1.0 : 0.0};
  std::copy(numbers, numbers + kCheckpointSize, out);
}

void ChaosIndicators::restore(const System& system, const double* in) {
  set_scales(system, in[0], in[1]);
  t0_ = in[2], t_ = in[3], log_norm_ = in[4], log_norm0_ = in[5];
  weighted_sum_ = in[6], y_integral_ = in[7], y_ = in[8], max_log10_ = in[9];
  values_ = values_of(in);
}

ChaosValues ChaosIndicators::values_of(const double* in) {
  ChaosValues v;
  v.megno = in[10], v.megno_y = in[11], v.fli = in[12], v.lyapunov = in[13], v.t = in[14];
  v.overflowed = in[15] != 0.0;
  return v;
}

}  // namespace noether
