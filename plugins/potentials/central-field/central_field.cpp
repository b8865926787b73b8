// central-field: a fixed point mass (the centre of a restricted problem) attracting every body,
//   U = −Σ_i μ m_i / ‖x_i − c‖,   μ = G M of the centre.
// An external field: total momentum is not conserved (check-potential --no-third-law). Add
// point-mass to the scene's potential list for the bodies' mutual attraction.
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <cmath>
#include <sstream>

namespace {

class CentralField final : public noether::Potential {
 public:
  CentralField(const noether::System& system, const noether::Params& p) {
    mu_ = p.at("mu").as_double();
    if (!(mu_ > 0)) throw noether::SceneError(p.at("mu").here() + "central-field: mu must be positive");
    const auto c = p.at("center").as_doubles();
    if (c.size() != 3) throw noether::SceneError(p.at("center").here() + "central-field: center needs 3 numbers");
    c_ = Eigen::Vector3d(c[0], c[1], c[2]);
    for (const auto& b : system.bodies()) {
      mass_.push_back(b.mass);
      name_.push_back(b.name);
    }
  }
  void evaluate(const noether::State& s, noether::Forces& out, noether::Workspace&) const override {
    out.set_zero();
    for (Eigen::Index i = 0; i < s.x.cols(); ++i) {
      const Eigen::Vector3d d = offset(s, i);
      const double r = d.norm();
      const double mum = mu_ * mass_[static_cast<std::size_t>(i)];
      out.U -= mum / r;
      out.f.col(i) = (-mum / (r * r * r)) * d;
    }
  }
  // The force Jacobian (docs/equations.md §20): body i's own block only,
  // ∂f_i/∂x_i = −μ m_i (I − 3 d̂ d̂ᵀ)/r³ with d = x_i − c (20.1).
  bool force_jacobian(const noether::State& s, Eigen::MatrixXd& K, noether::Workspace&) const override {
    for (Eigen::Index i = 0; i < s.x.cols(); ++i) {
      const Eigen::Vector3d d = offset(s, i);
      const double r2 = d.squaredNorm(), r = std::sqrt(r2);
      const double mum = mu_ * mass_[static_cast<std::size_t>(i)];
      K.block<3, 3>(3 * i, 3 * i) -= mum / (r2 * r) * (Eigen::Matrix3d::Identity() - 3.0 * d * d.transpose() / r2);
    }
    return true;
  }

 private:
  // d = x_i − c, refused when body i is at the centre (U is singular there).
  Eigen::Vector3d offset(const noether::State& s, Eigen::Index i) const {
    const Eigen::Vector3d d = s.x.col(i) - c_;
    if (!(d.squaredNorm() > 0)) {
      std::ostringstream msg;
      msg << "central-field: body '" << name_[static_cast<std::size_t>(i)] << "' is at the centre at t = " << s.t;
      throw noether::IntegrationError(msg.str(), s.t);
    }
    return d;
  }

  double mu_ = 1;
  Eigen::Vector3d c_ = Eigen::Vector3d::Zero();
  std::vector<double> mass_;
  std::vector<std::string> name_;
};

const noether::ParamDoc params[] = {
    {"mu", "number", nullptr, "G M of the fixed centre"},
    {"center", "list", "[0, 0, 0]", "position of the centre"},
};

std::unique_ptr<noether::Potential> make(const noether::System& s, const noether::Params& p) {
  return std::make_unique<CentralField>(s, p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {NOETHER_PLUGIN_API_VERSION,
                             noether::PluginKind::Potential,
                             "central-field",
                             "a fixed attracting centre (restricted problems, Kepler with a fixed Sun)",
                             params,
                             std::size(params),
                             &make,
                             nullptr};
