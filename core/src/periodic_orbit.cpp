#include <noether/error.hpp>
#include <noether/periodic_orbit.hpp>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include <algorithm>
#include <cmath>

namespace noether {

using Eigen::MatrixXd;
using Eigen::VectorXd;

PlanarSystem PlanarSystem::from(const System& system, const State& state, VectorXd& xi) {
  PlanarSystem sys;
  sys.G = system.G();
  const std::size_t n = system.size();
  if (n < 2) throw SceneError("periodic orbits need at least two bodies");
  if (system.rigid_count() > 0)
    throw SceneError("periodic orbits: point masses only (body '" +
                     system.body(system.body_of_rigid(0)).name + "' is rigid)");
  xi.resize(static_cast<Eigen::Index>(4 * n));
  for (std::size_t j = 0; j < n; ++j) {
    const auto c = static_cast<Eigen::Index>(j);
    const double m = system.body(j).mass;
    if (state.x(2, c) != 0.0 || state.p(2, c) != 0.0)
      throw SceneError("periodic orbits: planar scenes only (z = 0 and v_z = 0); body '" +
                       system.body(j).name + "' is not");
    sys.masses.push_back(m);
    xi[2 * c] = state.x(0, c);
    xi[2 * c + 1] = state.x(1, c);
    xi[static_cast<Eigen::Index>(2 * n) + 2 * c] = state.p(0, c) / m;
    xi[static_cast<Eigen::Index>(2 * n) + 2 * c + 1] = state.p(1, c) / m;
  }
  return sys;
}

VectorXd PlanarSystem::rhs(const VectorXd& xi) const {
  const auto N = static_cast<Eigen::Index>(2 * n());
  VectorXd d = VectorXd::Zero(2 * N);
  d.head(N) = xi.tail(N);
  for (std::size_t j = 0; j < n(); ++j)
    for (std::size_t l = j + 1; l < n(); ++l) {
      const auto J = static_cast<Eigen::Index>(2 * j), L = static_cast<Eigen::Index>(2 * l);
      const Eigen::Vector2d r = xi.segment<2>(L) - xi.segment<2>(J);
      const double r3 = std::pow(r.norm(), 3);
      d.segment<2>(N + J) += G * masses[l] / r3 * r;
      d.segment<2>(N + L) -= G * masses[j] / r3 * r;
    }
  return d;
}

MatrixXd PlanarSystem::jacobian(const VectorXd& xi) const {
  const auto N = static_cast<Eigen::Index>(2 * n());
  MatrixXd A = MatrixXd::Zero(2 * N, 2 * N);
  A.topRightCorner(N, N).setIdentity();
  for (std::size_t j = 0; j < n(); ++j)
    for (std::size_t l = j + 1; l < n(); ++l) {
      const auto J = static_cast<Eigen::Index>(2 * j), L = static_cast<Eigen::Index>(2 * l);
      const Eigen::Vector2d r = xi.segment<2>(L) - xi.segment<2>(J);
      const double rn = r.norm(), r3 = rn * rn * rn, r5 = r3 * rn * rn;
      // ∂/∂x_l of r/r³: (I − 3 r̂ r̂ᵀ)/r³
      const Eigen::Matrix2d B = Eigen::Matrix2d::Identity() / r3 - 3.0 * r * r.transpose() / r5;
      A.block<2, 2>(N + J, L) += G * masses[l] * B;
      A.block<2, 2>(N + J, J) -= G * masses[l] * B;
      A.block<2, 2>(N + L, J) += G * masses[j] * B;
      A.block<2, 2>(N + L, L) -= G * masses[j] * B;
    }
  return A;
}

double PlanarSystem::energy(const VectorXd& xi) const {
  const auto N = static_cast<Eigen::Index>(2 * n());
  double E = 0;
  for (std::size_t j = 0; j < n(); ++j) {
    E += 0.5 * masses[j] * xi.segment<2>(N + static_cast<Eigen::Index>(2 * j)).squaredNorm();
    for (std::size_t l = j + 1; l < n(); ++l)
      E -= G * masses[j] * masses[l] /
           (xi.segment<2>(static_cast<Eigen::Index>(2 * l)) - xi.segment<2>(static_cast<Eigen::Index>(2 * j))).norm();
  }
  return E;
}

FlowResult integrate_flow(const PlanarSystem& sys, const VectorXd& xi0, double T, bool variational,
                          const FlowOptions& options) {
  namespace odeint = boost::numeric::odeint;
  using Vec = std::vector<double>;
  const auto d = static_cast<Eigen::Index>(xi0.size());
  const std::size_t size = static_cast<std::size_t>(d) * (variational ? 1 + static_cast<std::size_t>(d) : 1);
  Vec y(size, 0.0);
  std::copy(xi0.data(), xi0.data() + d, y.begin());
  if (variational)
    for (Eigen::Index i = 0; i < d; ++i) y[static_cast<std::size_t>(d + i * d + i)] = 1.0;  // Φ(0) = I
  FlowResult result;
  auto rhs = [&](const Vec& x, Vec& dxdt, double) {
    const Eigen::Map<const VectorXd> xi(x.data(), d);
    Eigen::Map<VectorXd>(dxdt.data(), d) = sys.rhs(xi);
    if (variational) {  // Φ̇ = A(ξ) Φ (column-major d × d)
      const Eigen::Map<const MatrixXd> Phi(x.data() + d, d, d);
      Eigen::Map<MatrixXd>(dxdt.data() + d, d, d) = sys.jacobian(xi) * Phi;
    }
  };
  auto stepper = odeint::make_controlled(options.atol, options.rtol, odeint::runge_kutta_fehlberg78<Vec>());
  result.steps = odeint::integrate_adaptive(stepper, rhs, y, 0.0, T, T / 1000);
  result.end = Eigen::Map<const VectorXd>(y.data(), d);
  if (!result.end.allFinite()) throw IntegrationError("periodic orbit: the flow became non-finite (a collision?)", 0);
  if (variational) result.monodromy = Eigen::Map<const MatrixXd>(y.data() + d, d, d);
  return result;
}

MatrixXd invariant_directions(const PlanarSystem& sys, const VectorXd& xi) {
  const auto n = static_cast<Eigen::Index>(sys.n()), N = 2 * n;
  MatrixXd P = MatrixXd::Zero(2 * N, 7);
  const VectorXd a = sys.rhs(xi).tail(N);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector2d x = xi.segment<2>(2 * j), v = xi.segment<2>(N + 2 * j), acc = a.segment<2>(2 * j);
    P(2 * j, 0) = 1;            // translation in x
    P(2 * j + 1, 1) = 1;        // translation in y
    P(N + 2 * j, 2) = 1;        // moving frame (Galilean boost) in x
    P(N + 2 * j + 1, 3) = 1;    // moving frame in y
    P.block<2, 1>(2 * j, 4) = Eigen::Vector2d(-x.y(), x.x());       // rotation: (J x, J v)
    P.block<2, 1>(N + 2 * j, 4) = Eigen::Vector2d(-v.y(), v.x());
    P.block<2, 1>(2 * j, 5) = x - 1.5 * v;                          // dilation (docs/equations.md §9)
    P.block<2, 1>(N + 2 * j, 5) = -0.5 * v - 1.5 * acc;
    P.block<2, 1>(2 * j, 6) = v;                                    // the flow (time shift)
    P.block<2, 1>(N + 2 * j, 6) = acc;
  }
  return P;
}

namespace {
std::vector<std::complex<double>> sorted_eigenvalues(const MatrixXd& M) {
  Eigen::EigenSolver<MatrixXd> es(M, false);
  std::vector<std::complex<double>> ev(es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size());
  std::sort(ev.begin(), ev.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
  return ev;
}
}  // namespace

Stability stability(const PlanarSystem& sys, const VectorXd& xi0, const MatrixXd& monodromy, double tolerance) {
  const MatrixXd P = invariant_directions(sys, xi0);
  const auto d = monodromy.rows();
  const MatrixXd Pi = MatrixXd::Identity(d, d) - P * (P.transpose() * P).ldlt().solve(P.transpose());
  Stability s;
  s.multipliers = sorted_eigenvalues(Pi * monodromy * Pi);
  s.right_projected = sorted_eigenvalues(monodromy * Pi);
  s.unprojected = sorted_eigenvalues(monodromy);
  s.max_projected = std::abs(s.multipliers.front());
  s.max_unprojected = std::abs(s.unprojected.front());
  // In exact arithmetic the projected multipliers are a subset of Φ's (span P is invariant and
  // its multipliers are 1): if they exceed Φ's, the projection is not resolved numerically.
  if (s.max_projected > s.max_unprojected * (1 + 1e-3) + tolerance)
    s.verdict = "undecided: the projected multipliers exceed the unprojected ones (orbit not "
                "converged, or neutral directions beyond the first integrals)";
  else if (s.max_projected <= 1.0 + tolerance) s.verdict = "linearly stable";
  else if (s.max_projected > 1.0 + 100 * tolerance) s.verdict = "unstable";
  else s.verdict = "undecided";
  return s;
}

MatrixXd first_order_monodromy(const PlanarSystem& sys, const VectorXd& xi0, double T, std::size_t steps,
                               const FlowOptions& options) {
  const auto d = xi0.size();
  MatrixXd M = MatrixXd::Identity(d, d);
  VectorXd xi = xi0;
  const double h = T / static_cast<double>(steps);
  for (std::size_t i = 0; i < steps; ++i) {
    M = (MatrixXd::Identity(d, d) + h * sys.jacobian(xi)) * M;
    xi = integrate_flow(sys, xi, h, false, options).end;  // ξ*(t_i) by the accurate flow
  }
  return M;
}

Refinement refine_periodic_orbit(const PlanarSystem& sys, const VectorXd& xi0, double T, double target,
                                 int max_iterations, const FlowOptions& options, bool free_period) {
  Refinement r;
  r.xi0 = xi0;
  r.period = T;
  const auto d = xi0.size();
  for (int it = 0; it <= max_iterations; ++it) {
    const FlowResult f = integrate_flow(sys, r.xi0, r.period, true, options);
    const VectorXd residual = f.end - r.xi0;
    r.closure = residual.norm();
    r.iterations = it;
    if (r.closure <= target || it == max_iterations) break;
    MatrixXd J(d, d + (free_period ? 1 : 0));
    J.leftCols(d) = f.monodromy - MatrixXd::Identity(d, d);
    if (free_period) J.col(d) = sys.rhs(f.end);
    const VectorXd step = J.completeOrthogonalDecomposition().solve(-residual);  // minimum norm
    if (free_period && std::abs(step[d]) > 0.1 * r.period) break;
    r.xi0 += step.head(d);
    if (free_period) r.period += step[d];
  }
  return r;
}

}  // namespace noether
