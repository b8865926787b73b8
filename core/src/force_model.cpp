#include <noether/error.hpp>
#include <noether/force_jacobian.hpp>
#include <noether/force_model.hpp>

#include <cmath>

namespace noether {

ForceModel::~ForceModel() = default;
std::unique_ptr<Workspace> ForceModel::make_workspace() const { return std::make_unique<Workspace>(); }
bool ForceModel::depends_on_momenta() const { return true; }
void ForceModel::choose_models(const State&) {}
std::vector<PairModel> ForceModel::pair_models() const { return {}; }
bool ForceModel::pull_particles(const State&, std::vector<PointPull>&) const { return false; }

Eigen::Matrix<double, kBalanceRows, 1> balance_rate(const System& system, const State& state, const Forces& force) {
  Eigen::Matrix<double, kBalanceRows, 1> rate = Eigen::Matrix<double, kBalanceRows, 1>::Zero();
  for (std::size_t i = 0; i < system.size(); ++i) {  // (33.3)
    const auto c = static_cast<Eigen::Index>(i);
    const Vec3 f = force.f.col(c);
    rate(0) += f.dot(state.p.col(c)) / system.body(i).mass;
    rate.segment<3>(1) += f;
    rate.segment<3>(4) += Vec3(state.x.col(c)).cross(f);
  }
  for (std::size_t k = 0; k < system.rigid_count(); ++k) {
    const auto c = static_cast<Eigen::Index>(k);
    const Body& b = system.body(system.body_of_rigid(k));
    const Vec3 M = force.M.col(c);
    rate(0) += M.dot(b.inertia_inverse * Vec3(state.Pi.col(c)));
    rate.segment<3>(4) += state.R[k] * M;
  }
  return rate;
}

ForcingEvaluator::ForcingEvaluator(const System& system, std::shared_ptr<const Forcing> forcing)
    : system_(system), forcing_(std::move(forcing)) {
  if (!forcing_) throw Error("ForcingEvaluator: no forces given");
  for (const ForceTerm& term : *forcing_) {
    if (!term.model) throw Error("force '" + term.name + "' has no model");
    workspaces_.push_back(term.model->make_workspace());
    if (!workspaces_.back()) throw Error("force '" + term.name + "' made no workspace");
    depends_on_momenta_ = depends_on_momenta_ || term.model->depends_on_momenta();
    terms_.emplace_back();
    terms_.back().resize(system_);
  }
  total_.resize(system_);
}

void ForcingEvaluator::check_balance(const State& state, const char* who) const {
  if (state.force_balance.rows() != kBalanceRows || state.force_balance.cols() != static_cast<Eigen::Index>(size()))
    throw Error(std::string(who) + ": the state carries no balance of its " + std::to_string(size()) +
                " forces (State::force_balance)");
}

void ForcingEvaluator::operator()(const State& state) {
  total_.set_zero();
  for (std::size_t j = 0; j < terms_.size(); ++j) {
    Forces& f = terms_[j];
    (*forcing_)[j].model->evaluate(state, f, *workspaces_[j]);
    if (!f.f.allFinite() || !f.M.allFinite())
      throw IntegrationError("force '" + (*forcing_)[j].name + "' returned a non-finite force or moment at t = " +
                                 std::to_string(state.t),
                             state.t);
    total_.f += f.f;
    total_.M += f.M;
  }
}

void ForcingEvaluator::add_kick(const State& before, const State& after, double tau, Eigen::MatrixXd& balance) {
  // The kick's mean momenta at its (fixed) positions and attitudes: its balance (33.4).
  mean_.x = before.x;
  mean_.R = before.R;
  mean_.p = 0.5 * (before.p + after.p);
  mean_.Pi = 0.5 * (before.Pi + after.Pi);
  for (std::size_t j = 0; j < terms_.size(); ++j)
    balance.col(static_cast<Eigen::Index>(j)) += tau * balance_rate(system_, mean_, terms_[j]);
}

void ForcingEvaluator::add_to_inertial_hamiltonian(const State& state, double* dydt, double* balance_rates) {
  (*this)(state);
  const std::size_t n = system_.size(), nr = system_.rigid_count();
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) dydt[3 * n + 3 * i + a] += total_.f(a, static_cast<Eigen::Index>(i));
  for (std::size_t k = 0; k < nr; ++k)
    for (int a = 0; a < 3; ++a) dydt[6 * n + 9 * nr + 3 * k + a] += total_.M(a, static_cast<Eigen::Index>(k));
  for (std::size_t j = 0; j < terms_.size(); ++j)
    Eigen::Map<Eigen::Matrix<double, kBalanceRows, 1>>(balance_rates + kBalanceRows * j) =
        balance_rate(system_, state, terms_[j]);
}

void ForcingEvaluator::jacobian(const State& state, Eigen::MatrixXd& J) {
  const auto n = static_cast<Eigen::Index>(system_.size()), m = static_cast<Eigen::Index>(system_.rigid_count());
  saved_terms_ = terms_;
  saved_total_ = total_;
  // (33.5): each coordinate's step is ε^{1/3} of its scale, where central differences' truncation
  // (∝ step²) and round-off (∝ ε/step) balance: lengths of the largest separation (or of the
  // largest distance from the origin), momenta of a body's at the fastest speed, angular
  // momenta of the largest |Π| (none spinning: of turning at that speed over that length),
  // attitudes of a radian. A scale that is still zero falls back to 1.
  double L = 0.0, V = 0.0, S = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    L = std::max(L, state.x.col(i).norm());
    for (Eigen::Index j = 0; j < i; ++j) L = std::max(L, (state.x.col(i) - state.x.col(j)).norm());
    V = std::max(V, state.p.col(i).norm() / system_.body(static_cast<std::size_t>(i)).mass);
  }
  for (Eigen::Index k = 0; k < m; ++k) S = std::max(S, state.Pi.col(k).norm());
  if (!(S > 0.0) && L > 0.0)  // no body spins: the angular momentum of turning at V / L
    for (Eigen::Index k = 0; k < m; ++k)
      S = std::max(S, system_.body(system_.body_of_rigid(static_cast<std::size_t>(k))).inertia.norm() * V / L);
  const double step = std::cbrt(std::numeric_limits<double>::epsilon());
  const auto scale = [](double u) { return u > 0.0 && std::isfinite(u) ? u : 1.0; };
  Eigen::VectorXd steps(6 * n + 6 * m);
  for (Eigen::Index i = 0; i < n; ++i) {
    steps.segment(3 * i, 3).setConstant(step * scale(L));
    steps.segment(3 * n + 3 * m + 3 * i, 3).setConstant(step * system_.body(static_cast<std::size_t>(i)).mass * scale(V));
  }
  steps.segment(3 * n, 3 * m).setConstant(step);
  steps.segment(6 * n + 3 * m, 3 * m).setConstant(step * scale(S));
  J = differenced_state_jacobian(state, steps, [&](const State& z) {
    (*this)(z);
    Eigen::VectorXd value(3 * n + 3 * m);
    value << Eigen::Map<const Eigen::VectorXd>(total_.f.data(), 3 * n), Eigen::Map<const Eigen::VectorXd>(total_.M.data(), 3 * m);
    return value;
  });
  terms_ = saved_terms_;
  total_ = saved_total_;
}

}  // namespace noether
