#include <noether/error.hpp>
#include <noether/phase_chart.hpp>

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
