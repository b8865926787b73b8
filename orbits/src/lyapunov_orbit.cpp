#include <noether/error.hpp>
#include <noether/lie.hpp>
#include <noether/lyapunov_orbit.hpp>

#include "differences.hpp"
#include "relative_orbit_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace noether {

using Eigen::Index;
using Eigen::VectorXd;

namespace {

// `integrator` with its step replaced (step > 0).
PluginConfig with_step(const PluginConfig& integrator, double step) {
  PluginConfig c = integrator;
  if (step > 0) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", step);
    c.params.set("step", Params::scalar(text));
  }
  return c;
}

}  // namespace

PluginConfig lyapunov_integrator(const PluginConfig& integrator, const LyapunovOrbit& orbit) {
  return with_step(integrator, orbit.step);
}

OrbitMultipliers lyapunov_multipliers(const FullBodyModel& model, const PluginConfig& integrator,
                                      const LyapunovOrbit& orbit, double tolerance) {
  OrbitMultipliers mu = relative_orbit_multipliers(model, lyapunov_integrator(integrator, orbit), orbit.orbit, tolerance);
  if (mu.energy_conserved) return mu;
  auto& m = mu.multipliers;
  for (int k = 0; k < 2 && !m.empty(); ++k) {
    const auto nearest = std::min_element(m.begin(), m.end(), [](auto a, auto b) { return std::abs(a - 1.0) < std::abs(b - 1.0); });
    if (std::abs(*nearest - 1.0) > 1e-3) break;
    mu.family.push_back(*nearest);
    m.erase(nearest);
  }
  mu.max_modulus = m.empty() ? 0.0 : std::abs(m.front());
  mu.verdict = mu.max_modulus <= 1 + tolerance ? "linearly stable"
               : mu.max_modulus > 1 + 100 * tolerance ? "unstable" : "undecided";
  return mu;
}

LyapunovOrbit lyapunov_orbit(const FullBodyModel& model, const PluginConfig& integrator, const RelativeEquilibrium& eq,
                             const NormalMode& mode, double amplitude, double tolerance, int max_iterations,
                             bool differenced) {
  if (!(mode.frequency > 0) || mode.shape.size() == 0)
    throw SceneError("Lyapunov orbit: the mode must oscillate (it has no frequency: '" + mode.kind + "')");
  if (!(amplitude > 0)) throw SceneError("Lyapunov orbit: the amplitude must be positive");
  const System& sys = model.system;
  const PhaseChart eq_chart = equilibrium_chart(model, eq);
  const Vec3 W = eq.rate * eq.axis;
  // The mode's eigenvector is defined modulo rotations of the whole configuration (the
  // linearisation is reduced by them, (18.4)): of its representatives, the one that moves the
  // bodies' centres least — a libration is then the body's turn alone, not half of it with the
  // line of centres turned back by the other half, which would move the centres linearly and
  // change the separation at second order.
  const Vec3 e1 = eq.axis.unitOrthogonal(), e2 = eq.axis.cross(e1);
  Eigen::MatrixXd P(eq_chart.dimension(), 3);
  P.col(0) = eq_chart.rotation_generator(e1, W);
  P.col(1) = eq_chart.rotation_generator(e2, W);
  P.col(2) = eq_chart.rotation_generator(eq.axis, W);
  const Index centres = 6 * static_cast<Index>(sys.size());  // the x and v blocks come first
  const Eigen::MatrixXcd Pc = P.cast<std::complex<double>>();
  const Eigen::VectorXcd c = Pc.topRows(centres).completeOrthogonalDecomposition().solve(mode.shape.head(centres));
  Eigen::VectorXcd v = mode.shape - Pc * c;
  // Turned so that its largest component is real: e = Re v, max |e_i| = 1.
  Index big = 0;
  v.cwiseAbs().maxCoeff(&big);
  v /= v[big];
  const VectorXd e = v.real();
  // (19.3) the equilibrium displaced by a e, as an inertial state (turning-frame velocities + W × x).
  const auto displaced = [&](double a) {
    State s = eq_chart.retract(a * e);
    for (std::size_t i = 0; i < sys.size(); ++i) {
      const auto j = static_cast<Index>(i);
      s.p.col(j) += sys.body(i).mass * W.cross(Vec3(s.x.col(j)));
    }
    return detail::barycentric(model, s);
  };
  LyapunovOrbit out;
  out.linear_period = 2 * std::numbers::pi / mode.frequency;
  const State guess = displaced(amplitude);
  const double T0 = out.linear_period;
  // A fixed step: N steps per period, held while T moves.
  const bool fixed_step = integrator.params.has("step");
  if (fixed_step) out.steps = std::max(1L, std::lround(T0 / integrator.params.at("step").as_double()));
  const auto config = [&](double T) { return with_step(integrator, fixed_step ? T / static_cast<double>(out.steps) : 0); };
  const PhaseChart chart = detail::orbit_chart(model, guess, T0);
  const Index d = chart.dimension();
  const Vec3 k = model.angular_momentum(guess).normalized();
  const double L0 = model.angular_momentum(guess).norm();
  // The displacement's direction in the orbit's chart (a central difference of a ↦ local(displaced(a))).
  const double h = 1e-4 * amplitude;
  VectorXd along = (chart.local(displaced(amplitude + h)) - chart.local(displaced(amplitude - h))) / (2 * h);
  if (!(along.norm() > 0)) throw SceneError("Lyapunov orbit: the mode moves nothing in the chart");
  along.normalize();
  // u = (δ, α, τ), T = T0 (1 + τ): the closure (19.1), L·k̂ held, nothing added along the mode.
  const auto residual = [&](const VectorXd& u) {
    const double T = T0 * (1 + u[d + 1]);
    if (!(T > 0.1 * T0)) return VectorXd(VectorXd::Constant(d + 2, NAN));  // a step too far: rejected, halved
    const State start = chart.retract(u.head(d));
    const State end = integrator_map(model, config(T), start, T);
    VectorXd r(d + 2);
    r.head(d) = chart.local(rotated(end, exp_so3(-u[d] * k))) - u.head(d);
    r[d] = (model.angular_momentum(start).dot(k) - L0) / L0;
    r[d + 1] = along.dot(u.head(d));
    return r;
  };
  // The Jacobian: the closure's (δ, α) columns from the tangent map (19.6) where the integrator
  // carries one; T's column by central differences (with a fixed step, T moves the step too).
  const auto tangent_jacobian = [&](const VectorXd& u) {
    const double T = T0 * (1 + u[d + 1]);
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(d + 2, d + 2);
    J.topLeftCorner(d + 1, d + 1) = detail::closure_jacobian(model, config(T), chart, T, k, L0, u.head(d + 1));
    J.block(d + 1, 0, 1, d) = along.transpose();
    const double dt = 1e-6;
    VectorXd plus = u, minus = u;
    plus[d + 1] += dt, minus[d + 1] -= dt;
    J.col(d + 1) = (residual(plus) - residual(minus)) / (2 * dt);
    return J;
  };
  out.orbit.jacobian = detail::newton_jacobian(model, integrator, differenced);
  VectorXd u = VectorXd::Zero(d + 2);
  u[d] = std::remainder(eq.rate * T0, 2 * std::numbers::pi);  // the frame's turn over one period
  const auto newton = out.orbit.jacobian == "tangent map"
                          ? detail::gauss_newton(residual, tangent_jacobian, u, tolerance, max_iterations,
                                                 detail::kFlatDirections)
                          : detail::gauss_newton(residual, u, tolerance, max_iterations);
  RelativePeriodicOrbit& orbit = out.orbit;
  orbit.period = T0 * (1 + u[d + 1]);
  orbit.angle = u[d];
  orbit.axis = k;
  orbit.state = chart.retract(u.head(d));
  orbit.initial_closure = newton.first;
  orbit.closure = newton.last;
  orbit.iterations = newton.iterations;
  if (fixed_step) out.step = orbit.period / static_cast<double>(out.steps);
  return out;
}

}  // namespace noether
