// radiation: the pressure of sunlight on a shaped body, facet by facet (docs/forces.md,
// "Radiation"; docs/equations.md §36) — the force that, through the body's asymmetry, is YORP on
// its spin and, on the secondary of a binary, BYORP on the mutual orbit.
//
// A facet of area A, outward normal n and centroid c (body frame, about the centre of mass) lit
// at incidence μ = n·u > 0, u the unit vector from the body's centre of mass towards the Sun, at
// distance d, with pressure P = P0 (d0/d)², takes
//
//   f = −P A μ [ (1 − ρs) u + (2 ρs μ + (2/3)(ρd + α)) n ],   α = 1 − ρs − ρd if thermal, else 0   (36.1)
//
// — all the light's momentum, the specular part's mirror recoil, and the Lambertian recoil of the
// diffusely reflected part and (thermal) of the absorbed part re-emitted at once (zero
// conductivity, Rubincam 2000). A flat facet is lit uniformly, so the force is exact per facet and
// its torque about the centre of mass is c × f. Not modelled: the body's shadows on itself and
// other bodies' shadows (eclipses), light reflected or emitted onto the body by its other facets
// or by other bodies, thermal lag.
#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/plugin.hpp>
#include <noether/prescribed_conic.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace {

using noether::Forces;
using noether::Mat3;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

double fraction(const Params& p, const char* key) {
  const double v = p.at(key).as_double();
  if (!(v >= 0.0 && v <= 1.0)) throw SceneError(p.at(key).here() + "radiation: '" + key + "' must be in [0, 1]");
  return v;
}

double positive(const Params& p, const char* key) {
  const double v = p.at(key).as_double();
  if (!(v > 0.0) || !std::isfinite(v)) throw SceneError(p.at(key).here() + "radiation: '" + key + "' must be positive");
  return v;
}

// A block of facets' share of the sums in (36.1)'s gathered form (evaluate), and the blocks of one
// evaluating thread.
struct Sums {
  double lit_area = 0.0;
  Vec3 lit_centroid = Vec3::Zero(), normal_push = Vec3::Zero(), moment_push = Vec3::Zero();
  Sums& operator+=(const Sums& o) {
    lit_area += o.lit_area;
    lit_centroid += o.lit_centroid;
    normal_push += o.normal_push;
    moment_push += o.moment_push;
    return *this;
  }
};
struct RadiationWorkspace final : noether::Workspace {
  std::vector<Sums> blocks;
};
constexpr std::size_t kBlock = 64;  // facets per block: Alpha's 9168 make 144, shared in chunks of 16

class Radiation final : public noether::ForceModel {
 public:
  Radiation(const System& system, const Params& p) {
    const std::string name = p.at("body").as_string();
    const int index = system.index_of(name);
    if (index < 0) throw SceneError(p.at("body").here() + "radiation: no body named '" + name + "'");
    body_ = index;
    const auto& b = system.body(static_cast<std::size_t>(index));
    if (!b.solid || !b.rigid)
      throw SceneError(p.at("body").here() + "radiation: body '" + name +
                       "' has no surface: give it a polyhedron or ellipsoid shape (radiation acts facet by facet)");
    rigid_ = system.rigid_index(static_cast<std::size_t>(index));
    specular_ = fraction(p, "specular");
    diffuse_ = fraction(p, "diffuse");
    if (specular_ + diffuse_ > 1.0)
      throw SceneError(p.at("diffuse").here() + "radiation: specular + diffuse reflect more than all the light (" +
                       std::to_string(specular_ + diffuse_) + " > 1)");
    const double absorbed = 1.0 - specular_ - diffuse_;
    lambertian_ = (2.0 / 3.0) * (diffuse_ + (p.at("thermal").as_bool() ? absorbed : 0.0));
    pressure_ = positive(p, "pressure");
    distance_ = positive(p, "distance");

    const bool ellipsoid = b.solid->kind == noether::Solid::Kind::Ellipsoid;
    if (noether::given(p, "tessellation") && !ellipsoid)
      throw SceneError(p.at("tessellation").here() + "radiation: 'tessellation' applies to ellipsoids; '" + name +
                       "' is a polyhedron and keeps its facets");
    const long level = p.at("tessellation").as_int();
    if (ellipsoid && (level < 0 || level > 7))
      throw SceneError(p.at("tessellation").here() + "radiation: tessellation must be in [0, 7]");
    const noether::Mesh mesh =
        ellipsoid ? noether::tessellated_ellipsoid(b.solid->semi_axes, static_cast<int>(level)) : b.solid->mesh;
    for (const auto& f : mesh.faces) {  // A, n, c and c × n in the body frame
      const Vec3 a = mesh.vertices.col(f[0]), bb = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
      const Vec3 area_normal = 0.5 * (bb - a).cross(c - a);
      const double area = area_normal.norm();
      if (!(area > 0.0)) continue;  // validated meshes have none; a degenerate facet takes no light
      facets_.push_back({area, area_normal / area, (a + bb + c) / 3.0, ((a + bb + c) / 3.0).cross(area_normal / area)});
    }

    if (p.has("sun")) {
      for (const char* key : {"position", "velocity", "mu", "epoch", "center"})
        if (noether::given(p, key))
          throw SceneError(p.at(key).here() + "radiation: give the Sun either as a scene body ('sun') or by its conic "
                                              "('position', 'velocity', 'mu'), not both");
      const std::string sun = p.at("sun").as_string();
      sun_ = system.index_of(sun);
      if (sun_ < 0 || sun_ == body_)
        throw SceneError(p.at("sun").here() + "radiation: 'sun' must name another body of the scene, not '" + sun + "'");
    } else {
      if (!p.has("position") || !p.has("velocity"))
        throw SceneError(p.here() + "radiation: give the Sun: 'sun', a scene body, or its conic 'position', "
                                    "'velocity' and 'mu' relative to 'center'");
      conic_.emplace(system, p, 0.0, "radiation");
    }
  }

  bool depends_on_momenta() const override { return false; }

  std::unique_ptr<noether::Workspace> make_workspace() const override {
    auto w = std::make_unique<RadiationWorkspace>();
    w->blocks.resize((facets_.size() + kBlock - 1) / kBlock);
    return w;
  }

  void evaluate(const State& s, Forces& out, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<RadiationWorkspace>(workspace, "radiation");
    out.set_zero();
    const Vec3 sun = sun_ >= 0 ? Vec3(s.x.col(sun_)) : conic_->position(s);
    const Vec3 to_sun = sun - Vec3(s.x.col(body_));
    const double d2 = to_sun.squaredNorm();
    if (!(d2 > 0.0)) throw noether::IntegrationError("radiation: the body reached the Sun", s.t);
    const Mat3& R = s.R[static_cast<std::size_t>(rigid_)];
    const Vec3 u = R.transpose() * (to_sun / std::sqrt(d2));  // body frame
    const double P = pressure_ * distance_ * distance_ / d2;
    // Σ over lit facets of (36.1), gathered as f = −P [(1 − ρs) u Σ A μ + Σ A μ (2 ρs μ + β) n] and
    // c × f = −P [(1 − ρs) (Σ A μ c) × u + Σ A μ (2 ρs μ + β) (c × n)], β = (2/3)(ρd + α): each
    // block of kBlock facets summed on some thread (`noether run --threads`), the blocks added in
    // order, so the result is the same bit for bit for any number of threads.
    noether::parallel_for_each(w.blocks.size(), noether::evaluation_threads(), [&](std::size_t b, int) {
      Sums sums;  // in registers: the facets cannot alias it
      const std::size_t end = std::min(facets_.size(), (b + 1) * kBlock);
      for (std::size_t i = b * kBlock; i < end; ++i) {
        const Facet& k = facets_[i];
        const double mu = k.normal.dot(u);
        if (mu <= 0.0) continue;  // in its own shade
        const double a_mu = k.area * mu, wt = a_mu * (2.0 * specular_ * mu + lambertian_);
        sums.lit_area += a_mu;
        sums.lit_centroid += a_mu * k.centroid;
        sums.normal_push += wt * k.normal;
        sums.moment_push += wt * k.moment;
      }
      w.blocks[b] = sums;
    });
    Sums total;
    for (const Sums& b : w.blocks) total += b;
    const Vec3 f = -P * ((1.0 - specular_) * total.lit_area * u + total.normal_push);
    const Vec3 M = -P * ((1.0 - specular_) * total.lit_centroid.cross(u) + total.moment_push);
    out.f.col(body_) = R * f;
    out.M.col(rigid_) = M;
  }

 private:
  Eigen::Index body_ = 0, rigid_ = 0, sun_ = -1;
  double specular_ = 0.0, diffuse_ = 0.0, lambertian_ = 0.0, pressure_ = 0.0, distance_ = 0.0;
  struct Facet {
    double area;
    Vec3 normal, centroid, moment;  // n, c and c × n
  };
  std::vector<Facet> facets_;
  std::optional<noether::PrescribedConic> conic_;
};

const noether::ParamDoc params[] = {
    {"body", "string", nullptr, "the lit body: a polyhedron, or an ellipsoid (tessellated)"},
    {"pressure", "number", nullptr,
     "the radiation pressure P0 = flux / c of the light at `distance` (SI: 4.5606e-6 N/m² at 1 au), in the scene's "
     "units of force per area"},
    {"distance", "number", nullptr, "the distance d0 of `pressure` (SI: 1.495978707e11 m, 1 au); P = P0 (d0/d)²"},
    {"specular", "number", "0", "the fraction ρs of the light reflected as by a mirror"},
    {"diffuse", "number", "0", "the fraction ρd of the light reflected diffusely (Lambert); the rest is absorbed"},
    {"thermal", "bool", "true",
     "re-emit the absorbed light at once as Lambertian thermal radiation (zero conductivity, Rubincam 2000) — "
     "the source of YORP; false: the absorbed light only pushes"},
    {"tessellation", "integer", "4",
     "an ellipsoid's facets: the icosahedron subdivided this many times (20·4^level facets, level ≤ 7)"},
    {"sun", "string", "(none)", "the light source as a body of the scene (then no conic)"},
    {"position", "list", "(none)", "or the Sun on a conic: its position at `epoch` relative to `center`"},
    {"velocity", "list", "(none)", "its velocity at `epoch` relative to `center`"},
    {"mu", "number", "(none)", "the conic's gravitational parameter (G M of the Sun, required with a conic)"},
    {"epoch", "number", "0", "the time of `position` and `velocity`"},
    {"center", "string", "barycentre", "what the conic is relative to: barycentre, origin or a body's name"},
};

std::unique_ptr<noether::ForceModel> make(const System& system, const Params& p) {
  return std::make_unique<Radiation>(system, p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Force,
    "radiation",
    "sunlight's pressure on a shaped body facet by facet — reflected, absorbed and re-emitted (YORP, BYORP)",
    params,
    std::size(params),
    nullptr,
    nullptr,
    &make};
