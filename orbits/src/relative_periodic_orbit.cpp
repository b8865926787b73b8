#include <noether/error.hpp>
#include <noether/phase_chart.hpp>
#include <noether/relative_periodic_orbit.hpp>
#include <noether/stepping.hpp>

#include "differences.hpp"
#include "relative_orbit_support.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace noether {

using detail::barycentric;
using detail::complement;
using detail::orbit_chart;
using detail::jacobian_by_differences;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

class NullObserver final : public Observer {
 public:
  void observe(const State&, const Forces&, bool) override {}
};

}  // namespace

State integrator_map(const FullBodyModel& model, const PluginConfig& integrator, const State& s, double T) {
  auto method = model.registry->make_integrator(integrator.plugin, model.system, model.potential, integrator.params);
  State out = s;
  out.t = 0;
  NullObserver null;
  advance(*method, *model.potential, model.system, out, Schedule{T, T, Events{0.0, false, {}}, {}}, null);
  return out;
}

State rotated(const State& s, const Mat3& Q) {
  State out = s;
  out.x = Q * s.x;
  out.p = Q * s.p;
  for (auto& R : out.R) R = Q * R;
  return out;
}

RelativeClosure relative_closure(const FullBodyModel& model, const PluginConfig& integrator, const State& s, double T) {
  if (model.n() < 2) throw SceneError("relative periodic orbit: needs at least two bodies (a line of centres to turn)");
  if (!(T > 0)) throw SceneError("relative periodic orbit: the period must be positive");
  const State base = barycentric(model, s);
  const Vec3 L = model.angular_momentum(base);
  if (!(L.norm() > 0)) throw SceneError("relative periodic orbit: the state has no angular momentum to turn about");
  const Vec3 k = L.normalized();
  RelativeClosure out;
  out.end = integrator_map(model, integrator, base, T);
  const auto line = [&](const State& x) {
    const Vec3 d = x.x.col(1) - x.x.col(0);
    return Vec3(d - k * k.dot(d));
  };
  const Vec3 a = line(base), b = line(out.end);
  out.angle = std::atan2(a.cross(b).dot(k), a.dot(b));
  out.closure = orbit_chart(model, base, T).local(rotated(out.end, exp_so3(-out.angle * k))).cwiseAbs().maxCoeff();
  return out;
}

RelativePeriodicOrbit shoot_relative_periodic_orbit(const FullBodyModel& model, const PluginConfig& integrator,
                                                    const State& guess, double period, double angle,
                                                    double tolerance, int max_iterations) {
  if (!(period > 0)) throw SceneError("relative periodic orbit: the period must be positive");
  RelativePeriodicOrbit orbit;
  orbit.period = period;
  const State base = barycentric(model, guess);
  const Vec3 L = model.angular_momentum(base);
  if (!(L.norm() > 0)) throw SceneError("relative periodic orbit: the state has no angular momentum to turn about");
  orbit.axis = L.normalized();
  const PhaseChart chart = orbit_chart(model, base, period);
  const Index d = chart.dimension();
  // (19.1): u = (δ, α) ↦ local(Rot(−α) Φ_T(retract(δ))) − δ, and L·k̂ held at the guess's
  // (at fixed T the orbits form a family along which Newton would otherwise drift).
  const double L0 = L.norm();
  const auto residual = [&](const VectorXd& u) {
    const State start = chart.retract(u.head(d));
    const State end = integrator_map(model, integrator, start, period);
    VectorXd r(d + 1);
    r.head(d) = chart.local(rotated(end, exp_so3(-u[d] * orbit.axis))) - u.head(d);
    r[d] = (model.angular_momentum(start).dot(orbit.axis) - L0) / L0;
    return r;
  };
  VectorXd u = VectorXd::Zero(d + 1);
  u[d] = angle;
  const auto newton = detail::gauss_newton(residual, u, tolerance, max_iterations);
  orbit.initial_closure = newton.first;
  orbit.closure = newton.last;
  orbit.iterations = newton.iterations;
  orbit.state = chart.retract(u.head(d));
  orbit.angle = u[d];
  return orbit;
}

OrbitMultipliers relative_orbit_multipliers(const FullBodyModel& model, const PluginConfig& integrator,
                                            const RelativePeriodicOrbit& orbit, double tolerance) {
  const System& sys = model.system;
  const State base = barycentric(model, orbit.state);
  const PhaseChart chart = orbit_chart(model, base, orbit.period);
  const Index d = chart.dimension();
  const Mat3 back = exp_so3(-orbit.angle * orbit.axis);
  const auto map = [&](const VectorXd& delta) {
    return VectorXd(chart.local(rotated(integrator_map(model, integrator, chart.retract(delta), orbit.period), back)));
  };
  const VectorXd zero = VectorXd::Zero(d);
  const MatrixXd M = jacobian_by_differences(map, zero, 1e-5);  // (19.2)
  const auto conserved = [&](const VectorXd& delta) {
    const State s = chart.retract(delta);
    VectorXd c(2);
    c << model.energy(s), model.angular_momentum(s).dot(orbit.axis);
    return c;
  };
  const MatrixXd dC = jacobian_by_differences(conserved, zero, 1e-6);  // 2 × d
  // The symmetry directions: rotations of the whole state, and the flow F(s) itself.
  MatrixXd P(d, 4);
  const Vec3 e1 = orbit.axis.unitOrthogonal(), e2 = orbit.axis.cross(e1);
  P.col(0) = chart.rotation_generator(e1);
  P.col(1) = chart.rotation_generator(e2);
  P.col(2) = chart.rotation_generator(orbit.axis);
  {
    const Forces f = model.forces(base);
    VectorXd F(d);
    for (std::size_t i = 0; i < sys.size(); ++i) {
      const auto j = static_cast<Index>(i);
      F.segment<3>(chart.x(i)) = base.p.col(j) / sys.body(i).mass;
      F.segment<3>(chart.v(i)) = f.f.col(j) / sys.body(i).mass;
    }
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      const Vec3 Pi = base.Pi.col(static_cast<Index>(r)), Omega = sys.body(sys.body_of_rigid(r)).inertia_inverse * Pi;
      F.segment<3>(chart.eta(r)) = Omega;
      F.segment<3>(chart.Pi(r)) = Pi.cross(Omega) + f.M.col(static_cast<Index>(r));
    }
    P.col(3) = F.cwiseQuotient(chart.scale());
  }
  const MatrixXd V = chart.barycentre_free_basis();
  OrbitMultipliers out;
  // Does the map conserve E? The flow does; a symplectic map conserves a modified energy
  // instead, and has no time-shift symmetry: then only L·k̂ and the rotations are projected out,
  // and a pair of multipliers near 1 remains (docs/equations.md §19).
  const VectorXd dE = dC.row(0).transpose();
  out.energy_defect = (M.transpose() * dE - dE).norm() / std::max(1e-300, dE.norm());
  out.energy_conserved = out.energy_defect < 1e-6;
  MatrixXd W(V.cols(), out.energy_conserved ? 6 : 4);
  W.col(0) = V.transpose() * dC.row(1).transpose();
  W.middleCols(1, 3) = V.transpose() * P.leftCols(3);
  if (out.energy_conserved) W.col(4) = V.transpose() * dE, W.col(5) = V.transpose() * P.col(3);
  // A relative equilibrium has dE = ω dL and F = ω ∂_k: those columns are then dependent, to
  // the differencing's precision.
  const MatrixXd Q = V * complement(W, 1e-6);
  Eigen::EigenSolver<MatrixXd> es(Q.transpose() * M * Q, false);
  out.multipliers.assign(es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size());
  std::sort(out.multipliers.begin(), out.multipliers.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
  out.max_modulus = out.multipliers.empty() ? 0.0 : std::abs(out.multipliers.front());
  {
    const MatrixXd MP = M * P;
    const MatrixXd outside = MP - P * P.completeOrthogonalDecomposition().solve(MP);
    const VectorXd dL = dC.row(1).transpose();
    out.invariance_defect = std::max(outside.leftCols(out.energy_conserved ? 4 : 3).norm() / std::max(1e-300, M.norm() * P.norm()),
                                     (M.transpose() * dL - dL).norm() / std::max(1e-300, dL.norm()));
  }
  out.verdict = out.max_modulus <= 1 + tolerance ? "linearly stable"
                : out.max_modulus > 1 + 100 * tolerance ? "unstable" : "undecided";
  return out;
}

}  // namespace noether
