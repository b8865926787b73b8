// spherical-harmonics: one body's exterior gravity field as spherical harmonics to degree N
// (Cunningham's recursion, docs/equations.md §32), acting on every other body of the scene as on
// a point mass — a spacecraft or particles about an asteroid — with the reaction on the field
// body: the opposite force and the torque M = −m r × ∇V in its body frame (32.3). Pairs that do
// not involve the field body are Newtonian point masses. The field is the body's own Stokes
// coefficients (a body given by `gravity:`) or those of its shape (ellipsoid or polyhedron, at its
// radius). The series converges outside the Brillouin sphere (the body's radius): a body inside
// it is warned about once, as the values there are those of the truncated series, not the body's.
#include <noether/error.hpp>
#include <noether/plugin.hpp>
#include <noether/spherical_harmonic_field.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace {

using noether::Forces;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

struct FieldWorkspace final : noether::Workspace {
  std::optional<noether::SphericalHarmonicField> field;  // its scratch
  std::vector<bool> warned;                              // inside the Brillouin sphere, per body
};

class SphericalHarmonics final : public noether::Potential {
 public:
  SphericalHarmonics(const System& system, const Params& params) : G_(system.G()) {
    const std::string name = params.at("body").as_string();
    const int index = system.index_of(name);
    if (index < 0)
      throw SceneError(params.at("body").here() + "spherical-harmonics: no body named '" + name + "'");
    body_ = static_cast<std::size_t>(index);
    const noether::Body& b = system.body(body_);
    const long N = params.at("degree").as_int();
    const int top = noether::multi_index::kMaxDegree;  // the recursion's, on unnormalised coefficients
    const int known = b.field ? std::min(b.field->degree, top) : top;
    if (N < 0 || N > known)
      throw SceneError(params.at("degree").here() + "spherical-harmonics: degree " + std::to_string(N) +
                       " is outside 0.." + std::to_string(known) +
                       (b.field && b.field->degree < top ? " (the degree of body '" + name + "''s field)"
                                                         : " (the highest this model evaluates)"));
    const int degree = static_cast<int>(N);
    if (b.field) {
      coefficients_ = noether::truncated(*b.field, degree, false);
    } else if (b.solid) {
      coefficients_ = noether::stokes_from_integrals(b.solid->integrals(degree), b.solid->radius, degree, false);
    } else {
      throw SceneError(params.at("body").here() + "spherical-harmonics: body '" + name +
                       "' has neither a gravity field (gravity:) nor an ellipsoid or polyhedron shape");
    }
    rigid_ = system.rigid_index(body_);
    brillouin_ = b.radius;
    for (const auto& other : system.bodies()) mass_.push_back(other.mass), names_.push_back(other.name);
  }

  std::unique_ptr<noether::Workspace> make_workspace() const override {
    auto w = std::make_unique<FieldWorkspace>();
    w->field.emplace(coefficients_, G_);
    w->warned.assign(mass_.size(), false);
    return w;
  }

  void evaluate(const State& s, Forces& out, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<FieldWorkspace>(workspace, "spherical-harmonics");
    out.set_zero();
    const auto F = static_cast<Eigen::Index>(body_);
    const noether::Mat3& R = s.R[static_cast<std::size_t>(rigid_)];
    const Eigen::Index n = s.x.cols();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (i == F) continue;
      const double m = mass_[static_cast<std::size_t>(i)];
      const Vec3 r = R.transpose() * (s.x.col(i) - s.x.col(F));  // body frame of the field body
      const double distance = r.norm();
      if (!(distance > 0.0)) collision(body_, static_cast<std::size_t>(i), s.t);
      if (distance < brillouin_ && !w.warned[static_cast<std::size_t>(i)]) {
        w.warned[static_cast<std::size_t>(i)] = true;
        spdlog::warn("spherical-harmonics: body '{}' is {:.6g} from the centre of '{}' at t = {:.6g}, inside its "
                     "Brillouin sphere (radius {:.6g}), where the series of degree {} may not converge to the body's field",
                     names_[static_cast<std::size_t>(i)], distance, names_[body_], s.t, brillouin_,
                     coefficients_.degree);
      }
      const noether::SphericalHarmonicField::Value v = (*w.field)(r);
      out.U -= m * v.potential;
      const Vec3 f = m * (R * v.acceleration);  // on body i (32.3)
      out.f.col(i) += f;
      out.f.col(F) -= f;
      out.M.col(rigid_) -= m * r.cross(v.acceleration);
    }
    for (Eigen::Index i = 0; i < n; ++i)  // the other pairs: Newtonian point masses
      for (Eigen::Index j = i + 1; j < n; ++j) {
        if (i == F || j == F) continue;
        const Vec3 d = s.x.col(i) - s.x.col(j);
        const double r2 = d.squaredNorm();
        if (!(r2 > 0.0)) collision(static_cast<std::size_t>(i), static_cast<std::size_t>(j), s.t);
        const double Gmm = G_ * mass_[static_cast<std::size_t>(i)] * mass_[static_cast<std::size_t>(j)];
        out.U -= Gmm / std::sqrt(r2);
        const Vec3 f = (-Gmm / (r2 * std::sqrt(r2))) * d;
        out.f.col(i) += f;
        out.f.col(j) -= f;
      }
  }

  // K = ∂(f, M)/∂(x, θ) (docs/equations.md §20) from the field's Hessian H = ∇∇V (32.2): with
  // r = R_Fᵀ(x_i − x_F), g = ∇V, f_i = m R_F g and M_F = −m r × g (32.3),
  //   ∂f_i/∂x_i = m R_F H R_Fᵀ,   ∂f_i/∂θ_F = m R_F (H S(r) − S(g)),
  //   ∂M_F/∂r = −m (S(r) H − S(g)),  ∂r/∂x_i = R_Fᵀ = −∂r/∂x_F,  ∂r/∂θ_F = S(r)          (32.4)
  // and f_F = −f_i; the other pairs as point masses.
  bool force_jacobian(const State& s, Eigen::MatrixXd& K, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<FieldWorkspace>(workspace, "spherical-harmonics");
    const auto F = static_cast<Eigen::Index>(body_);
    const noether::Mat3& R = s.R[static_cast<std::size_t>(rigid_)];
    const Eigen::Index n = s.x.cols(), th = 3 * n + 3 * rigid_;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (i == F) continue;
      const double m = mass_[static_cast<std::size_t>(i)];
      const Vec3 r = R.transpose() * (s.x.col(i) - s.x.col(F));
      if (!(r.norm() > 0.0)) collision(body_, static_cast<std::size_t>(i), s.t);
      const noether::SphericalHarmonicField::Value v = (*w.field)(r, true);
      const noether::Mat3 A = m * R * v.hessian * R.transpose();
      const noether::Mat3 B = m * R * (v.hessian * noether::hat(r) - noether::hat(v.acceleration));
      const noether::Mat3 D = -m * (noether::hat(r) * v.hessian - noether::hat(v.acceleration));
      K.block<3, 3>(3 * i, 3 * i) += A;
      K.block<3, 3>(3 * i, 3 * F) -= A;
      K.block<3, 3>(3 * F, 3 * i) -= A;
      K.block<3, 3>(3 * F, 3 * F) += A;
      K.block<3, 3>(3 * i, th) += B;
      K.block<3, 3>(3 * F, th) -= B;
      K.block<3, 3>(th, 3 * i) += D * R.transpose();
      K.block<3, 3>(th, 3 * F) -= D * R.transpose();
      K.block<3, 3>(th, th) += D * noether::hat(r);
    }
    for (Eigen::Index i = 0; i < n; ++i)  // point masses: −∂²U/∂x∂x (docs/equations.md (20.1))
      for (Eigen::Index j = i + 1; j < n; ++j) {
        if (i == F || j == F) continue;
        const Vec3 d = s.x.col(i) - s.x.col(j);
        const double r2 = d.squaredNorm(), r = std::sqrt(r2);
        const double Gmm = G_ * mass_[static_cast<std::size_t>(i)] * mass_[static_cast<std::size_t>(j)];
        const noether::Mat3 P = Gmm / (r2 * r) * (noether::Mat3::Identity() - 3.0 * d * d.transpose() / r2);
        K.block<3, 3>(3 * i, 3 * j) += P;
        K.block<3, 3>(3 * j, 3 * i) += P;
        K.block<3, 3>(3 * i, 3 * i) -= P;
        K.block<3, 3>(3 * j, 3 * j) -= P;
      }
    return true;
  }

 private:
  [[noreturn]] void collision(std::size_t i, std::size_t j, double t) const {
    std::ostringstream msg;
    msg << "spherical-harmonics: bodies '" << names_[i] << "' and '" << names_[j] << "' are at the same position at t = "
        << t << " (a collision)";
    throw noether::IntegrationError(msg.str(), t);
  }

  double G_;
  std::size_t body_ = 0;
  int rigid_ = -1;
  double brillouin_ = 0.0;
  noether::StokesCoefficients coefficients_;
  std::vector<double> mass_;
  std::vector<std::string> names_;
};

std::unique_ptr<noether::Potential> make(const System& system, const Params& params) {
  params.check_keys({"plugin", "body", "degree"}, "the spherical-harmonics potential");
  return std::make_unique<SphericalHarmonics>(system, params);
}

const noether::ParamDoc kParams[] = {
    {"body", "string", nullptr,
     "the body whose field acts on every other body (as on a point mass): given by its field, or an ellipsoid or polyhedron"},
    {"degree", "integer", nullptr, "the highest degree of its spherical-harmonic field, 0..40 (its field's degree at most)"}};

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Potential,
    "spherical-harmonics",
    "one body's exterior field as spherical harmonics to degree N (Cunningham's recursion) on every other body as a "
    "point mass, with the reaction on the field body; other pairs Newtonian",
    kParams,
    2,
    &make,
    nullptr};
