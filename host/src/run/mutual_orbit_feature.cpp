// The mutual orbit of a two-body-like scene as a run feature (mutual_orbit_feature.hpp).
#include "run/mutual_orbit_feature.hpp"

#include <noether/error.hpp>

#include "run/summary_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace noether::detail {

MutualOrbitFeature::MutualOrbitFeature(const System& system, std::size_t a, std::size_t b)
    : system_(system), a_(static_cast<Eigen::Index>(std::min(a, b))), b_(static_cast<Eigen::Index>(std::max(a, b))) {}

void MutualOrbitFeature::start_at(const State& state) {
  timing_ = false;
  e1_ = e2_ = Vec3::Zero();
  t0_ = t_prev_ = angle_prev_ = swept_ = 0.0;
  revolutions_ = 0;
  period_ = std::numeric_limits<double>::quiet_NaN();
  const Vec3 r = relative(state), v = state.p.col(b_) / system_.body(static_cast<std::size_t>(b_)).mass -
                                      state.p.col(a_) / system_.body(static_cast<std::size_t>(a_)).mass;
  const Vec3 h = r.cross(v);
  if (!(h.norm() > 0)) return;  // a radial fall: no orbit to time
  timing_ = true;
  e1_ = r.normalized();
  e2_ = h.cross(r).normalized();
  t0_ = t_prev_ = state.t;
}

void MutualOrbitFeature::track(const State& state) {
  if (!timing_ || state.t <= t_prev_) return;
  const Vec3 r = relative(state);
  const double angle = std::atan2(r.dot(e2_), r.dot(e1_));
  double step = angle - angle_prev_;
  step -= 2 * std::numbers::pi * std::round(step / (2 * std::numbers::pi));  // to (−π, π]
  const double before = swept_, after = before + step;
  for (double turn = 2 * std::numbers::pi * (revolutions_ + 1); after >= turn && after > before;
       turn += 2 * std::numbers::pi) {
    const double t_turn = t_prev_ + (turn - before) / (after - before) * (state.t - t_prev_);
    ++revolutions_;
    period_ = (t_turn - t0_) / revolutions_;
  }
  swept_ = after;
  angle_prev_ = angle;
  t_prev_ = state.t;
}

void MutualOrbitFeature::observe_frame(const State& state, bool first_of_segment, RunSummary&) {
  if (first_of_segment) start_at(state);
  track(state);
}

void MutualOrbitFeature::save_running(SavedSummary& out) const {
  out.numbers.push_back({"mutual_orbit",
                         {timing_ ? 1.0 : 0.0, e1_.x(), e1_.y(), e1_.z(), e2_.x(), e2_.y(), e2_.z(), t0_, t_prev_,
                          angle_prev_, swept_, static_cast<double>(revolutions_), period_}});
}

void MutualOrbitFeature::restore_running(const SavedSummary& in) {
  const std::vector<double>* v = in.number("mutual_orbit");
  if (!v) return;  // an older checkpoint: timed from the loaded state
  if (v->size() != 13) throw Error("its mutual orbit's running values are not 13 numbers");
  const std::vector<double>& n = *v;
  timing_ = n[0] != 0.0;
  e1_ = Vec3(n[1], n[2], n[3]);
  e2_ = Vec3(n[4], n[5], n[6]);
  t0_ = n[7], t_prev_ = n[8], angle_prev_ = n[9], swept_ = n[10];
  revolutions_ = static_cast<int>(n[11]);
  period_ = n[12];
}

void MutualOrbitFeature::summarize(RunSummary& summary) const {
  summary.mutual_pair = timing_ ? system_.body(static_cast<std::size_t>(a_)).name + "–" +
                                      system_.body(static_cast<std::size_t>(b_)).name
                                : std::string();
  summary.mutual_period = period_;
  summary.mutual_revolutions = revolutions_;
}

}  // namespace noether::detail
