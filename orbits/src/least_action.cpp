#include <noether/error.hpp>
#include <noether/least_action.hpp>

#include <nlopt.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

namespace noether {

using Eigen::VectorXd;
constexpr double kTwoPi = 2 * std::numbers::pi;

void LeastActionProblem::validate() const {
  if (!model.potential) throw SceneError("orbit find: the problem has no model (bodies and potential)");
  bool mutual_only = true;
  for (const auto& p : model.potentials) mutual_only &= p.plugin == "point-mass";
  if (n() < 1 || (mutual_only && n() < 2))
    throw SceneError("orbit find: need at least 2 bodies under mutual gravity (or 1 in an external field), not " +
                     std::to_string(n()));
  if (!(period > 0) || !std::isfinite(period))
    throw SceneError("orbit find: the period must be positive and finite");
  if (modes < 1) throw SceneError("orbit find: need at least one Fourier mode");
  if (points <= 2 * modes)
    throw SceneError("orbit find: " + std::to_string(points) + " quadrature points alias " +
                     std::to_string(modes) + " modes; use more than 2 × modes = " +
                     std::to_string(2 * modes) + " points");
  if (choreography) {
    if (points % static_cast<int>(n()) != 0)
      throw SceneError("orbit find: a choreography needs the number of points to be a multiple of the "
                       "number of bodies (" + std::to_string(n()) + ")");
    for (std::size_t j = 0; j < n(); ++j)
      if (mass(j) != mass(0)) throw SceneError("orbit find: a choreography needs equal masses");
  }
}

namespace {

// Index of coefficient (curve, coordinate d, slot s) with slot 0 = c0, 1..F = a_k, F+1..2F = b_k.
std::size_t index(const LeastActionProblem& p, std::size_t curve, int d, int slot) {
  return (curve * 2 + static_cast<std::size_t>(d)) * (1 + 2 * static_cast<std::size_t>(p.modes)) +
         static_cast<std::size_t>(slot);
}

// Which curve and which quadrature index body j uses at point i.
std::pair<std::size_t, int> curve_of(const LeastActionProblem& p, std::size_t j, int i) {
  if (!p.choreography) return {j, i};
  return {0, (i + static_cast<int>(j) * p.points / static_cast<int>(p.n())) % p.points};
}

struct Tables {
  std::vector<double> cos, sin;  // [i * F + (k − 1)]
};

Tables tables(const LeastActionProblem& p) {
  Tables t;
  for (int i = 0; i < p.points; ++i)
    for (int k = 1; k <= p.modes; ++k) {
      const double th = kTwoPi * k * i / p.points;
      t.cos.push_back(std::cos(th));
      t.sin.push_back(std::sin(th));
    }
  return t;
}

// z, ż, z̈ of one curve coordinate at point i.
void evaluate_curve(const LeastActionProblem& p, const Tables& tb, const VectorXd& c, std::size_t curve, int d,
                    int i, double& z, double& zd, double& zdd) {
  z = c[static_cast<Eigen::Index>(index(p, curve, d, 0))];
  zd = zdd = 0;
  for (int k = 1; k <= p.modes; ++k) {
    const double a = c[static_cast<Eigen::Index>(index(p, curve, d, k))];
    const double b = c[static_cast<Eigen::Index>(index(p, curve, d, p.modes + k))];
    const double C = tb.cos[static_cast<std::size_t>(i * p.modes + k - 1)], S = tb.sin[static_cast<std::size_t>(i * p.modes + k - 1)];
    z += a * C + b * S;
    zd += k * (-a * S + b * C);
    zdd += -k * k * (a * C + b * S);
  }
}

}  // namespace

// The model's state with body j at (X_j, 0) (the bodies at rest: U depends on positions only).
void place(const std::vector<Eigen::Vector2d>& X, State& state) {
  for (std::size_t j = 0; j < X.size(); ++j)
    state.x.col(static_cast<Eigen::Index>(j)) = Vec3(X[j].x(), X[j].y(), 0.0);
}

double action(const LeastActionProblem& p, const VectorXd& c, VectorXd* gradient, Workspace* workspace) {
  static thread_local Tables tb;
  static thread_local std::pair<int, int> key{-1, -1};
  if (key != std::make_pair(p.points, p.modes)) {
    tb = tables(p);
    key = {p.points, p.modes};
  }
  std::unique_ptr<Workspace> own;
  if (!workspace) own = p.model.potential->make_workspace(), workspace = own.get();
  if (gradient) gradient->setZero(c.size());
  const std::size_t n = p.n();
  const double omega = kTwoPi / p.period;  // dτ/dt
  double A = 0;
  // Kinetic part, exactly: ∫₀^T ½ m ‖dz/dt‖² dt = ω (π/2) m Σ k² (a_k² + b_k²) per coordinate (8.2).
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t curve = p.choreography ? 0 : j;
    for (int d = 0; d < 2; ++d)
      for (int k = 1; k <= p.modes; ++k)
        for (int slot : {k, p.modes + k}) {
          const auto ix = static_cast<Eigen::Index>(index(p, curve, d, slot));
          A += 0.5 * omega * std::numbers::pi * p.mass(j) * k * k * c[ix] * c[ix];
          if (gradient) (*gradient)[ix] += omega * std::numbers::pi * p.mass(j) * k * k * c[ix];
        }
  }
  // Potential part by the trapezoid rule: −(1/ω)(2π/m) Σ_i U(z(τ_i)), U and f = −∂U/∂x from
  // the model's potential (8.3).
  const double w = kTwoPi / p.points / omega;
  std::vector<Eigen::Vector2d> X(n);
  std::vector<std::pair<std::size_t, int>> at(n);
  State state = State::zeros(p.model.system);
  Forces forces;
  forces.resize(p.model.system);
  for (int i = 0; i < p.points; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      at[j] = curve_of(p, j, i);
      double z, zd, zdd;
      for (int d = 0; d < 2; ++d) {
        evaluate_curve(p, tb, c, at[j].first, d, at[j].second, z, zd, zdd);
        X[j][d] = z;
      }
    }
    place(X, state);
    p.model.potential->evaluate(state, forces, *workspace);
    A -= w * forces.U;
    if (!gradient) continue;
    for (std::size_t j = 0; j < n; ++j) {
      const Eigen::Vector2d g = w * forces.f.col(static_cast<Eigen::Index>(j)).head<2>();  // ∂(−wU)/∂X_j = w f_j
      const auto [curve, ii] = at[j];
      for (int d = 0; d < 2; ++d) {
        (*gradient)[static_cast<Eigen::Index>(index(p, curve, d, 0))] += g[d];
        for (int k = 1; k <= p.modes; ++k) {
          (*gradient)[static_cast<Eigen::Index>(index(p, curve, d, k))] += g[d] * tb.cos[static_cast<std::size_t>(ii * p.modes + k - 1)];
          (*gradient)[static_cast<Eigen::Index>(index(p, curve, d, p.modes + k))] += g[d] * tb.sin[static_cast<std::size_t>(ii * p.modes + k - 1)];
        }
      }
    }
  }
  return A;
}

namespace {
struct NloptData {
  const LeastActionProblem* p;
  Workspace* workspace;
  int evaluations = 0;
};
double objective(unsigned n, const double* x, double* grad, void* data) {
  auto* d = static_cast<NloptData*>(data);
  ++d->evaluations;
  const Eigen::Map<const VectorXd> c(x, n);
  if (!grad) return action(*d->p, c, nullptr, d->workspace);
  VectorXd g;
  const double A = action(*d->p, c, &g, d->workspace);
  std::copy(g.data(), g.data() + n, grad);
  return std::isfinite(A) ? A : 1e300;
}
}  // namespace

FourierOrbit minimize_action(const LeastActionProblem& p, const VectorXd& start, int max_evaluations) {
  p.validate();
  const auto n = static_cast<unsigned>(p.size());
  nlopt_opt opt = nlopt_create(NLOPT_LD_LBFGS, n);
  const auto workspace = p.model.potential->make_workspace();
  NloptData data{&p, workspace.get()};
  nlopt_set_min_objective(opt, &objective, &data);
  nlopt_set_ftol_rel(opt, 1e-15);
  nlopt_set_xtol_rel(opt, 1e-13);
  nlopt_set_maxeval(opt, max_evaluations);
  nlopt_set_vector_storage(opt, 20);
  std::vector<double> x(start.data(), start.data() + start.size());
  double f = 0;
  nlopt_optimize(opt, x.data(), &f);  // stops on tolerance, roundoff or maxeval; judged below
  nlopt_destroy(opt);
  FourierOrbit o;
  o.coefficients = Eigen::Map<VectorXd>(x.data(), static_cast<Eigen::Index>(n));
  o.action = f;
  o.evaluations = data.evaluations;
  // Residual of the equations of motion m ω² z'' = F along the curve (F from the model, in
  // 3-D: a force out of the plane counts as residual), and the closest approach.
  const Tables tb = tables(p);
  const double omega2 = std::pow(kTwoPi / p.period, 2);
  double worst = 0, fmax = 0;
  o.min_distance = 1e300;
  State state = State::zeros(p.model.system);
  Forces forces;
  forces.resize(p.model.system);
  for (int i = 0; i < p.points; ++i) {
    std::vector<Eigen::Vector2d> X(p.n()), Acc(p.n());
    for (std::size_t j = 0; j < p.n(); ++j) {
      const auto [curve, ii] = curve_of(p, j, i);
      for (int d = 0; d < 2; ++d) {
        double z, zd, zdd;
        evaluate_curve(p, tb, o.coefficients, curve, d, ii, z, zd, zdd);
        X[j][d] = z;
        Acc[j][d] = omega2 * zdd;
      }
    }
    place(X, state);
    p.model.potential->evaluate(state, forces, *workspace);
    for (std::size_t j = 0; j < p.n(); ++j) {
      for (std::size_t l = j + 1; l < p.n(); ++l) o.min_distance = std::min(o.min_distance, (X[l] - X[j]).norm());
      const Vec3 F = forces.f.col(static_cast<Eigen::Index>(j));
      const Vec3 ma(p.mass(j) * Acc[j].x(), p.mass(j) * Acc[j].y(), 0.0);
      worst = std::max(worst, (ma - F).norm());
      fmax = std::max(fmax, F.norm());
    }
  }
  o.residual = fmax > 0 ? worst / fmax : worst;
  return o;
}

VectorXd random_start(const LeastActionProblem& p, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  VectorXd c = VectorXd::Zero(static_cast<Eigen::Index>(p.size()));
  for (std::size_t curve = 0; curve < p.curves(); ++curve)
    for (int d = 0; d < 2; ++d) {
      if (!p.choreography) c[static_cast<Eigen::Index>(index(p, curve, d, 0))] = normal(rng);
      for (int k = 1; k <= p.modes; ++k) {
        c[static_cast<Eigen::Index>(index(p, curve, d, k))] = normal(rng) / k;
        c[static_cast<Eigen::Index>(index(p, curve, d, p.modes + k))] = normal(rng) / k;
      }
    }
  return c;
}

Eigen::Vector2d fourier_position(const LeastActionProblem& p, const VectorXd& c, std::size_t j, double t) {
  const std::size_t curve = p.choreography ? 0 : j;
  const double tt = p.choreography ? t + kTwoPi * static_cast<double>(j) / static_cast<double>(p.n()) : t;
  Eigen::Vector2d z;
  for (int d = 0; d < 2; ++d) {
    z[d] = c[static_cast<Eigen::Index>(index(p, curve, d, 0))];
    for (int k = 1; k <= p.modes; ++k)
      z[d] += c[static_cast<Eigen::Index>(index(p, curve, d, k))] * std::cos(k * tt) +
              c[static_cast<Eigen::Index>(index(p, curve, d, p.modes + k))] * std::sin(k * tt);
  }
  return z;
}

VectorXd FourierOrbit::initial_state(const LeastActionProblem& p) const {
  const auto n = static_cast<Eigen::Index>(p.n());
  VectorXd xi(4 * n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const std::size_t curve = p.choreography ? 0 : static_cast<std::size_t>(j);
    const double t = p.choreography ? kTwoPi * static_cast<double>(j) / static_cast<double>(n) : 0.0;
    for (int d = 0; d < 2; ++d) {
      double z = coefficients[static_cast<Eigen::Index>(index(p, curve, d, 0))], zd = 0;
      for (int k = 1; k <= p.modes; ++k) {
        const double a = coefficients[static_cast<Eigen::Index>(index(p, curve, d, k))];
        const double b = coefficients[static_cast<Eigen::Index>(index(p, curve, d, p.modes + k))];
        z += a * std::cos(k * t) + b * std::sin(k * t);
        zd += k * (-a * std::sin(k * t) + b * std::cos(k * t));
      }
      xi[2 * j + d] = z;
      xi[2 * n + 2 * j + d] = (kTwoPi / p.period) * zd;  // dz/dt = ω dz/dτ
    }
  }
  return xi;
}

}  // namespace noether
