#include <noether/error.hpp>
#include <noether/relative_equilibrium.hpp>

#include "differences.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace noether {

using detail::complement;
using detail::jacobian_by_differences;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

std::string format(double v) { return (std::ostringstream() << v).str(); }

// The rotation that takes the unit vector a to the unit vector b along the shorter arc.
Mat3 rotation_between(const Vec3& a, const Vec3& b) {
  const Vec3 axis = a.cross(b);
  const double s = axis.norm();
  if (s < 1e-15) return Mat3::Identity();
  return exp_so3(axis / s * std::atan2(s, a.dot(b)));
}

}  // namespace

namespace {

// The unknowns of (18.2) and the state they stand for: u = (δx_i / ℓ, η_k, δω / ω0), the
// configuration x_i = x̄_i + ℓ δx_i, R_k = R̄_k exp(S(η_k)) turning at ω = ω0 (1 + u_last) about
// k̂ through its barycentre (which is put at the origin).
struct EquilibriumUnknowns {
  const FullBodyModel& model;
  Eigen::Matrix3Xd x;  // the guess's positions, relative to its barycentre
  std::vector<Mat3> R;
  Vec3 k;
  double length, rate0;

  Index size() const { return static_cast<Index>(3 * model.n() + 3 * model.rigid() + 1); }
  double rate(const VectorXd& u) const { return rate0 * (1 + u[size() - 1]); }

  State state(const VectorXd& u) const {
    const System& sys = model.system;
    State s = State::zeros(sys);
    const double w = rate(u);
    for (std::size_t i = 0; i < sys.size(); ++i)
      s.x.col(static_cast<Index>(i)) = x.col(static_cast<Index>(i)) + length * u.segment<3>(3 * static_cast<Index>(i));
    s.x.colwise() -= model.barycentre(s);
    for (std::size_t i = 0; i < sys.size(); ++i)
      s.p.col(static_cast<Index>(i)) = sys.body(i).mass * w * k.cross(Vec3(s.x.col(static_cast<Index>(i))));
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      s.R[r] = R[r] * exp_so3(u.segment<3>(static_cast<Index>(3 * sys.size() + 3 * r)));
      s.Pi.col(static_cast<Index>(r)) = sys.body(sys.body_of_rigid(r)).inertia * (w * s.R[r].transpose() * k);  // Π = J Ω, Ω = ω Rᵀk̂
    }
    return s;
  }
};

}  // namespace

RelativeEquilibrium find_relative_equilibrium(const FullBodyModel& model, const State& guess,
                                              const EquilibriumOptions& options) {
  const System& sys = model.system;
  const std::size_t n = sys.size();
  if (n < 2) throw SceneError("relative equilibria need at least two bodies (one body about a fixed centre has no barycentre to turn about)");
  if (options.fix == EquilibriumFamily::separation &&
      (options.body_a >= n || options.body_b >= n || options.body_a == options.body_b))
    throw SceneError("relative equilibrium: the pair whose separation is fixed must be two different bodies of the scene");
  {  // Σ f_i = 0: a potential of mutual gravity, invariant under translations and rotations
    const Forces f = model.forces(guess);
    const double sum = f.f.rowwise().sum().norm(), largest = f.f.colwise().norm().maxCoeff();
    if (!(sum <= 1e-9 * largest))
      throw SceneError("relative equilibria need a potential of mutual gravity (forces that sum to zero); this scene's "
                       "forces sum to " + format(sum) + " against " + format(largest) +
                       " for the largest (an external field such as central-field has no relative equilibria of this kind)");
  }
  const Vec3 L = model.angular_momentum(guess);
  if (!(L.norm() > 0))
    throw SceneError("relative equilibrium: the scene's total angular momentum about its barycentre is zero, so there "
                     "is no axis to turn about; give the bodies an orbital velocity");

  EquilibriumUnknowns eq{model, guess.x, guess.R, L.normalized(), 0, 0};
  eq.x.colwise() -= model.barycentre(guess);
  eq.length = eq.x.colwise().norm().maxCoeff();
  RelativeEquilibrium out;
  out.axis = eq.k;
  if (options.align)
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      Eigen::SelfAdjointEigenSolver<Mat3> es(sys.body(sys.body_of_rigid(r)).inertia);
      if (es.eigenvalues().maxCoeff() - es.eigenvalues().minCoeff() <= 1e-12 * es.eigenvalues().maxCoeff()) continue;
      Index best = 0;
      for (Index j = 1; j < 3; ++j)
        if (std::abs(eq.k.dot(eq.R[r] * es.eigenvectors().col(j))) > std::abs(eq.k.dot(eq.R[r] * es.eigenvectors().col(best))))
          best = j;
      Vec3 a = eq.R[r] * es.eigenvectors().col(best);
      if (a.dot(eq.k) < 0) a = -a;
      double turn = std::acos(std::clamp(a.dot(eq.k), -1.0, 1.0));
      eq.R[r] = rotation_between(a, eq.k) * eq.R[r];
      // Two bodies: the in-plane principal axis nearest to the line of centres onto it (the
      // nearest of the four symmetric orientations: long or short axis towards the other body).
      const std::size_t self = sys.body_of_rigid(r);
      if (n == 2) {
        const Vec3 to_other = eq.x.col(static_cast<Index>(1 - self)) - eq.x.col(static_cast<Index>(self));
        const Vec3 line = (to_other - eq.k * eq.k.dot(to_other)).normalized();
        Vec3 nearest = Vec3::Zero();
        for (Index j = 0; j < 3; ++j) {
          if (j == best) continue;
          const Vec3 e = eq.R[r] * es.eigenvectors().col(j);
          const Vec3 c = e.dot(line) >= 0 ? e : Vec3(-e);
          if (c.dot(line) > nearest.dot(line)) nearest = c;
        }
        const double angle = std::atan2(nearest.cross(line).dot(eq.k), nearest.dot(line));
        eq.R[r] = exp_so3(angle * eq.k) * eq.R[r];
        turn = std::max(turn, std::abs(angle));
      }
      out.alignment = std::max(out.alignment, turn);
    }

  // ω0 from the centripetal balance of the guess: Σ m_i (−a_i · d_i) = ω² Σ m_i ‖d_i‖², d_i ⟂ k̂.
  {
    State s = guess;
    s.x = eq.x;
    s.R = eq.R;
    const Forces f = model.forces(s);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d = eq.x.col(static_cast<Index>(i)) - eq.k * eq.k.dot(eq.x.col(static_cast<Index>(i)));
      num -= f.f.col(static_cast<Index>(i)).dot(d);
      den += sys.body(i).mass * d.squaredNorm();
    }
    if (!(num > 0 && den > 0))
      throw SceneError("relative equilibrium: the bodies of the guess do not attract each other towards the axis of "
                       "the angular momentum, so no rate ω balances them");
    eq.rate0 = std::sqrt(num / den);
  }
  if (options.fix == EquilibriumFamily::rate && !(std::isnan(options.value) || options.value > 0))
    throw SceneError("relative equilibrium: the rate must be positive, not " + format(options.value));

  const VectorXd zero = VectorXd::Zero(eq.size());
  const auto constraint_value = [&](const State& s, double w) {
    switch (options.fix) {
      case EquilibriumFamily::separation:
        return (s.x.col(static_cast<Index>(options.body_a)) - s.x.col(static_cast<Index>(options.body_b))).norm();
      case EquilibriumFamily::angular_momentum: return model.angular_momentum(s).dot(eq.k);
      case EquilibriumFamily::rate: return w;
    }
    return 0.0;
  };
  double target = options.value;
  if (std::isnan(target)) {
    if (options.fix == EquilibriumFamily::separation)
      target = (guess.x.col(static_cast<Index>(options.body_a)) - guess.x.col(static_cast<Index>(options.body_b))).norm();
    else if (options.fix == EquilibriumFamily::angular_momentum) target = L.norm();
    else target = eq.rate0;
  }
  if (!(target > 0)) throw SceneError("relative equilibrium: the fixed separation, angular momentum or rate must be positive");
  const double target_scale = target;

  // The residual (18.2), scaled: centripetal balance per body, moment balance per rigid body,
  // and the member of the family.
  const auto residual = [&](const VectorXd& u) {
    const State s = eq.state(u);
    const Forces f = model.forces(s);
    const double w = eq.rate(u), a_scale = eq.rate0 * eq.rate0 * eq.length;
    VectorXd res(eq.size());
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d = s.x.col(static_cast<Index>(i)) - eq.k * eq.k.dot(s.x.col(static_cast<Index>(i)));
      res.segment<3>(3 * static_cast<Index>(i)) = (f.f.col(static_cast<Index>(i)) / sys.body(i).mass + w * w * d) / a_scale;
    }
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      const Mat3& J = sys.body(sys.body_of_rigid(r)).inertia;
      const Vec3 Omega = w * s.R[r].transpose() * eq.k;
      res.segment<3>(static_cast<Index>(3 * n + 3 * r)) =
          (f.M.col(static_cast<Index>(r)) - Omega.cross(J * Omega)) / (eq.rate0 * eq.rate0 * 0.5 * J.trace());
    }
    res[eq.size() - 1] = (constraint_value(s, w) - target) / target_scale;
    return res;
  };

  VectorXd u = zero;
  const auto newton = detail::gauss_newton(residual, u, options.tolerance, options.max_iterations);
  out.residual = newton.last;
  out.iterations = newton.iterations;
  out.converged = out.residual <= options.tolerance;
  // (18.2) with a separation fixed is even in ω: the mirror solution −ω is the same
  // configuration turning the other way; report the one turning about +k̂.
  u[eq.size() - 1] = std::abs(1 + u[eq.size() - 1]) - 1;
  out.state = eq.state(u);
  out.rate = eq.rate(u);
  out.separation = n >= 2 ? (out.state.x.col(static_cast<Index>(options.body_a)) -
                             out.state.x.col(static_cast<Index>(options.body_b))).norm() : 0.0;
  out.angular_momentum = model.angular_momentum(out.state).dot(eq.k);
  out.contact = sys.body(options.body_a).radius + sys.body(options.body_b).radius;
  out.energy = model.energy(out.state);
  return out;
}

const NormalMode* libration_mode(const EquilibriumStability& stability, const std::string& body) {
  for (const auto& m : stability.modes)
    if (m.kind == "libration of " + body && m.frequency > 0) return &m;
  return nullptr;
}

PhaseChart equilibrium_chart(const FullBodyModel& model, const RelativeEquilibrium& eq) {
  State base = eq.state;
  base.p.setZero();  // velocities in the turning frame: zero at the equilibrium
  const double length = std::max(1e-300, base.x.colwise().norm().maxCoeff());
  return PhaseChart(model.system, std::move(base), length, eq.rate);
}

EquilibriumStability linear_stability(const FullBodyModel& model, const RelativeEquilibrium& eq, double tolerance) {
  const System& sys = model.system;
  const PhaseChart chart = equilibrium_chart(model, eq);
  const Vec3 W = eq.rate * eq.axis;  // the frame's angular velocity
  const Index d = chart.dimension();

  // The vector field of the turning frame (18.3) in the chart's scaled coordinates.
  const auto field = [&](const VectorXd& delta) {
    const State s = chart.retract(delta);
    const Forces f = model.forces(s);
    VectorXd dot(d);
    for (std::size_t i = 0; i < sys.size(); ++i) {
      const auto j = static_cast<Index>(i);
      const Vec3 x = s.x.col(j), u = s.p.col(j) / sys.body(i).mass;
      dot.segment<3>(chart.x(i)) = u;
      dot.segment<3>(chart.v(i)) = f.f.col(j) / sys.body(i).mass - 2 * W.cross(u) - W.cross(W.cross(x));
    }
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      const auto j = static_cast<Index>(r);
      const Vec3 Pi = s.Pi.col(j), Omega = sys.body(sys.body_of_rigid(r)).inertia_inverse * Pi;
      dot.segment<3>(chart.eta(r)) = Omega - s.R[r].transpose() * W;  // exact to first order: zero at δ = 0
      dot.segment<3>(chart.Pi(r)) = Pi.cross(Omega) + f.M.col(j);
    }
    return VectorXd(dot.cwiseQuotient(chart.scale()));
  };
  // L about the origin (the barycentre), inertial velocities u + W × x; and L · k̂.
  const auto L3 = [&](const VectorXd& delta) {
    const State s = chart.retract(delta);
    Vec3 L = Vec3::Zero();
    for (std::size_t i = 0; i < sys.size(); ++i) {
      const Vec3 x = s.x.col(static_cast<Index>(i));
      L += sys.body(i).mass * x.cross(Vec3(s.p.col(static_cast<Index>(i)) / sys.body(i).mass + W.cross(x)));
    }
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) L += s.R[r] * s.Pi.col(static_cast<Index>(r));
    return VectorXd(L);
  };
  const auto Lk = [&](const VectorXd& delta) { return VectorXd::Constant(1, L3(delta).dot(eq.axis)); };

  EquilibriumStability st;
  const VectorXd zero = VectorXd::Zero(d);
  st.linearisation = jacobian_by_differences(field, zero, 1e-6);
  const MatrixXd& A = st.linearisation;
  const VectorXd dL = jacobian_by_differences(Lk, zero, 1e-6).row(0).transpose();

  // Symmetry directions: the rotations of the whole configuration (18.4).
  const Vec3 e1 = eq.axis.unitOrthogonal(), e2 = eq.axis.cross(e1);
  MatrixXd P(d, 3);
  P.col(0) = chart.rotation_generator(e1, W);
  P.col(1) = chart.rotation_generator(e2, W);
  P.col(2) = chart.rotation_generator(eq.axis, W);
  const MatrixXd V = chart.barycentre_free_basis();
  MatrixXd constraints(V.cols(), 4);
  constraints.col(0) = V.transpose() * dL;
  constraints.rightCols(3) = V.transpose() * P;
  const MatrixXd Q = V * complement(constraints);
  const MatrixXd B = Q.transpose() * A * Q;

  {  // invariance: A P ⊂ span P, dLᵀ A = 0
    const MatrixXd AP = A * P;
    const MatrixXd outside = AP - P * P.completeOrthogonalDecomposition().solve(AP);
    st.invariance_defect = std::max(outside.norm() / std::max(1e-300, A.norm() * P.norm()),
                                    (dL.transpose() * A).norm() / std::max(1e-300, A.norm() * dL.norm()));
  }

  Eigen::EigenSolver<MatrixXd> es(B, true);
  const auto lambda = es.eigenvalues();
  st.eigenvalues.assign(lambda.data(), lambda.data() + lambda.size());
  std::sort(st.eigenvalues.begin(), st.eigenvalues.end(),
            [](auto a, auto b) { return a.imag() != b.imag() ? a.imag() > b.imag() : a.real() > b.real(); });
  double largest = 0;
  for (auto l : st.eigenvalues) largest = std::max(largest, std::abs(l)), st.max_real = std::max(st.max_real, std::abs(l.real()));
  st.scale = std::max(eq.rate, largest);
  const double z = tolerance * st.scale;

  // One mode per ±λ, ±λ̄ group; what moves in it, from the eigenvector in the full chart.
  const Vec3& k = eq.axis;
  int zeros = 0;
  st.planar = true;
  double in_max_real = 0, out_max_real = 0;
  for (Index m = 0; m < lambda.size(); ++m) {
    const std::complex<double> l = lambda[m];
    const bool zero_mode = std::abs(l) <= z;
    if (zero_mode && (zeros++ % 2 == 1)) continue;
    if (!zero_mode && !(l.imag() > z ? l.real() >= -z : (std::abs(l.imag()) <= z && l.real() > 0))) continue;
    const Eigen::VectorXcd v = Q.cast<std::complex<double>>() * es.eigenvectors().col(m);
    std::vector<std::pair<std::string, double>> share;
    double orbit_in = 0, orbit_out = 0;
    for (std::size_t i = 0; i < sys.size(); ++i)
      for (Index block : {chart.x(i), chart.v(i)}) {
        const Eigen::Vector3cd c = v.segment<3>(block);
        const double along = std::norm(k.cast<std::complex<double>>().dot(c));
        orbit_out += along;
        orbit_in += c.squaredNorm() - along;
      }
    share.emplace_back("orbit (in-plane)", orbit_in);
    share.emplace_back("orbit (out of plane)", orbit_out);
    double out_of_plane = orbit_out;
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      const Vec3 b = eq.state.R[r].transpose() * k;  // k̂ in the body frame
      double about = 0, tilt = 0;
      for (Index block : {chart.eta(r), chart.Pi(r)}) {
        const Eigen::Vector3cd c = v.segment<3>(block);
        const double along = std::norm(b.cast<std::complex<double>>().dot(c));
        about += along;
        tilt += c.squaredNorm() - along;
      }
      const std::string& name = sys.body(sys.body_of_rigid(r)).name;
      share.emplace_back("libration of " + name, about);
      share.emplace_back("tilt of " + name, tilt);
      out_of_plane += tilt;
    }
    double total = 0;
    for (const auto& s : share) total += s.second;
    const auto best = std::max_element(share.begin(), share.end(), [](auto& a, auto& b) { return a.second < b.second; });
    NormalMode mode;
    mode.eigenvalue = l;
    mode.frequency = zero_mode ? 0.0 : std::abs(l.imag()) > z ? std::abs(l.imag()) : 0.0;
    mode.kind = zero_mode ? "neutral (a further symmetry of the model)" : best->first;
    mode.weight = best->second / total;
    mode.shape = v.normalized();
    const double out_share = out_of_plane / total;
    mode.in_plane = out_share <= 1e-6;
    if (out_share > 1e-6 && out_share < 1 - 1e-6) st.planar = false;
    (mode.in_plane ? in_max_real : out_max_real) = std::max(mode.in_plane ? in_max_real : out_max_real, std::abs(l.real()));
    st.modes.push_back(mode);
  }
  std::sort(st.modes.begin(), st.modes.end(), [](const NormalMode& a, const NormalMode& b) { return a.frequency < b.frequency; });
  const auto judge = [&](double re) {
    return re <= z ? "linearly stable" : re > 100 * z ? "unstable" : "undecided";
  };
  st.verdict = judge(st.max_real);

  // The energy–momentum test (18.5): ∇(E − W·L) in the chart, right-trivialised in η (exact for
  // the Hessian at a critical point), differenced once more.
  const auto gradient = [&](const VectorXd& delta) {
    const State s = chart.retract(delta);
    const Forces f = model.forces(s);
    VectorXd g(d);
    for (std::size_t i = 0; i < sys.size(); ++i) {
      const auto j = static_cast<Index>(i);
      const Vec3 x = s.x.col(j);
      g.segment<3>(chart.x(i)) = -f.f.col(j) + sys.body(i).mass * W.cross(W.cross(x));
      g.segment<3>(chart.v(i)) = s.p.col(j);  // m u
    }
    for (std::size_t r = 0; r < sys.rigid_count(); ++r) {
      const auto j = static_cast<Index>(r);
      const Vec3 Pi = s.Pi.col(j), w = s.R[r].transpose() * W;
      g.segment<3>(chart.eta(r)) = -f.M.col(j) - Pi.cross(w);
      g.segment<3>(chart.Pi(r)) = sys.body(sys.body_of_rigid(r)).inertia_inverse * Pi - w;
    }
    return VectorXd(g.cwiseProduct(chart.scale()));
  };
  MatrixXd H = jacobian_by_differences(gradient, zero, 1e-6);
  H = 0.5 * (H + H.transpose()).eval();
  const MatrixXd dL3 = jacobian_by_differences(L3, zero, 1e-6);  // 3 × d
  MatrixXd keep(V.cols(), 4);
  keep.leftCols(3) = V.transpose() * dL3.transpose();
  keep.col(3) = V.transpose() * P.col(2);
  const MatrixXd QE = V * complement(keep);
  Eigen::SelfAdjointEigenSolver<MatrixXd> hs(QE.transpose() * H * QE);
  const double h_scale = std::max(1e-300, hs.eigenvalues().cwiseAbs().maxCoeff());
  for (Index i = 0; i < hs.eigenvalues().size(); ++i) {
    st.hessian_eigenvalues.push_back(hs.eigenvalues()[i] / h_scale);
    if (hs.eigenvalues()[i] < -tolerance * h_scale) ++st.energetic_index;
  }
  const double lowest = st.hessian_eigenvalues.empty() ? 0.0 : st.hessian_eigenvalues.front();
  st.energetic_verdict = lowest > tolerance ? "energetically stable"
                         : st.energetic_index > 0 ? "not energetically stable" : "undecided";
  if (st.planar) st.in_plane_verdict = judge(in_max_real), st.out_of_plane_verdict = judge(out_max_real);
  return st;
}

}  // namespace noether
