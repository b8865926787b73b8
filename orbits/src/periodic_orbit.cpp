#include <noether/error.hpp>
#include <noether/periodic_orbit.hpp>
#include <noether/stepping.hpp>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace noether {

using Eigen::MatrixXd;
using Eigen::VectorXd;

OrbitModel OrbitModel::from_scene(const Scene& scene, PluginRegistry& registry) {
  const System& system = scene.system;
  if (system.size() < 1) throw SceneError("periodic orbits need at least one body");
  if (!scene.impulses.empty())
    throw SceneError("periodic orbits follow the scene's conservative dynamics; its impulses would break every "
                     "orbit: remove them (--set impulses=[])");
  if (system.rigid_count() > 0)
    throw SceneError("least-action orbits: point masses only; body '" + system.body(system.body_of_rigid(0)).name +
                     "' is rigid (for rigid bodies: noether orbit equilibrium for relative equilibria, orbit "
                     "verify / refine / stability for relative periodic orbits)");
  OrbitModel m;
  m.system = system;
  m.potentials = scene.potentials;
  std::vector<std::shared_ptr<const Potential>> terms;
  for (const auto& p : scene.potentials) terms.push_back(registry.make_potential(p.plugin, system, p.params));
  m.potential = terms.size() == 1 ? terms.front() : std::make_shared<SumPotential>(terms);
  m.registry = std::make_shared<PluginRegistry>(registry.search_path());
  return m;
}

OrbitModel OrbitModel::point_masses(const std::vector<double>& masses, double G, PluginRegistry& registry) {
  std::ostringstream scene;
  scene.precision(17);
  scene << "G: " << G << "\nbodies:\n";
  for (std::size_t j = 0; j < masses.size(); ++j)
    scene << "  - {name: b" << j + 1 << ", mass: " << masses[j] << ", position: [" << j << ", 0, 0]}\n";
  scene << "potential: {plugin: point-mass}\nintegrator: {plugin: rk}\nrun: {t_end: 1, output_every: 1}\n";
  return from_scene(parse_scene(scene.str(), "point masses"), registry);
}

VectorXd OrbitModel::phase_point(const State& s) const {
  const auto N = static_cast<Eigen::Index>(3 * n());
  VectorXd xi(2 * N);
  for (std::size_t j = 0; j < n(); ++j) {
    const auto c = static_cast<Eigen::Index>(j);
    xi.segment<3>(3 * c) = s.x.col(c);
    xi.segment<3>(N + 3 * c) = s.p.col(c) / system.body(j).mass;
  }
  return xi;
}

State OrbitModel::state(const VectorXd& xi, double t) const {
  const auto N = static_cast<Eigen::Index>(3 * n());
  State s = State::zeros(system);
  s.t = t;
  for (std::size_t j = 0; j < n(); ++j) {
    const auto c = static_cast<Eigen::Index>(j);
    s.x.col(c) = xi.segment<3>(3 * c);
    s.p.col(c) = system.body(j).mass * xi.segment<3>(N + 3 * c);
  }
  return s;
}

VectorXd OrbitModel::rhs(const VectorXd& xi) const { return rhs(xi, *potential->make_workspace()); }
MatrixXd OrbitModel::jacobian(const VectorXd& xi) const { return jacobian(xi, *potential->make_workspace()); }

VectorXd OrbitModel::rhs(const VectorXd& xi, Workspace& workspace) const {
  const auto N = static_cast<Eigen::Index>(3 * n());
  Forces f;
  f.resize(system);
  potential->evaluate(state(xi), f, workspace);
  VectorXd d(2 * N);
  d.head(N) = xi.tail(N);
  for (std::size_t j = 0; j < n(); ++j)
    d.segment<3>(N + 3 * static_cast<Eigen::Index>(j)) = f.f.col(static_cast<Eigen::Index>(j)) / system.body(j).mass;
  return d;
}

MatrixXd OrbitModel::jacobian(const VectorXd& xi, Workspace& workspace) const {
  const auto N = static_cast<Eigen::Index>(3 * n());
  MatrixXd A = MatrixXd::Zero(2 * N, 2 * N);
  A.topRightCorner(N, N).setIdentity();
  // M⁻¹ ∂f/∂x from the model's force Jacobian when it has one (9.2, 20.1) ...
  const State st = state(xi);
  const auto size = N + 3 * static_cast<Eigen::Index>(st.R.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(size, size);
  if (potential->force_jacobian(st, K, workspace)) {
    for (Eigen::Index k = 0; k < N; ++k) A.block(N + k, 0, 1, N) = K.row(k) / system.body(static_cast<std::size_t>(k / 3)).mass;
    return A;
  }
  // ... else by central differences of the accelerations, step ε^{1/3} × the scale of x.
  const double scale = std::max(1e-300, xi.head(N).cwiseAbs().maxCoeff());
  const double e = 6e-6 * scale;
  VectorXd y = xi;
  for (Eigen::Index k = 0; k < N; ++k) {
    y[k] = xi[k] + e;
    const VectorXd plus = rhs(y, workspace).tail(N);
    y[k] = xi[k] - e;
    const VectorXd minus = rhs(y, workspace).tail(N);
    y[k] = xi[k];
    A.block(N, k, N, 1) = (plus - minus) / (2 * e);
  }
  return A;
}

double OrbitModel::energy(const VectorXd& xi) const {
  const auto N = static_cast<Eigen::Index>(3 * n());
  Forces f;
  f.resize(system);
  potential->evaluate(state(xi), f);
  double E = f.U;
  for (std::size_t j = 0; j < n(); ++j)
    E += 0.5 * system.body(j).mass * xi.segment<3>(N + 3 * static_cast<Eigen::Index>(j)).squaredNorm();
  return E;
}

bool OrbitModel::planar(const VectorXd& xi) const {
  const auto N = static_cast<Eigen::Index>(3 * n());
  const VectorXd F = rhs(xi);
  const double x_scale = xi.head(N).cwiseAbs().maxCoeff(), v_scale = xi.tail(N).cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < static_cast<Eigen::Index>(n()); ++j)
    if (std::abs(xi[3 * j + 2]) > 1e-12 * x_scale || std::abs(xi[N + 3 * j + 2]) > 1e-12 * v_scale ||
        std::abs(F[N + 3 * j + 2]) > 1e-12 * std::max(1.0, F.tail(N).cwiseAbs().maxCoeff()))
      return false;
  return true;
}

VectorXd lift_planar(const VectorXd& planar) {
  const Eigen::Index n = planar.size() / 4, N = 3 * n;
  VectorXd xi = VectorXd::Zero(6 * n);
  for (Eigen::Index j = 0; j < n; ++j) {
    xi.segment<2>(3 * j) = planar.segment<2>(2 * j);
    xi.segment<2>(N + 3 * j) = planar.segment<2>(2 * n + 2 * j);
  }
  return xi;
}

VectorXd planar_part(const VectorXd& xi) {
  const Eigen::Index n = xi.size() / 6, N = 3 * n;
  VectorXd planar(4 * n);
  for (Eigen::Index j = 0; j < n; ++j) {
    planar.segment<2>(2 * j) = xi.segment<2>(3 * j);
    planar.segment<2>(2 * n + 2 * j) = xi.segment<2>(N + 3 * j);
  }
  return planar;
}

namespace {

class NullObserver final : public Observer {
 public:
  void observe(const State&, const Forces&, bool) override {}
};

// The rk plugin's Fehlberg 7(8) at the given tolerances, through the stepping loop (no events).
VectorXd plugin_flow(const OrbitModel& model, const VectorXd& xi0, double T, const FlowOptions& options,
                     std::size_t& steps) {
  std::ostringstream spec;
  spec.precision(17);
  spec << "{method: rkf78, rtol: " << options.rtol << ", atol: " << options.atol << "}";
  auto integrator = model.registry->make_integrator("rk", model.system, model.potential,
                                                    parse_params(spec.str(), "orbit flow"));
  State s = model.state(xi0);
  NullObserver null;
  Schedule schedule{T, T, Events{0.0, false, {}}, {}};
  advance(*integrator, *model.potential, model.system, s, schedule, null);
  steps = static_cast<std::size_t>(integrator->work().steps);
  return model.phase_point(s);
}

}  // namespace

FlowResult integrate_flow(const OrbitModel& model, const VectorXd& xi0, double T, bool variational,
                          const FlowOptions& options) {
  FlowResult result;
  if (!variational) {
    result.end = plugin_flow(model, xi0, T, options, result.steps);
  } else {
    namespace odeint = boost::numeric::odeint;
    using Vec = std::vector<double>;
    const auto d = static_cast<Eigen::Index>(xi0.size());
    Vec y(static_cast<std::size_t>(d * (1 + d)), 0.0);
    std::copy(xi0.data(), xi0.data() + d, y.begin());
    for (Eigen::Index i = 0; i < d; ++i) y[static_cast<std::size_t>(d + i * d + i)] = 1.0;  // Φ(0) = I
    const auto workspace = model.potential->make_workspace();
    auto rhs = [&](const Vec& x, Vec& dxdt, double) {
      const Eigen::Map<const VectorXd> xi(x.data(), d);
      Eigen::Map<VectorXd>(dxdt.data(), d) = model.rhs(xi, *workspace);
      const Eigen::Map<const MatrixXd> Phi(x.data() + d, d, d);  // Φ̇ = A(ξ) Φ (9.1)
      Eigen::Map<MatrixXd>(dxdt.data() + d, d, d) = model.jacobian(xi, *workspace) * Phi;
    };
    auto stepper = odeint::make_controlled(options.atol, options.rtol, odeint::runge_kutta_fehlberg78<Vec>());
    result.steps = odeint::integrate_adaptive(stepper, rhs, y, 0.0, T, T / 1000);
    result.end = Eigen::Map<const VectorXd>(y.data(), d);
    result.monodromy = Eigen::Map<const MatrixXd>(y.data() + d, d, d);
  }
  if (!result.end.allFinite()) throw IntegrationError("periodic orbit: the flow became non-finite (a collision?)", 0);
  return result;
}

MatrixXd invariant_directions(const OrbitModel& model, const VectorXd& xi) {
  const auto n = static_cast<Eigen::Index>(model.n()), N = 2 * n;
  const VectorXd p = planar_part(xi), a = planar_part(model.rhs(xi)).tail(N);
  MatrixXd P = MatrixXd::Zero(2 * N, 7);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector2d x = p.segment<2>(2 * j), v = p.segment<2>(N + 2 * j), acc = a.segment<2>(2 * j);
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

// Indices of ξ in the planar layout (x, y of every body, then u, v), and of (z, v_z).
std::vector<Eigen::Index> in_plane_indices(Eigen::Index n) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index j = 0; j < n; ++j) out.push_back(3 * j), out.push_back(3 * j + 1);
  for (Eigen::Index j = 0; j < n; ++j) out.push_back(3 * n + 3 * j), out.push_back(3 * n + 3 * j + 1);
  return out;
}
std::vector<Eigen::Index> out_of_plane_indices(Eigen::Index n) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index j = 0; j < n; ++j) out.push_back(3 * j + 2);
  for (Eigen::Index j = 0; j < n; ++j) out.push_back(3 * n + 3 * j + 2);
  return out;
}

}  // namespace

Stability stability(const OrbitModel& model, const VectorXd& xi0, const MatrixXd& monodromy, double tolerance) {
  for (const auto& p : model.potentials)
    if (p.plugin != "point-mass")
      throw SceneError("orbit stability projects out the first integrals of mutual point-mass gravity "
                       "(translations, moving frames, rotation, dilation); potential '" + p.plugin +
                       "' has other symmetries and is not supported (noether orbit verify and refine are)");
  if (!model.planar(xi0))
    throw SceneError("orbit stability: planar orbits only for now (z = 0 and v_z = 0 for every body); "
                     "noether orbit verify and refine handle 3-D orbits");
  const auto n = static_cast<Eigen::Index>(model.n());
  const auto in = in_plane_indices(n), out = out_of_plane_indices(n);
  const MatrixXd Phi = monodromy(in, in);
  const MatrixXd P = invariant_directions(model, xi0);
  const auto d = Phi.rows();
  const MatrixXd Pi = MatrixXd::Identity(d, d) - P * (P.transpose() * P).ldlt().solve(P.transpose());
  Stability s;
  s.multipliers = sorted_eigenvalues(Pi * Phi * Pi);
  s.right_projected = sorted_eigenvalues(Phi * Pi);
  s.unprojected = sorted_eigenvalues(Phi);
  s.out_of_plane = sorted_eigenvalues(monodromy(out, out));
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

MatrixXd first_order_monodromy(const OrbitModel& model, const VectorXd& xi0, double T, std::size_t steps,
                               const FlowOptions& options) {
  const auto d = xi0.size();
  MatrixXd M = MatrixXd::Identity(d, d);
  VectorXd xi = xi0;
  const double h = T / static_cast<double>(steps);
  const auto workspace = model.potential->make_workspace();
  for (std::size_t i = 0; i < steps; ++i) {
    M = (MatrixXd::Identity(d, d) + h * model.jacobian(xi, *workspace)) * M;
    std::size_t unused = 0;
    xi = plugin_flow(model, xi, h, options, unused);  // ξ*(t_i) by the accurate flow
  }
  return M;
}

Refinement refine_periodic_orbit(const OrbitModel& model, const VectorXd& xi0, double T, double target,
                                 int max_iterations, const FlowOptions& options, bool free_period) {
  Refinement r;
  r.xi0 = xi0;
  r.period = T;
  const auto d = xi0.size();
  for (int it = 0; it <= max_iterations; ++it) {
    const FlowResult f = integrate_flow(model, r.xi0, r.period, true, options);
    const VectorXd residual = f.end - r.xi0;
    r.closure = residual.norm();
    r.iterations = it;
    if (r.closure <= target || it == max_iterations) break;
    MatrixXd J(d, d + (free_period ? 1 : 0));
    J.leftCols(d) = f.monodromy - MatrixXd::Identity(d, d);
    if (free_period) J.col(d) = model.rhs(f.end);
    const VectorXd step = J.completeOrthogonalDecomposition().solve(-residual);  // minimum norm
    if (free_period && std::abs(step[d]) > 0.1 * r.period) break;
    r.xi0 += step.head(d);
    if (free_period) r.period += step[d];
  }
  return r;
}

namespace {

// Params back to YAML flow style (scalars as written in the scene).
std::string to_yaml(const Params& p) {
  if (p.is_map()) {
    std::string out = "{";
    for (const auto& [k, v] : p.entries()) out += (out.size() > 1 ? ", " : "") + k + ": " + to_yaml(v);
    return out + "}";
  }
  if (p.is_sequence()) {
    std::string out = "[";
    for (const auto& v : p.items()) out += (out.size() > 1 ? ", " : "") + to_yaml(v);
    return out + "]";
  }
  const std::string& s = p.as_string();
  return s.find_first_of(":,[]{}#&*!|>'\"%@`") == std::string::npos && !s.empty() ? s : "\"" + s + "\"";
}

}  // namespace

std::string orbit_scene(const OrbitModel& model, const VectorXd& xi0, double period, const std::string& description) {
  std::ostringstream out;
  out.precision(17);
  const auto n = static_cast<Eigen::Index>(model.n()), N = 3 * n;
  out << "# " << description << "\n";
  out << "description: periodic orbit, period " << period << "\n";
  out << "G: " << model.system.G() << "\nbodies:\n";
  for (Eigen::Index j = 0; j < n; ++j) {
    const auto& b = model.system.body(static_cast<std::size_t>(j));
    out << "  - {name: " << b.name << ", mass: " << b.mass << ", position: [" << xi0[3 * j] << ", "
        << xi0[3 * j + 1] << ", " << xi0[3 * j + 2] << "], velocity: [" << xi0[N + 3 * j] << ", "
        << xi0[N + 3 * j + 1] << ", " << xi0[N + 3 * j + 2] << "]}\n";
  }
  if (model.potentials.size() == 1) {
    out << "potential: " << to_yaml(model.potentials.front().params) << "\n";
  } else {
    out << "potential:\n";
    for (const auto& p : model.potentials) out << "  - " << to_yaml(p.params) << "\n";
  }
  out << "integrator: {plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-15}\n";
  out << "run: {t_end: " << period << ", output_every: " << period / 200 << "}\n";
  return out.str();
}

}  // namespace noether
