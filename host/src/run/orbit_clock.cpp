// The period of one pair's relative orbit from the trajectory (orbit_clock.hpp).
#include "run/orbit_clock.hpp"

#include <cmath>
#include <numbers>

namespace noether::detail {

OrbitClock::OrbitClock(const System& system, std::size_t a, std::size_t b)
    : system_(system), a_(static_cast<Eigen::Index>(a)), b_(static_cast<Eigen::Index>(b)) {}

Vec3 OrbitClock::relative_velocity(const State& state) const {
  return state.p.col(b_) / system_.body(static_cast<std::size_t>(b_)).mass -
         state.p.col(a_) / system_.body(static_cast<std::size_t>(a_)).mass;
}

void OrbitClock::start_at(const State& state) {
  timing_ = false;
  e1_ = e2_ = Vec3::Zero();
  t0_ = t_prev_ = state.t;
  angle_prev_ = swept_ = 0.0;
  rate_prev_ = std::numeric_limits<double>::quiet_NaN();
  revolutions_ = 0;
  period_ = std::numeric_limits<double>::quiet_NaN();
  const Vec3 r = relative(state), h = r.cross(relative_velocity(state));
  if (!(h.norm() > 0)) return;  // a radial fall: no orbit to time
  timing_ = true;
  e1_ = r.normalized();
  e2_ = h.cross(r).normalized();
  rate_prev_ = rate(state);
}

double OrbitClock::rate(const State& state) const {
  const Vec3 r = relative(state), v = relative_velocity(state);
  const double x = r.dot(e1_), y = r.dot(e2_);
  return (x * v.dot(e2_) - y * v.dot(e1_)) / (x * x + y * y);  // d/dt atan2(y, x)
}

namespace {

// When the angle swept reaches `turn` between two frames, from its values s0 < turn <= s1 and
// rates w0, w1 there: the cubic Hermite interpolant's crossing, by bisection (its error O(Δt⁴);
// a linear one's, O(Δt²), is 0.3 s a crossing of Dimorphos' orbit after DART at 600 s frames).
// Without the rates (a checkpoint from before they were kept): the linear one.
double crossing(double t0, double s0, double w0, double t1, double s1, double w1, double turn) {
  const double dt = t1 - t0;
  if (!std::isfinite(w0) || !std::isfinite(w1)) return t0 + (turn - s0) / (s1 - s0) * dt;
  auto H = [&](double u) {  // the Hermite basis h00, h10, h01, h11 at u ∈ [0, 1]
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * s0 + (u3 - 2 * u2 + u) * dt * w0 + (-2 * u3 + 3 * u2) * s1 + (u3 - u2) * dt * w1;
  };
  double lo = 0.0, hi = 1.0;  // H(lo) < turn <= H(hi)
  for (int k = 0; k < 60 && hi - lo > 1e-16; ++k) (H(0.5 * (lo + hi)) < turn ? lo : hi) = 0.5 * (lo + hi);
  return t0 + hi * dt;
}

}  // namespace

void OrbitClock::track(const State& state) {
  if (!timing_ || state.t <= t_prev_) return;
  const Vec3 r = relative(state);
  const double angle = std::atan2(r.dot(e2_), r.dot(e1_)), w = rate(state);
  double step = angle - angle_prev_;
  step -= 2 * std::numbers::pi * std::round(step / (2 * std::numbers::pi));  // to (−π, π]
  // The nearest branch is the angle swept only when frames are well under half a turn apart:
  // more than a third of a turn, by the step or by the rates' trapezoid, and the period would
  // alias (a revolution lost between frames) — it is not measured.
  const double trapezoid = std::isfinite(rate_prev_) ? 0.5 * (rate_prev_ + w) * (state.t - t_prev_) : 0.0;
  if (std::max(std::abs(step), std::abs(trapezoid)) > 2 * std::numbers::pi / 3) undersampled_ = true;
  const double before = swept_, after = before + step;
  for (double turn = 2 * std::numbers::pi * (revolutions_ + 1); after >= turn && after > before;
       turn += 2 * std::numbers::pi) {
    const double t_turn = crossing(t_prev_, before, rate_prev_, state.t, after, w, turn);
    ++revolutions_;
    period_ = (t_turn - t0_) / revolutions_;
  }
  swept_ = after;
  angle_prev_ = angle;
  rate_prev_ = w;
  t_prev_ = state.t;
}

std::vector<double> OrbitClock::pack() const {
  return {timing_ ? 1.0 : 0.0, e1_.x(), e1_.y(), e1_.z(), e2_.x(), e2_.y(), e2_.z(), t0_, t_prev_, angle_prev_,
          swept_, static_cast<double>(revolutions_), period_, rate_prev_, undersampled_ ? 1.0 : 0.0};
}

bool OrbitClock::unpack(const std::vector<double>& n) {
  if (n.size() < 13 || n.size() > 15 || !(n[11] >= 0.0 && n[11] < 2e9)) return false;
  timing_ = n[0] != 0.0;
  e1_ = Vec3(n[1], n[2], n[3]);
  e2_ = Vec3(n[4], n[5], n[6]);
  t0_ = n[7], t_prev_ = n[8], angle_prev_ = n[9], swept_ = n[10];
  revolutions_ = static_cast<int>(n[11]);
  period_ = n[12];
  rate_prev_ = n.size() > 13 ? n[13] : std::numeric_limits<double>::quiet_NaN();
  undersampled_ = n.size() > 14 && n[14] != 0.0;
  return true;
}

}  // namespace noether::detail
