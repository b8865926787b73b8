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

// J_r⁻¹(φ) = ∂ log(exp(S(φ)) exp(S(θ)))/∂θ at θ = 0 = I + ½ S(φ) + c S(φ)², with
// c = 1/x² − (1 + cos x)/(2 x sin x) at x = ‖φ‖ (below 1e-2 its series 1/12 + x²/720 + x⁴/30240).
Mat3 inverse_right_jacobian(const Vec3& phi) {
  const double x = phi.norm();
  const double c = x < 1e-2 ? 1.0 / 12 + x * x / 720 + std::pow(x, 4) / 30240
                            : 1 / (x * x) - (1 + std::cos(x)) / (2 * x * std::sin(x));
  const Mat3 S = hat(phi);
  return Mat3::Identity() + 0.5 * S + c * S * S;
}

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

MatrixXd tangent_monodromy(const FullBodyModel& model, const PluginConfig& integrator, const PhaseChart& chart,
                           double T, const Mat3& Q) {
  auto method = model.registry->make_integrator(integrator.plugin, model.system, model.potential, integrator.params);
  if (!method->tangent_map_unavailable().empty()) return {};
  const System& sys = model.system;
  const auto n = static_cast<Index>(sys.size()), m = static_cast<Index>(sys.rigid_count());
  const Index N = State::tangent_rows(sys), q = 3 * n + 3 * m;
  const VectorXd& scale = chart.scale();
  // D retract at 0 (19.4): z's coordinates per chart coordinate. x = x_b + s_x δ_x,
  // γ = γ_b + m s_v δ_v, R = R_b exp(S(s_η δ_η)) (θ = s_η δ_η at δ = 0), Π = Π_b + s_Π δ_Π.
  MatrixXd A = MatrixXd::Zero(N, chart.dimension());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto j = static_cast<Index>(i);
    for (Index a = 0; a < 3; ++a) {
      A(3 * j + a, chart.x(i) + a) = scale[chart.x(i) + a];
      A(q + 3 * j + a, chart.v(i) + a) = sys.body(i).mass * scale[chart.v(i) + a];
    }
  }
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    const auto r = static_cast<Index>(k);
    for (Index a = 0; a < 3; ++a) {
      A(3 * n + 3 * r + a, chart.eta(k) + a) = scale[chart.eta(k) + a];
      A(q + 3 * n + 3 * r + a, chart.Pi(k) + a) = scale[chart.Pi(k) + a];
    }
  }
  State s = chart.retract(VectorXd::Zero(chart.dimension()));
  s.t = 0;
  s.tangent = A;
  NullObserver null;
  advance(*method, *model.potential, sys, s, Schedule{T, T, Events{0.0, false, {}}, {}}, null);
  const State end = rotated(s, Q);
  // D local at the end: the inverse scales, and for an attitude ∂ log(R_bᵀ R exp(S(θ)))/∂θ = J_r⁻¹(φ)
  // at φ = log(R_bᵀ R) (≈ I near a closed orbit).
  MatrixXd B = MatrixXd::Zero(chart.dimension(), N);
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto j = static_cast<Index>(i);
    for (Index a = 0; a < 3; ++a) {
      B(chart.x(i) + a, 3 * j + a) = 1.0 / scale[chart.x(i) + a];
      B(chart.v(i) + a, q + 3 * j + a) = 1.0 / (sys.body(i).mass * scale[chart.v(i) + a]);
    }
  }
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    const auto r = static_cast<Index>(k);
    const Mat3 J = inverse_right_jacobian(log_so3(chart.base().R[k].transpose() * end.R[k]));
    for (Index a = 0; a < 3; ++a) {
      for (Index b = 0; b < 3; ++b) B(chart.eta(k) + b, 3 * n + 3 * r + a) = J(b, a) / scale[chart.eta(k) + b];
      B(chart.Pi(k) + a, q + 3 * n + 3 * r + a) = 1.0 / scale[chart.Pi(k) + a];
    }
  }
  return B * end.tangent;
}

MatrixXd conserved_gradients(const FullBodyModel& model, const PhaseChart& chart, const Eigen::Matrix3Xd& axes) {
  const System& sys = model.system;
  const State& s = chart.base();
  const VectorXd& scale = chart.scale();
  const Forces f = model.forces(s);
  const Vec3 c = model.barycentre(s), vc = model.barycentre_velocity(s);
  VectorXd dE = VectorXd::Zero(chart.dimension());
  Eigen::Matrix3Xd dL = Eigen::Matrix3Xd::Zero(3, chart.dimension());  // L about the barycentre
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto j = static_cast<Index>(i);
    const double m = sys.body(i).mass;
    const Vec3 gamma = s.p.col(j);
    // E = Σ |γ_i|²/2m_i + Σ ½ Π_kᵀ J_k⁻¹ Π_k + U: ∂E/∂x_i = −f_i, ∂E/∂γ_i = γ_i/m_i (γ_i = m_i v_i).
    // L = Σ x_i × γ_i − M c × v_c: ∂L/∂x_i = e × (γ_i − m_i v_c), ∂L/∂γ_i = (x_i − c) × e.
    for (Index a = 0; a < 3; ++a) {
      const Index ix = chart.x(i) + a, iv = chart.v(i) + a;
      const Vec3 e = Vec3::Unit(a);
      dE[ix] = -f.f(a, j) * scale[ix];
      dE[iv] = gamma[a] * scale[iv];
      dL.col(ix) = e.cross(gamma - m * vc) * scale[ix];
      dL.col(iv) = m * (s.x.col(j) - c).cross(e) * scale[iv];
    }
  }
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    const auto r = static_cast<Index>(k);
    const Vec3 Pi = s.Pi.col(r), Omega = sys.body(sys.body_of_rigid(k)).inertia_inverse * Pi;
    // R_k → R_k exp(S(η)): ∂U/∂η = −M_k (the body-frame moment, §2), ∂(R_k Π_k)/∂η = R_k (e × Π_k);
    // ∂E/∂Π_k = Ω_k, ∂L/∂Π_k = R_k.
    for (Index a = 0; a < 3; ++a) {
      const Index ie = chart.eta(k) + a, ip = chart.Pi(k) + a;
      const Vec3 e = Vec3::Unit(a);
      dE[ie] = -f.M(a, r) * scale[ie];
      dE[ip] = Omega[a] * scale[ip];
      dL.col(ie) = s.R[k] * e.cross(Pi) * scale[ie];
      dL.col(ip) = s.R[k] * e * scale[ip];
    }
  }
  MatrixXd out(1 + axes.cols(), chart.dimension());
  out.row(0) = dE.transpose();
  out.bottomRows(axes.cols()) = axes.transpose() * dL;
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
