#include <noether/error.hpp>
#include <noether/phase_chart.hpp>

#include <cmath>

namespace noether {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

PhaseChart::PhaseChart(const System& system, State base, double length, double rate)
    : system_(&system), base_(std::move(base)), length_(length), rate_(rate) {
  if (!(length > 0) || !(rate > 0)) throw SceneError("phase chart: the length and rate scales must be positive");
  n_ = static_cast<Index>(system.size());
  r_ = static_cast<Index>(system.rigid_count());
  d_ = 6 * n_ + 6 * r_;
  scale_.resize(d_);
  scale_.head(3 * n_).setConstant(length);
  scale_.segment(3 * n_, 3 * n_).setConstant(rate * length);
  scale_.segment(6 * n_, 3 * r_).setConstant(1.0);
  for (Index k = 0; k < r_; ++k)
    scale_.segment<3>(Pi(static_cast<std::size_t>(k))).setConstant(
        rate * 0.5 * system.body(system.body_of_rigid(static_cast<std::size_t>(k))).inertia.trace());
}

State PhaseChart::retract(const VectorXd& delta) const {
  const VectorXd d = delta.cwiseProduct(scale_);
  State s = base_;
  for (std::size_t i = 0; i < system_->size(); ++i) {
    const auto j = static_cast<Index>(i);
    s.x.col(j) += d.segment<3>(x(i));
    s.p.col(j) += system_->body(i).mass * d.segment<3>(v(i));
  }
  for (std::size_t k = 0; k < system_->rigid_count(); ++k) {
    s.R[k] = base_.R[k] * exp_so3(d.segment<3>(eta(k)));
    s.Pi.col(static_cast<Index>(k)) += d.segment<3>(Pi(k));
  }
  return s;
}

VectorXd PhaseChart::local(const State& s) const {
  VectorXd d(d_);
  for (std::size_t i = 0; i < system_->size(); ++i) {
    const auto j = static_cast<Index>(i);
    d.segment<3>(x(i)) = s.x.col(j) - base_.x.col(j);
    d.segment<3>(v(i)) = (s.p.col(j) - base_.p.col(j)) / system_->body(i).mass;
  }
  for (std::size_t k = 0; k < system_->rigid_count(); ++k) {
    d.segment<3>(eta(k)) = log_so3(base_.R[k].transpose() * s.R[k]);
    d.segment<3>(Pi(k)) = s.Pi.col(static_cast<Index>(k)) - base_.Pi.col(static_cast<Index>(k));
  }
  return d.cwiseQuotient(scale_);
}

namespace {

// J_r(φ) = I − (1 − cos x)/x² S(φ) + (x − sin x)/x³ S(φ)², x = ‖φ‖: exp(S(φ + ε)) =
// exp(S(φ)) exp(S(J_r(φ) ε)) to first order (series below x = 1e-2).
Mat3 right_jacobian(const Vec3& phi) {
  const double x = phi.norm(), x2 = x * x;
  const double a = x < 1e-2 ? 0.5 - x2 / 24 + x2 * x2 / 720 : (1 - std::cos(x)) / x2;
  const double b = x < 1e-2 ? 1.0 / 6 - x2 / 120 + x2 * x2 / 5040 : (x - std::sin(x)) / (x2 * x);
  const Mat3 S = hat(phi);
  return Mat3::Identity() - a * S + b * S * S;
}

// J_r⁻¹(φ) = I + ½ S(φ) + c S(φ)², c = 1/x² − (1 + cos x)/(2 x sin x) (series below 1e-2).
Mat3 inverse_right_jacobian(const Vec3& phi) {
  const double x = phi.norm();
  const double c = x < 1e-2 ? 1.0 / 12 + x * x / 720 + std::pow(x, 4) / 30240
                            : 1 / (x * x) - (1 + std::cos(x)) / (2 * x * std::sin(x));
  const Mat3 S = hat(phi);
  return Mat3::Identity() + 0.5 * S + c * S * S;
}

}  // namespace

MatrixXd PhaseChart::retract_derivative(const VectorXd& delta) const {
  // x = x⁰ + s_x δ_x, γ = γ⁰ + m s_v δ_v, R = R⁰ exp(S(s_η δ_η)), Π = Π⁰ + s_Π δ_Π.
  const Index q = 3 * n_ + 3 * r_;
  MatrixXd A = MatrixXd::Zero(2 * q, d_);
  for (std::size_t i = 0; i < system_->size(); ++i) {
    const auto j = static_cast<Index>(i);
    for (Index a = 0; a < 3; ++a) {
      A(3 * j + a, x(i) + a) = scale_[x(i) + a];
      A(q + 3 * j + a, v(i) + a) = system_->body(i).mass * scale_[v(i) + a];
    }
  }
  for (std::size_t k = 0; k < system_->rigid_count(); ++k) {
    const auto r = static_cast<Index>(k);
    const Vec3 eta_k = delta.segment<3>(eta(k)).cwiseProduct(scale_.segment<3>(eta(k)));
    A.block<3, 3>(3 * n_ + 3 * r, eta(k)) = right_jacobian(eta_k) * scale_.segment<3>(eta(k)).asDiagonal();
    for (Index a = 0; a < 3; ++a) A(q + 3 * n_ + 3 * r + a, Pi(k) + a) = scale_[Pi(k) + a];
  }
  return A;
}

MatrixXd PhaseChart::local_derivative(const State& state) const {
  const Index q = 3 * n_ + 3 * r_;
  MatrixXd B = MatrixXd::Zero(d_, 2 * q);
  for (std::size_t i = 0; i < system_->size(); ++i) {
    const auto j = static_cast<Index>(i);
    for (Index a = 0; a < 3; ++a) {
      B(x(i) + a, 3 * j + a) = 1.0 / scale_[x(i) + a];
      B(v(i) + a, q + 3 * j + a) = 1.0 / (system_->body(i).mass * scale_[v(i) + a]);
    }
  }
  for (std::size_t k = 0; k < system_->rigid_count(); ++k) {
    const auto r = static_cast<Index>(k);
    const Mat3 J = inverse_right_jacobian(log_so3(base_.R[k].transpose() * state.R[k]));
    B.block<3, 3>(eta(k), 3 * n_ + 3 * r) = scale_.segment<3>(eta(k)).cwiseInverse().asDiagonal() * J;
    for (Index a = 0; a < 3; ++a) B(Pi(k) + a, q + 3 * n_ + 3 * r + a) = 1.0 / scale_[Pi(k) + a];
  }
  return B;
}

MatrixXd PhaseChart::barycentre_free_basis() const {
  MatrixXd C = MatrixXd::Zero(6, d_);
  for (std::size_t i = 0; i < system_->size(); ++i)
    for (Index a = 0; a < 3; ++a) {
      C(a, x(i) + a) = system_->body(i).mass * scale_[x(i) + a];
      C(3 + a, v(i) + a) = system_->body(i).mass * scale_[v(i) + a];
    }
  // The null space of C: the last d − 6 right singular vectors.
  Eigen::JacobiSVD<MatrixXd> svd(C, Eigen::ComputeFullV);
  return svd.matrixV().rightCols(d_ - 6);
}

VectorXd PhaseChart::rotation_generator(const Vec3& e, const Vec3& frame) const {
  double M = 0;
  Vec3 c = Vec3::Zero(), vc = Vec3::Zero();
  for (std::size_t i = 0; i < system_->size(); ++i) {
    M += system_->body(i).mass;
    c += system_->body(i).mass * base_.x.col(static_cast<Index>(i));
    vc += base_.p.col(static_cast<Index>(i));
  }
  c /= M;
  vc /= M;
  VectorXd g = VectorXd::Zero(d_);
  for (std::size_t i = 0; i < system_->size(); ++i) {
    const auto j = static_cast<Index>(i);
    const Vec3 r = base_.x.col(j) - c, u = base_.p.col(j) / system_->body(i).mass - vc;
    g.segment<3>(x(i)) = e.cross(r);
    // Velocities in a frame turning at `frame`: u = ẋ − frame × x; rotating the configuration by
    // e (to first order) turns the inertial velocity with it, so δu = e × (u + frame × r) − frame × (e × r).
    g.segment<3>(v(i)) = e.cross(u + frame.cross(r)) - frame.cross(e.cross(r));
  }
  for (std::size_t k = 0; k < system_->rigid_count(); ++k) g.segment<3>(eta(k)) = base_.R[k].transpose() * e;
  return g.cwiseQuotient(scale_);
}

}  // namespace noether
