// Parameters of the dynamics in the tangent (docs/equations.md §22).
#include <noether/error.hpp>
#include <noether/parameter_derivatives.hpp>

namespace noether {

namespace {

// g += w (f_1 … f_n, M_1 … M_m): one stencil point's forces in a column of G (22.1), (33.9).
void add_weighted(double w, const Forces& forces, Eigen::Ref<Eigen::VectorXd> g) {
  const Eigen::Index n = forces.f.cols(), m = forces.M.cols();
  for (Eigen::Index i = 0; i < n; ++i) g.segment<3>(3 * i) += w * forces.f.col(i);
  for (Eigen::Index k = 0; k < m; ++k) g.segment<3>(3 * n + 3 * k) += w * forces.M.col(k);
}

}  // namespace

ParameterForces::ParameterForces(std::shared_ptr<const ParameterDerivatives> derivatives)
    : derivatives_(std::move(derivatives)) {
  if (!derivatives_) throw Error("ParameterForces: no parameters");
  for (const DynamicsParameter& p : derivatives_->parameters) {
    const bool models = !p.models.empty(), forces = !p.forcings.empty();
    if ((!models && !forces) || (models && p.models.size() != p.weights.size()) ||
        (forces && (p.forcings.size() != p.weights.size() || p.systems.size() != p.weights.size())))
      throw Error("ParameterForces: parameter '" + p.name + "' has no stencil of models or forces");
    models_.emplace_back();
    for (const auto& model : p.models) models_.back().emplace_back(model);
    evaluations_per_call_ += static_cast<std::int64_t>(p.models.size());
    forcings_.emplace_back();
    for (std::size_t s = 0; s < p.forcings.size(); ++s) forcings_.back().emplace_back(p.systems[s], p.forcings[s]);
    has_forcing_ = has_forcing_ || forces;
  }
}

const Eigen::MatrixXd& ParameterForces::operator()(const State& state) {
  const auto n = static_cast<Eigen::Index>(state.x.cols()), m = static_cast<Eigen::Index>(state.R.size());
  G_.setZero(3 * n + 3 * m, static_cast<Eigen::Index>(size()));
  forces_.f.resize(3, n);
  forces_.M.resize(3, m);
  for (std::size_t j = 0; j < size(); ++j) {
    auto g = G_.col(static_cast<Eigen::Index>(j));
    const std::vector<double>& weights = derivatives_->parameters[j].weights;
    for (std::size_t s = 0; s < models_[j].size(); ++s) {  // Σ_s w_s (f, M)(p_s)             (22.1)
      models_[j][s](state, forces_);
      add_weighted(weights[s], forces_, g);
    }
  }
  return G_;
}

const Eigen::MatrixXd& ParameterForces::forcing(const State& state) {
  const auto n = static_cast<Eigen::Index>(state.x.cols()), m = static_cast<Eigen::Index>(state.R.size());
  G_forcing_.setZero(3 * n + 3 * m, static_cast<Eigen::Index>(size()));
  for (std::size_t j = 0; j < size(); ++j) {
    auto g = G_forcing_.col(static_cast<Eigen::Index>(j));
    const std::vector<double>& weights = derivatives_->parameters[j].weights;
    for (std::size_t s = 0; s < forcings_[j].size(); ++s) {  // Σ_s w_s (f^F, M^F)(p_s) at z   (33.9)
      forcings_[j][s](state);
      add_weighted(weights[s], forcings_[j][s].total(), g);
    }
  }
  return G_forcing_;
}

const Eigen::MatrixXd& ParameterForces::with_forcing(const State& state) {
  G_sum_ = (*this)(state);
  if (has_forcing_) G_sum_ += forcing(state);
  return G_sum_;
}

void add_parameter_rhs(const System& system, const State& state, const ParameterDerivatives& derivatives,
                       const Eigen::MatrixXd& G, Eigen::Ref<Eigen::MatrixXd> dV) {
  const auto n = static_cast<Eigen::Index>(system.size());
  const auto m = static_cast<Eigen::Index>(system.rigid_count());
  const Eigen::Index q = 3 * n + 3 * m;
  for (std::size_t j = 0; j < derivatives.size(); ++j) {
    const DynamicsParameter& p = derivatives.parameters[j];
    auto column = dV.col(static_cast<Eigen::Index>(j));
    const auto g = G.col(static_cast<Eigen::Index>(j));
    for (Eigen::Index i = 0; i < n; ++i) {
      const double mass = system.body(static_cast<std::size_t>(i)).mass;
      column.segment<3>(3 * i) -= (p.mass(i) / (mass * mass)) * state.p.col(i);  // ∂(γ/m)/∂p
      column.segment<3>(q + 3 * i) += g.segment<3>(3 * i);                         // ∂f/∂p
    }
    for (Eigen::Index r = 0; r < m; ++r) {
      const Body& body = system.body(system.body_of_rigid(static_cast<std::size_t>(r)));
      const Vec3 Pi = state.Pi.col(r);
      const Vec3 dOmega = -body.inertia_inverse * (p.inertia[static_cast<std::size_t>(r)] * (body.inertia_inverse * Pi));
      column.segment<3>(3 * n + 3 * r) += dOmega;
      column.segment<3>(q + 3 * n + 3 * r) += Pi.cross(dOmega) + g.segment<3>(3 * n + 3 * r);
    }
  }
}

}  // namespace noether
