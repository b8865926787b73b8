// tides: the tide other bodies raise on one body, with a constant time lag (Mignard 1979; Hut 1981;
// docs/equations.md §34). The body is rigid (its spin takes the tidal torque) with a Love number
// k2, a radius R and a time lag Δt; every other body B is a point mass to it. B feels
//
//   F = −(3 k2 G m_B² R⁵ / r¹⁰) [ r² r + Δt (2 r (r·v) + r² (r × ω + v)) ]                   (34.1)
//
// with r = x_B − x_A, v = v_B − v_A and ω = R_A J_A⁻¹ Π_A the body's inertial spin; the body
// feels −F and the torque −r × F (34.2), so that total linear and angular momentum are
// conserved exactly. The first term is the static bulge, the gradient of −k2 G m_B² R⁵ / (2 r⁶);
// the second the lagged one, whose power is −(3 k2 G m_B² R⁵ Δt / r¹⁰)(r² |u|² + 2 (r·v)²) ≤ 0
// with u = v + r × ω (34.3): it only dissipates.
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using noether::Forces;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

class Tides final : public noether::ForceModel {
 public:
  Tides(const System& system, const Params& p) : G_(system.G()) {
    const std::string name = p.at("body").as_string();
    const int index = system.index_of(name);
    if (index < 0) throw SceneError(p.at("body").here() + "tides: no body named '" + name + "'");
    body_ = static_cast<std::size_t>(index);
    const auto& b = system.body(body_);
    if (!b.rigid)
      throw SceneError(p.at("body").here() + "tides: body '" + name +
                       "' is a point mass: its spin must take the tidal torque, so give it an inertia or a shape");
    rigid_ = static_cast<Eigen::Index>(system.rigid_index(body_));
    inertia_inverse_ = b.inertia_inverse;
    k2_ = p.at("k2").as_double();
    lag_ = p.at("time_lag").as_double();
    radius_ = p.has("radius") ? p.at("radius").as_double() : b.radius;
    static_bulge_ = p.at("static_bulge").as_bool();
    radius5_ = std::pow(radius_, 5);
    if (!(k2_ >= 0.0) || !std::isfinite(k2_)) throw SceneError(p.at("k2").here() + "tides: k2 must be ≥ 0 and finite");
    if (!(lag_ >= 0.0) || !std::isfinite(lag_))
      throw SceneError(p.at("time_lag").here() + "tides: time_lag must be ≥ 0 and finite");
    if (!(radius_ > 0.0) || !std::isfinite(radius_))
      throw SceneError((p.has("radius") ? p.at("radius").here() : p.here()) + "tides: body '" + name +
                       "' has no radius: give tides a radius (or the body a shape or a radius)");
    if (p.has("perturbers")) {
      for (const auto& item : p.at("perturbers").items()) {
        const int j = system.index_of(item.as_string());
        if (j < 0 || static_cast<std::size_t>(j) == body_)
          throw SceneError(item.here() + "tides: '" + item.as_string() + "' is not another body of the scene");
        perturbers_.push_back(static_cast<std::size_t>(j));
      }
    } else {
      for (std::size_t j = 0; j < system.size(); ++j)
        if (j != body_) perturbers_.push_back(j);
    }
    for (std::size_t j = 0; j < system.size(); ++j) mass_.push_back(system.body(j).mass);
  }

  void evaluate(const State& s, Forces& out, noether::Workspace&) const override {
    out.set_zero();
    const auto a = static_cast<Eigen::Index>(body_);
    const Vec3 xa = s.x.col(a), va = s.p.col(a) / mass_[body_];
    const noether::Mat3& Ra = s.R[static_cast<std::size_t>(rigid_)];
    const Vec3 omega = Ra * (inertia_inverse_ * Vec3(s.Pi.col(rigid_)));  // inertial spin
    Vec3 torque = Vec3::Zero();
    for (const std::size_t j : perturbers_) {
      const auto b = static_cast<Eigen::Index>(j);
      const Vec3 r = Vec3(s.x.col(b)) - xa;
      const Vec3 v = Vec3(s.p.col(b)) / mass_[j] - va;
      const double r2 = r.squaredNorm();
      if (!(r2 > 0.0)) throw noether::IntegrationError("tides: two bodies at the same position", s.t);
      const double c = 3.0 * k2_ * G_ * mass_[j] * mass_[j] * radius5_ / (r2 * r2 * r2 * r2 * r2);
      Vec3 bracket = lag_ * (2.0 * r.dot(v) * r + r2 * (r.cross(omega) + v));  // (34.1)
      if (static_bulge_) bracket += r2 * r;
      const Vec3 F = -c * bracket;
      out.f.col(b) += F;
      out.f.col(a) -= F;
      torque -= r.cross(F);  // (34.2)
    }
    out.M.col(rigid_) = Ra.transpose() * torque;
  }

 private:
  double G_;
  std::size_t body_ = 0;
  Eigen::Index rigid_ = 0;
  noether::Mat3 inertia_inverse_;
  double k2_ = 0.0, lag_ = 0.0, radius_ = 0.0, radius5_ = 0.0;  // R and R⁵
  bool static_bulge_ = true;
  std::vector<std::size_t> perturbers_;
  std::vector<double> mass_;
};

const noether::ParamDoc params[] = {
    {"body", "string", nullptr, "the body the tide is raised on (rigid: its spin takes the tidal torque)"},
    {"k2", "number", nullptr, "its Love number k2 (≥ 0)"},
    {"time_lag", "number", nullptr,
     "its constant time lag Δt (≥ 0), in the scene's unit of time; Q ≈ 1 / (2 |ω − n| Δt) for a spin ω and "
     "a mean motion n (docs/forces.md)"},
    {"radius", "number", "(the body's radius)", "the radius R of its tidal bulge, R⁵ in (34.1)"},
    {"static_bulge", "bool", "true",
     "include the static (unlagged) bulge's force, the gradient of −k2 G m² R⁵/(2 r⁶), conservative"},
    {"perturbers", "list", "(every other body)", "the bodies that raise the tide (point masses to it)"},
};

std::unique_ptr<noether::ForceModel> make(const System& system, const Params& p) {
  return std::make_unique<Tides>(system, p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Force,
    "tides",
    "constant-time-lag tides raised on a rigid body by the others (Mignard 1979): forces and spin torque",
    params,
    std::size(params),
    nullptr,
    nullptr,
    &make};
