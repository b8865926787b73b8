// cannonball: sunlight's pressure on a body taken as a sphere — the model spacecraft and dust
// dynamics use when the attitude and the shape do not matter (docs/forces.md, "Cannonball
// radiation"; docs/equations.md §40). A body of mass m, area-to-mass ratio A/m and reflectivity ρ
// (C_R = 1 + ρ: 1 all light absorbed, 2 all reflected back) at distance d from the Sun, û the unit
// vector from the Sun to it, takes
//
//   f = ν m C_R P0 (d0 / d)² (A/m) û,   ν = 0 in another body's shadow, else 1                   (40.1)
//
// at its centre of mass (no torque). With a Sun at rest the push is a repulsion from the Sun in
// 1/d²: the body moves about it as in a Kepler problem of G M (1 − β), β = C_R P0 d0² (A/m) / (G M)
// (40.2), which the tests hold it to. The shadow (40.3): the segment from the body's centre to the
// Sun meets another body's bounding sphere (its `radius`, or its shape's) — a point Sun, no
// penumbra, the lit body a point. Massless particles (`particles: true`) feel the same push, with
// the same A/m and ρ, as a point source of negative G M at the Sun (no shadows for them).
#include <noether/error.hpp>
#include <noether/plugin.hpp>
#include <noether/light_source.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace {

using noether::Forces;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

double positive(const Params& p, const char* key) {
  const double v = p.at(key).as_double();
  if (!(v > 0.0) || !std::isfinite(v)) throw SceneError(p.at(key).here() + "cannonball: '" + key + "' must be positive");
  return v;
}

class Cannonball final : public noether::ForceModel {
 public:
  Cannonball(const System& system, const Params& p) : light_(system, p, "cannonball") {
    const double area_to_mass = positive(p, "area_to_mass");
    const double reflectivity = p.at("reflectivity").as_double();
    if (!(reflectivity >= 0.0 && reflectivity <= 1.0))
      throw SceneError(p.at("reflectivity").here() + "cannonball: 'reflectivity' ρ must be in [0, 1] (C_R = 1 + ρ)");
    const double distance = positive(p, "distance");
    push_ = (1.0 + reflectivity) * positive(p, "pressure") * distance * distance * area_to_mass;  // C_R P0 d0² A/m
    particles_ = p.at("particles").as_bool();
    for (const auto& b : system.bodies()) masses_.push_back(b.mass);

    sun_ = light_.body();

    if (p.has("bodies")) {
      const Params& listed = p.at("bodies");
      if (!listed.is_sequence())
        throw SceneError(listed.here() + "cannonball: 'bodies' must list body names ([spacecraft]; [] for particles only)");
      for (const Params& name : listed.items()) {
        const int index = system.index_of(name.as_string());
        if (index < 0) throw SceneError(name.here() + "cannonball: no body named '" + name.as_string() + "'");
        if (index == sun_) throw SceneError(name.here() + "cannonball: '" + name.as_string() + "' is the Sun");
        for (const Eigen::Index seen : bodies_)
          if (seen == index) throw SceneError(name.here() + "cannonball: '" + name.as_string() + "' is listed twice");
        bodies_.push_back(index);
      }
    }
    if (bodies_.empty() && !particles_)
      throw SceneError(p.here() + "cannonball: it pushes nothing: list 'bodies', or set 'particles: true'");
    if (p.at("eclipses").as_bool())
      for (std::size_t j = 0; j < system.size(); ++j)
        if (static_cast<Eigen::Index>(j) != sun_ && system.body(j).radius > 0.0)
          occluders_.push_back({static_cast<Eigen::Index>(j), system.body(j).radius});
  }

  bool depends_on_momenta() const override { return false; }

  void evaluate(const State& s, Forces& out, noether::Workspace&) const override {
    out.set_zero();
    const Vec3 sun = light_.position(s);
    for (const Eigen::Index i : bodies_) {
      const Vec3 from_sun = Vec3(s.x.col(i)) - sun;
      const double d2 = from_sun.squaredNorm();
      if (!(d2 > 0.0)) throw noether::IntegrationError("cannonball: a body reached the Sun", s.t);
      const double d = std::sqrt(d2);
      if (in_shadow(s, i, -from_sun / d, d)) continue;  // ν = 0 (40.3)
      out.f.col(i) = (masses_[static_cast<std::size_t>(i)] * push_ / (d2 * d)) * from_sun;  // (40.1)
    }
  }

  // The particles feel the push as a point source of G M = −C_R P0 d0² A/m at the Sun (40.1).
  bool pull_particles(const State& s, std::vector<noether::PointPull>& pulls) const override {
    if (!particles_) return false;
    const double sun_mass = sun_ >= 0 ? masses_[static_cast<std::size_t>(sun_)] : 1.0;
    pulls.push_back({-push_, light_.position(s), light_.velocity(s, sun_mass), 0.0});
    return true;
  }


 private:
  // Whether the segment from body i towards the Sun (unit `to_sun`, length d) meets another body's
  // bounding sphere (40.3).
  bool in_shadow(const State& s, Eigen::Index i, const Vec3& to_sun, double d) const {
    for (const Occluder& o : occluders_) {
      if (o.body == i) continue;
      const Vec3 w = Vec3(s.x.col(o.body)) - Vec3(s.x.col(i));
      const double along = w.dot(to_sun);
      if (along <= 0.0 || along >= d) continue;  // behind the body, or beyond the Sun
      if ((w - along * to_sun).squaredNorm() < o.radius * o.radius) return true;
    }
    return false;
  }

  struct Occluder {
    Eigen::Index body;
    double radius;
  };
  double push_ = 0.0;  // C_R P0 d0² (A/m)
  bool particles_ = false;
  Eigen::Index sun_ = -1;
  noether::LightSource light_;
  std::vector<Eigen::Index> bodies_;
  std::vector<Occluder> occluders_;
  std::vector<double> masses_;
};

const noether::ParamDoc params[] = {
    {"bodies", "list", "[]",
     "the bodies pushed, by name (point masses or any others, each taken as a sphere at its centre of mass: no torque)"},
    {"area_to_mass", "number", nullptr,
     "the cross-section area over the mass, A/m, in the scene's units (SI: m²/kg; a spacecraft ~0.01, 10 µm dust ~100)"},
    {"reflectivity", "number", "0", "ρ in [0, 1]: the coefficient C_R = 1 + ρ (0: all light absorbed; 1: all reflected back)"},
    {"pressure", "number", nullptr,
     "the radiation pressure P0 = flux / c of the light at `distance` (SI: 4.5606e-6 N/m² at 1 au), in the scene's "
     "units of force per area"},
    {"distance", "number", nullptr, "the distance d0 of `pressure` (SI: 1.495978707e11 m, 1 au); P = P0 (d0/d)²"},
    {"particles", "bool", "false",
     "push the scene's massless particles too, with the same A/m and ρ (no shadows for them)"},
    {"eclipses", "bool", "true",
     "other bodies' shadows: a body whose segment towards the Sun meets another body's bounding sphere (its radius or "
     "its shape's) takes no light (a point Sun: no penumbra)"},
    {"sun", "string", "(none)", "the light source as a body of the scene (then no conic)"},
    {"position", "list", "(none)", "or the Sun on a conic: its position at `epoch` relative to `center`"},
    {"velocity", "list", "(none)", "its velocity at `epoch` relative to `center`"},
    {"mu", "number", "(none)", "the conic's gravitational parameter (G M of the Sun, required with a conic)"},
    {"epoch", "number", "0", "the time of `position` and `velocity`"},
    {"center", "string", "barycentre", "what the conic is relative to: barycentre, origin or a body's name"},
};

std::unique_ptr<noether::ForceModel> make(const System& system, const Params& p) {
  return std::make_unique<Cannonball>(system, p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Force,
    "cannonball",
    "sunlight's pressure on a body taken as a sphere (area-to-mass ratio, reflectivity): spacecraft, dust, particles",
    params,
    std::size(params),
    nullptr,
    nullptr,
    &make};
