#pragma once
// Shared by the relative-periodic-orbit and Lyapunov-orbit code (not installed): a state moved
// to its barycentre's rest frame, the chart an orbit is shot in, and Φ_T(s) without an observer.
#include <noether/full_body_model.hpp>
#include <noether/phase_chart.hpp>

#include <algorithm>
#include <numbers>

namespace noether::detail {

// The state with its barycentre at rest at the origin.
inline State barycentric(const FullBodyModel& model, State s) {
  const Vec3 c = model.barycentre(s), vc = model.barycentre_velocity(s);
  s.x.colwise() -= c;
  for (std::size_t i = 0; i < model.n(); ++i)
    s.p.col(static_cast<Eigen::Index>(i)) -= model.system.body(i).mass * vc;
  return s;
}

// The chart at s: lengths scaled by the largest distance from the barycentre, rates by 2π/T.
inline PhaseChart orbit_chart(const FullBodyModel& model, const State& s, double period) {
  return PhaseChart(model.system, s, std::max(1e-300, s.x.colwise().norm().maxCoeff()), 2 * std::numbers::pi / period);
}

}  // namespace noether::detail
