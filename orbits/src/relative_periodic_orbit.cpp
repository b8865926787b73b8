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
  // The tangent's rows of x and γ turn with them; θ (R Q-turned as Q R exp(S(θ))) and Π are
  // body-frame and do not.
  const auto n = static_cast<Index>(s.x.cols()), m = static_cast<Index>(s.R.size());
  for (Index i = 0; i < n && s.tangent.size() > 0; ++i) {
    out.tangent.middleRows(3 * i, 3) = Q * s.tangent.middleRows(3 * i, 3);
    out.tangent.middleRows(3 * n + 3 * m + 3 * i, 3) = Q * s.tangent.middleRows(3 * n + 3 * m + 3 * i, 3);
  }
  return out;
}

namespace {

// Φ_T from retract(δ) carrying the tangent ∂z/∂δ (PhaseChart::retract_derivative), turned by Q:
// the end state, whose tangent is ∂z(T)/∂δ of Rot(Q) Φ_T(retract(δ)). Empty tangent when the
// integrator carries none.
State carried_map(const FullBodyModel& model, const PluginConfig& integrator, const PhaseChart& chart, double T,
                  const Mat3& Q, const VectorXd& delta) {
  auto method = model.registry->make_integrator(integrator.plugin, model.system, model.potential, integrator.params);
  State s = chart.retract(delta);
  s.t = 0;
  if (method->tangent_map_unavailable().empty()) s.tangent = chart.retract_derivative(delta);
  NullObserver null;
  advance(*method, *model.potential, model.system, s, Schedule{T, T, Events{0.0, false, {}}, {}}, null);
  return rotated(s, Q);
}

// The gradients of E and of L·a (L about the barycentre) for each column a of `axes`, in the
// tangent coordinates z of `s` (21.1): rows (1 + axes.cols()) × (6n + 6r).
MatrixXd conserved_gradients_z(const FullBodyModel& model, const State& s, const Eigen::Matrix3Xd& axes) {
  const System& sys = model.system;
  const auto n = static_cast<Index>(sys.size()), m = static_cast<Index>(sys.rigid_count());
  const Index q = 3 * n + 3 * m;
  const Forces f = model.forces(s);
  const Vec3 c = model.barycentre(s), vc = model.barycentre_velocity(s);
  VectorXd dE = VectorXd::Zero(2 * q);
  Eigen::Matrix3Xd dL = Eigen::Matrix3Xd::Zero(3, 2 * q);
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto j = static_cast<Index>(i);
    const double mass = sys.body(i).mass;
    const Vec3 gamma = s.p.col(j);
    // E = Σ |γ_i|²/2m_i + Σ ½ Π_kᵀ J_k⁻¹ Π_k + U: ∂E/∂x_i = −f_i, ∂E/∂γ_i = γ_i/m_i.
    // L = Σ x_i × γ_i − M c × v_c: ∂L/∂x_i = e × (γ_i − m_i v_c), ∂L/∂γ_i = (x_i − c) × e.
    for (Index a = 0; a < 3; ++a) {
      const Vec3 e = Vec3::Unit(a);
      dE[3 * j + a] = -f.f(a, j);
      dE[q + 3 * j + a] = gamma[a] / mass;
      dL.col(3 * j + a) = e.cross(gamma - mass * vc);
      dL.col(q + 3 * j + a) = (s.x.col(j) - c).cross(e);
    }
  }
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    const auto r = static_cast<Index>(k);
    const Vec3 Pi = s.Pi.col(r), Omega = sys.body(sys.body_of_rigid(k)).inertia_inverse * Pi;
    // R_k → R_k exp(S(θ)): ∂U/∂θ = −M_k (the body-frame moment, §2), ∂(R_k Π_k)/∂θ = R_k (e × Π_k);
    // ∂E/∂Π_k = Ω_k, ∂L/∂Π_k = R_k.
    for (Index a = 0; a < 3; ++a) {
      const Vec3 e = Vec3::Unit(a);
      dE[3 * n + 3 * r + a] = -f.M(a, r);
      dE[q + 3 * n + 3 * r + a] = Omega[a];
      dL.col(3 * n + 3 * r + a) = s.R[k] * e.cross(Pi);
      dL.col(q + 3 * n + 3 * r + a) = s.R[k] * e;
    }
  }
  MatrixXd out(1 + axes.cols(), 2 * q);
  out.row(0) = dE.transpose();
  out.bottomRows(axes.cols()) = axes.transpose() * dL;
  return out;
}

// d/dα of Rot(−α k̂) s in the tangent coordinates of s (already turned): δx = −k̂ × x,
// δγ = −k̂ × γ, θ = −Rᵀ k̂, δΠ = 0.
VectorXd turn_generator(const State& s, const Vec3& k) {
  const auto n = s.x.cols(), m = static_cast<Index>(s.R.size()), q = 3 * n + 3 * m;
  VectorXd g = VectorXd::Zero(2 * q);
  for (Index i = 0; i < n; ++i) {
    g.segment<3>(3 * i) = -k.cross(Vec3(s.x.col(i)));
    g.segment<3>(q + 3 * i) = -k.cross(Vec3(s.p.col(i)));
  }
  for (Index r = 0; r < m; ++r) g.segment<3>(3 * n + 3 * r) = -(s.R[static_cast<std::size_t>(r)].transpose() * k);
  return g;
}

}  // namespace

MatrixXd tangent_monodromy(const FullBodyModel& model, const PluginConfig& integrator, const PhaseChart& chart,
                           double T, const Mat3& Q) {
  // (19.4): D local at the end × Rot(Q) D Φ_T × D retract at 0.
  const State end = carried_map(model, integrator, chart, T, Q, VectorXd::Zero(chart.dimension()));
  if (end.tangent.size() == 0) return {};
  return chart.local_derivative(end) * end.tangent;
}

MatrixXd conserved_gradients(const FullBodyModel& model, const PhaseChart& chart, const Eigen::Matrix3Xd& axes) {
  return conserved_gradients_z(model, chart.base(), axes) * chart.retract_derivative(VectorXd::Zero(chart.dimension()));
}

namespace detail {

MatrixXd closure_jacobian(const FullBodyModel& model, const PluginConfig& integrator, const PhaseChart& chart,
                          double T, const Vec3& k, double L0, const VectorXd& u) {
  const Index d = chart.dimension();
  const State end = carried_map(model, integrator, chart, T, exp_so3(-u[d] * k), u.head(d));
  if (end.tangent.size() == 0) return {};
  const MatrixXd B = chart.local_derivative(end);
  MatrixXd J(d + 1, d + 1);
  J.topLeftCorner(d, d) = B * end.tangent - MatrixXd::Identity(d, d);
  J.topRightCorner(d, 1) = B * turn_generator(end, k);
  const Eigen::Matrix3Xd axis = k;
  J.bottomLeftCorner(1, d) =
      conserved_gradients_z(model, chart.retract(u.head(d)), axis).row(1) * chart.retract_derivative(u.head(d)) / L0;
  J(d, d) = 0;
  return J;
}

}  // namespace detail

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
                                                    double tolerance, int max_iterations, bool differenced) {
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
  const auto tangent_jacobian = [&](const VectorXd& u) {
    return detail::closure_jacobian(model, integrator, chart, period, orbit.axis, L0, u);
  };
  orbit.jacobian = detail::newton_jacobian(model, integrator, differenced);
  VectorXd u = VectorXd::Zero(d + 1);
  u[d] = angle;
  const auto newton = orbit.jacobian == "tangent map"
                          ? detail::gauss_newton(residual, tangent_jacobian, u, tolerance, max_iterations,
                                                 detail::kFlatDirections)
                          : detail::gauss_newton(residual, u, tolerance, max_iterations);
  orbit.initial_closure = newton.first;
  orbit.closure = newton.last;
  orbit.iterations = newton.iterations;
  orbit.state = chart.retract(u.head(d));
  orbit.angle = u[d];
  return orbit;
}

OrbitMultipliers relative_orbit_multipliers(const FullBodyModel& model, const PluginConfig& integrator,
                                            const RelativePeriodicOrbit& orbit, double tolerance, bool differenced) {
  const System& sys = model.system;
  const State base = barycentric(model, orbit.state);
  const PhaseChart chart = orbit_chart(model, base, orbit.period);
  const Index d = chart.dimension();
  const Mat3 back = exp_so3(-orbit.angle * orbit.axis);
  const auto map = [&](const VectorXd& delta) {
    return VectorXd(chart.local(rotated(integrator_map(model, integrator, chart.retract(delta), orbit.period), back)));
  };
  const VectorXd zero = VectorXd::Zero(d);
  OrbitMultipliers out;
  // (19.2): from the integrator's tangent map where it has one (19.4), else by differences.
  MatrixXd M = differenced ? MatrixXd() : tangent_monodromy(model, integrator, chart, orbit.period, back);
  out.monodromy = M.size() > 0 ? "tangent map" : "differences";
  if (M.size() == 0) M = jacobian_by_differences(map, zero, 1e-5);
  const Vec3 e1 = orbit.axis.unitOrthogonal(), e2 = orbit.axis.cross(e1);
  Eigen::Matrix3d axes;
  axes << orbit.axis, e1, e2;
  // 4 × d: E, L·k̂, L·e1, L·e2, analytic. Near a relative equilibrium dE ≈ ω dL·k̂ (on the
  // synchronous moon's 3° libration orbit the two rows are 6e-6 from parallel), and the
  // subspace where both are fixed is found to the gradients' error divided by that angle:
  // differenced gradients (error ~1e-10) put a pair of multipliers 1.6e-5 off the unit circle.
  const MatrixXd dC = conserved_gradients(model, chart, axes);
  // The symmetry directions: rotations of the whole state, and the flow F(s) itself.
  MatrixXd P(d, 4);
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
  // Does the map conserve E? The flow does; a symplectic map conserves a modified energy
  // instead, and has no time-shift symmetry: then only L·k̂ and the rotations are projected out,
  // and a pair of multipliers near 1 remains (docs/equations.md §19).
  const VectorXd dE = dC.row(0).transpose();
  out.energy_defect = (M.transpose() * dE - dE).norm() / std::max(1e-300, dE.norm());
  out.energy_conserved = out.energy_defect < 1e-6;
  // The invariant subspace S: barycentre-free, with L (all three components: L⊥ = 0 is kept,
  // its pair turned by α) and, for a flow, E fixed; then the quotient by the symmetries that lie
  // in S — the rotation about k̂ and, for a flow, the flow itself. (The rotations about e1, e2
  // change L⊥ and are not in S: compressing M onto a complement that is orthogonal to them is
  // not the quotient map, and left a pair ~1e-5 off the unit circle.)
  MatrixXd W(V.cols(), out.energy_conserved ? 6 : 4);
  W.col(0) = V.transpose() * dC.row(1).transpose();
  W.col(1) = V.transpose() * dC.row(2).transpose();
  W.col(2) = V.transpose() * dC.row(3).transpose();
  W.col(3) = V.transpose() * P.col(2);
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
