// point-mass: Newtonian gravity between body centres, U = −Σ_{i<j} G m_i m_j / ‖x_i − x_j‖.
// Rigid bodies feel no moment in this model (their attitude does not enter U).
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <cmath>
#include <sstream>

namespace {

using noether::Forces;
using noether::State;
using noether::System;

class PointMass final : public noether::Potential {
 public:
  explicit PointMass(const System& system) : G_(system.G()) {
    for (const auto& b : system.bodies()) {
      mass_.push_back(b.mass);
      name_.push_back(b.name);
    }
  }

  void evaluate(const State& s, Forces& out, noether::Workspace&) const override {
    out.set_zero();
    const Eigen::Index n = s.x.cols();
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = i + 1; j < n; ++j) {
        const Eigen::Vector3d d = s.x.col(i) - s.x.col(j);
        const double r2 = d.squaredNorm();
        if (!(r2 > 0.0)) collision(i, j, s.t);
        const double r = std::sqrt(r2);
        const double Gmm = G_ * mass_[static_cast<std::size_t>(i)] * mass_[static_cast<std::size_t>(j)];
        out.U -= Gmm / r;
        const Eigen::Vector3d F = (-Gmm / (r2 * r)) * d;  // force on i, towards j
        out.f.col(i) += F;
        out.f.col(j) -= F;
      }
    }
  }

  // The force Jacobian (docs/equations.md §20): for each pair, B = G m_i m_j (I − 3 d̂ d̂ᵀ)/r³
  // with d = x_i − x_j is ∂²U_ij/∂x_i² (∂U_ij/∂x_i = G m_i m_j d/r³); K = −∂²U/∂x∂x takes −B in
  // the blocks (i, i) and (j, j) and +B in (i, j) and (j, i) (20.1). Attitudes do not enter U:
  // the rows and columns of rigid bodies' attitudes stay zero.
  bool force_jacobian(const State& s, Eigen::MatrixXd& K, noether::Workspace&) const override {
    const Eigen::Index n = s.x.cols();
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = i + 1; j < n; ++j) {
        const Eigen::Vector3d d = s.x.col(i) - s.x.col(j);
        const double r2 = d.squaredNorm();
        if (!(r2 > 0.0)) collision(i, j, s.t);
        const double r = std::sqrt(r2);
        const double Gmm = G_ * mass_[static_cast<std::size_t>(i)] * mass_[static_cast<std::size_t>(j)];
        const Eigen::Matrix3d B = Gmm / (r2 * r) * (Eigen::Matrix3d::Identity() - 3.0 * d * d.transpose() / r2);
        K.block<3, 3>(3 * i, 3 * j) += B;
        K.block<3, 3>(3 * j, 3 * i) += B;
        K.block<3, 3>(3 * i, 3 * i) -= B;
        K.block<3, 3>(3 * j, 3 * j) -= B;
      }
    return true;
  }

 private:
  [[noreturn]] void collision(Eigen::Index i, Eigen::Index j, double t) const {
    std::ostringstream msg;
    msg << "point-mass: bodies '" << name_[static_cast<std::size_t>(i)] << "' and '"
        << name_[static_cast<std::size_t>(j)] << "' are at the same position at t = " << t
        << " (a collision); U is singular there";
    throw noether::IntegrationError(msg.str(), t);
  }

  double G_;
  std::vector<double> mass_;
  std::vector<std::string> name_;
};

std::unique_ptr<noether::Potential> make(const System& system, const noether::Params&) {
  return std::make_unique<PointMass>(system);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {NOETHER_PLUGIN_API_VERSION,
                             noether::PluginKind::Potential,
                             "point-mass",
                             "Newtonian gravity between body centres (no moments)",
                             nullptr,
                             0,
                             &make,
                             nullptr};
