// j2: Newtonian gravity between all bodies plus the J2 oblateness of one rigid body, the
// primary, acting on every other body — with the moment those bodies exert back on it.
//
// The primary's symmetry axis is k = R_P e3 (its body z axis). For a body j at r = x_j − x_P,
//   U = −Σ_{i<j} G m_i m_j / r_ij  +  Σ_j (C_j/2) (3 (k·r)² / r⁵ − 1 / r³),
// with C_j = G M_P m_j J2 Re², since the primary's exterior potential per unit mass is
//   V = −(G M_P / r) [1 − J2 (Re/r)² P2(k·r/r)],  P2(s) = (3s² − 1)/2.
// Derivatives (docs/equations.md §2):
//   ∂U_J2/∂r = (C/2) [6 (k·r) k / r⁵ − 15 (k·r)² r / r⁷ + 3 r / r⁵]
//   ∂U_J2/∂k = 3 C (k·r) r / r⁵,  and the primary's body-frame moment is
//   M_P = (R_Pᵀ ∂U/∂k) × e3   (η·M = −dU/dε along R exp(εS(η)), with dk = R (η × e3)).
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <cmath>

namespace {

using noether::Forces;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using Vec3 = Eigen::Vector3d;

class J2Potential final : public noether::Potential {
 public:
  J2Potential(const System& system, const Params& p)
      : G_(system.G()), J2_(p.at("J2").as_double()), Re_(p.at("radius").as_double()) {
    const std::string name = p.at("primary").as_string();
    const int i = system.index_of(name);
    if (i < 0) throw SceneError(p.at("primary").here() + "j2: no body named '" + name + "'");
    if (system.rigid_index(static_cast<std::size_t>(i)) < 0)
      throw SceneError(p.at("primary").here() + "j2: the primary '" + name +
                       "' must be a rigid body (give it an inertia): its attitude sets the axis");
    if (!(Re_ > 0.0)) throw SceneError(p.at("radius").here() + "j2: radius must be positive");
    primary_ = static_cast<std::size_t>(i);
    primary_rigid_ = system.rigid_index(primary_);
    for (const auto& b : system.bodies()) mass_.push_back(b.mass);
  }

  void evaluate(const State& s, Forces& out, noether::Workspace&) const override {
    out.set_zero();
    const auto n = static_cast<std::size_t>(s.x.cols());
    // Point-mass field between every pair.
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const Vec3 d = s.x.col(static_cast<Eigen::Index>(i)) - s.x.col(static_cast<Eigen::Index>(j));
        const double r = d.norm(), Gmm = G_ * mass_[i] * mass_[j];
        out.U -= Gmm / r;
        const Vec3 F = (-Gmm / (r * r * r)) * d;
        out.f.col(static_cast<Eigen::Index>(i)) += F;
        out.f.col(static_cast<Eigen::Index>(j)) -= F;
      }
    // The primary's J2 acting on every other body, and back.
    const noether::Mat3& R = s.R[static_cast<std::size_t>(primary_rigid_)];
    const Vec3 k = R.col(2);
    const auto P = static_cast<Eigen::Index>(primary_);
    Vec3 dU_dk = Vec3::Zero();
    for (std::size_t j = 0; j < n; ++j) {
      if (j == primary_) continue;
      const auto J = static_cast<Eigen::Index>(j);
      const Vec3 r = s.x.col(J) - s.x.col(P);
      const double r2 = r.squaredNorm(), rn = std::sqrt(r2), r3 = r2 * rn, r5 = r3 * r2;
      const double kr = k.dot(r);
      const double C = G_ * mass_[primary_] * mass_[j] * J2_ * Re_ * Re_;
      out.U += 0.5 * C * (3.0 * kr * kr / r5 - 1.0 / r3);
      const Vec3 dU_dr = 0.5 * C * (6.0 * kr / r5 * k - 15.0 * kr * kr / (r5 * r2) * r + 3.0 / r5 * r);
      out.f.col(J) -= dU_dr;
      out.f.col(P) += dU_dr;
      dU_dk += 3.0 * C * kr / r5 * r;
    }
    out.M.col(primary_rigid_) += (R.transpose() * dU_dk).cross(Vec3::UnitZ());
  }


 private:
  double G_, J2_, Re_;
  std::size_t primary_ = 0;
  int primary_rigid_ = 0;
  std::vector<double> mass_;
};

const noether::ParamDoc params[] = {
    {"primary", "string", nullptr, "name of the oblate rigid body; its body z axis is the pole"},
    {"J2", "number", nullptr, "second zonal harmonic of the primary (dimensionless)"},
    {"radius", "number", nullptr, "reference (equatorial) radius Re of the primary"},
};

std::unique_ptr<noether::Potential> make(const System& system, const Params& p) {
  return std::make_unique<J2Potential>(system, p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {NOETHER_PLUGIN_API_VERSION,
                             noether::PluginKind::Potential,
                             "j2",
                             "point masses plus the J2 oblateness of one rigid primary",
                             params,
                             std::size(params),
                             &make,
                             nullptr};
