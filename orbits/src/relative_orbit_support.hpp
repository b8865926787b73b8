#pragma once
// Shared by the relative-periodic-orbit and Lyapunov-orbit code (not installed): a state moved
// to its barycentre's rest frame, the chart an orbit is shot in, and Φ_T(s) without an observer.
#include <noether/full_body_model.hpp>
#include <noether/phase_chart.hpp>
#include <noether/scene.hpp>

#include <algorithm>
#include <numbers>
#include <string>

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

// Shooting with an exact Jacobian does not step along directions where the closure changes at
// less than this fraction of its largest rate (docs/equations.md §19: a symmetry, or the discrete
// map's near-symmetry along its orbit, whose rate is the method's error and whose exact step
// would leave the linear regime); with the noise of a differenced Jacobian they are never seen.
inline constexpr double kFlatDirections = 1e-10;

// The Jacobian of the closure (19.1) at u = (δ, α) — the chart residual
// local(Rot(−α k̂) Φ_T(retract(δ))) − δ and (L·k̂ − L0)/L0 — from `integrator`'s tangent map
// (docs/equations.md eq. 19.6): (d + 1) × (d + 1), columns δ then α. Empty when the integrator
// carries no tangent map.
Eigen::MatrixXd closure_jacobian(const FullBodyModel& model, const PluginConfig& integrator, const PhaseChart& chart,
                                 double T, const Vec3& k, double L0, const Eigen::VectorXd& u);

// The shooting's Jacobian for `integrator`: "tangent map" when it carries one (and the caller did
// not ask for `differenced`), else "differences" (RelativePeriodicOrbit::jacobian).
inline std::string newton_jacobian(const FullBodyModel& model, const PluginConfig& integrator, bool differenced) {
  if (differenced) return "differences";
  auto method = model.registry->make_integrator(integrator.plugin, model.system, model.potential, integrator.params);
  return method->tangent_map_unavailable().empty() ? "tangent map" : "differences";
}

}  // namespace noether::detail
