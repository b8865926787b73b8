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
// its torque about the centre of mass is c × f.
//
// Shadows (36.5): a lit facet takes no light when the ray from its centroid towards the Sun meets
// another body (`eclipses`, on by default: a shaped body by its shape, any other with a radius as
// that sphere) or, with `self_shadowing`, the body's own surface — the facets seen along the light,
// binned on a grid over the plane across it (noether/occlusion_map.hpp, made for each evaluation's
// Sun direction). The Sun is a point: no penumbra, and a facet is lit or shaded whole, by its
// centroid. Not modelled: light reflected or emitted onto the body by its other facets or by other
// bodies, thermal lag.
#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/occlusion_map.hpp>
#include <noether/plugin.hpp>
#include <noether/light_source.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
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
// A body that may shade the lit one (36.5): its shape — a polyhedron's facets, an ellipsoid's
// semi-axes, or a sphere — in its own frame, and the radius of a sphere about its centre that holds it.
struct Occluder {
  Eigen::Index body = 0;
  int rigid = -1;                  // its attitude's index; −1: a sphere, no attitude
  double radius = 0.0;
  Vec3 semi_axes = Vec3::Zero();   // an ellipsoid's (zero: not one)
  std::vector<noether::Mesh> mesh;  // a polyhedron's (one surface; empty: not one)
};

// An occluder placed for one evaluation: a facet at c (the lit body's frame) casts its ray from
// origin + Q c along d, in the occluder's frame; a polyhedron's facets seen along d.
struct PlacedOccluder {
  const Occluder* occluder;
  Vec3 origin, d;
  Mat3 Q;
  std::optional<noether::OcclusionMap> facets;

  // Whether the ray o + t d (t > 0; the occluder's frame) meets the body.
  bool shades(const Vec3& o) const {
    const double oo = o.squaredNorm(), od = o.dot(d), r = occluder->radius;
    if (oo > r * r && (od >= 0.0 || oo - od * od > r * r)) return false;  // misses the bounding sphere
    if (facets) return facets->blocked(o);
    if (occluder->semi_axes.isZero()) return true;  // the sphere itself
    const Vec3 p = o.cwiseQuotient(occluder->semi_axes), q = d.cwiseQuotient(occluder->semi_axes);
    const double A = q.squaredNorm(), B = p.dot(q), C = p.squaredNorm() - 1.0;
    const double disc = B * B - A * C;
    return disc >= 0.0 && -B + std::sqrt(disc) > 0.0;  // the farther root ahead of the facet
  }
};

struct RadiationWorkspace final : noether::Workspace {
  std::vector<Sums> blocks;
  std::vector<PlacedOccluder> placed;
  std::optional<noether::OcclusionMap> self;  // the body's own facets along this evaluation's light
};
constexpr std::size_t kBlock = 64;  // facets per block: Alpha's 9168 make 144, shared in chunks of 16

class Radiation final : public noether::ForceModel {
 public:
  Radiation(const System& system, const Params& p) : light_(system, p, "radiation") {
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
    for (std::size_t k = 0; k < mesh.faces.size(); ++k) {  // A, n, c and c × n in the body frame
      const auto& f = mesh.faces[k];
      const Vec3 a = mesh.vertices.col(f[0]), bb = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
      const Vec3 area_normal = 0.5 * (bb - a).cross(c - a);
      const double area = area_normal.norm();
      if (!(area > 0.0)) continue;  // validated meshes have none; a degenerate facet takes no light
      facets_.push_back({area, area_normal / area, (a + bb + c) / 3.0, ((a + bb + c) / 3.0).cross(area_normal / area),
                         static_cast<int>(k)});
    }
    radius_ = b.solid->radius;
    if (p.at("self_shadowing").as_bool()) own_surface_ = {mesh};

    sun_ = light_.body();
    if (sun_ == body_)
      throw SceneError(p.at("sun").here() + "radiation: 'sun' must name another body of the scene, not the lit '" +
                       name + "'");

    if (p.at("eclipses").as_bool()) {  // every other body that can stand in the light
      for (std::size_t j = 0; j < system.size(); ++j) {
        const auto& other = system.body(j);
        const auto index = static_cast<Eigen::Index>(j);
        if (index == body_ || index == sun_) continue;
        Occluder o;
        o.body = index;
        o.radius = other.radius;
        if (other.solid && other.rigid) {
          o.rigid = system.rigid_index(j);
          if (other.solid->kind == noether::Solid::Kind::Ellipsoid)
            o.semi_axes = other.solid->semi_axes;
          else
            o.mesh = {other.solid->mesh};
        } else if (!(other.radius > 0.0)) {
          continue;  // a point without a size casts no shadow
        }
        occluders_.push_back(std::move(o));
      }
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
    const Vec3 to_sun = light_.position(s) - Vec3(s.x.col(body_));
    const double d2 = to_sun.squaredNorm();
    if (!(d2 > 0.0)) throw noether::IntegrationError("radiation: the body reached the Sun", s.t);
    const Mat3& R = s.R[static_cast<std::size_t>(rigid_)];
    const Vec3 u = R.transpose() * (to_sun / std::sqrt(d2));  // body frame
    const double P = pressure_ * distance_ * distance_ / d2;
    place_occluders(s, to_sun / std::sqrt(d2), std::sqrt(d2), w.placed);
    if (!own_surface_.empty()) w.self.emplace(own_surface_, u);
    const noether::OcclusionMap* self = w.self ? &*w.self : nullptr;
    // Σ over lit facets of (36.1), gathered as f = −P [(1 − ρs) u Σ A μ + Σ A μ (2 ρs μ + β) n] and
    // c × f = −P [(1 − ρs) (Σ A μ c) × u + Σ A μ (2 ρs μ + β) (c × n)], β = (2/3)(ρd + α): each
    // block of kBlock facets summed on some thread (`noether run --threads`), the blocks added in
    // order, so the result is the same bit for bit for any number of threads.
    // The block's loop is made twice, with and without the shadows' tests, so that a body in full
    // light (no occluder near, no self-shadowing) pays nothing for them.
    auto sum_block = [&](auto shadows, std::size_t b) {
      Sums sums;  // in registers: the facets cannot alias it
      const std::size_t end = std::min(facets_.size(), (b + 1) * kBlock);
      for (std::size_t i = b * kBlock; i < end; ++i) {
        const Facet& k = facets_[i];
        const double mu = k.normal.dot(u);
        if (mu <= 0.0) continue;  // in its own shade
        if constexpr (decltype(shadows)::value) {
          if (self && self->blocked(k.centroid, static_cast<std::size_t>(k.face))) continue;  // its own shadow (36.5)
          if (in_eclipse(k.centroid, w.placed)) continue;  // another body's (36.5)
        }
        const double a_mu = k.area * mu, wt = a_mu * (2.0 * specular_ * mu + lambertian_);
        sums.lit_area += a_mu;
        sums.lit_centroid += a_mu * k.centroid;
        sums.normal_push += wt * k.normal;
        sums.moment_push += wt * k.moment;
      }
      w.blocks[b] = sums;
    };
    const bool shadows = self || !w.placed.empty();
    noether::parallel_for_each(w.blocks.size(), noether::evaluation_threads(), [&](std::size_t b, int) {
      if (shadows)
        sum_block(std::true_type{}, b);
      else
        sum_block(std::false_type{}, b);
    });
    Sums total;
    for (const Sums& b : w.blocks) total += b;
    const Vec3 f = -P * ((1.0 - specular_) * total.lit_area * u + total.normal_push);
    const Vec3 M = -P * ((1.0 - specular_) * total.lit_centroid.cross(u) + total.moment_push);
    out.f.col(body_) = R * f;
    out.M.col(rigid_) = M;
  }

 private:
  // The occluders whose bounding spheres' shadows (along the light, towards the lit body) meet the
  // lit body's bounding sphere, placed for the facets' rays (36.5); none in most configurations.
  void place_occluders(const State& s, const Vec3& towards_sun, double sun_distance,
                       std::vector<PlacedOccluder>& placed) const {
    placed.clear();
    const Vec3 x = s.x.col(body_);
    const Mat3& R = s.R[static_cast<std::size_t>(rigid_)];
    for (const Occluder& o : occluders_) {
      const Vec3 w = Vec3(s.x.col(o.body)) - x;
      const double along = w.dot(towards_sun), reach = o.radius + radius_;
      if (along < -reach || along - o.radius > sun_distance) continue;  // behind the lit body, or past the Sun
      if ((w - along * towards_sun).squaredNorm() > reach * reach) continue;  // beside the light's path
      if (o.rigid < 0) {
        placed.push_back({&o, -w, towards_sun, R, std::nullopt});
      } else {
        const Mat3 Rt = s.R[static_cast<std::size_t>(o.rigid)].transpose();
        placed.push_back({&o, Rt * (-w), Rt * towards_sun, Rt * R, std::nullopt});
        if (!o.mesh.empty()) placed.back().facets.emplace(o.mesh, placed.back().d);
      }
    }
  }
  static bool in_eclipse(const Vec3& centroid, const std::vector<PlacedOccluder>& placed) {
    for (const PlacedOccluder& p : placed)
      if (p.shades(p.origin + p.Q * centroid)) return true;
    return false;
  }

  Eigen::Index body_ = 0, rigid_ = 0, sun_ = -1;
  double specular_ = 0.0, diffuse_ = 0.0, lambertian_ = 0.0, pressure_ = 0.0, distance_ = 0.0, radius_ = 0.0;
  struct Facet {
    double area;
    Vec3 normal, centroid, moment;  // n, c and c × n
    int face;                       // its face in the mesh
  };
  std::vector<Facet> facets_;
  std::vector<noether::Mesh> own_surface_;  // the facets' mesh, with self_shadowing (else empty)
  std::vector<Occluder> occluders_;
  noether::LightSource light_;
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
    {"eclipses", "bool", "true",
     "other bodies' shadows: a facet whose ray towards the Sun meets another body takes no light (a shaped body by "
     "its shape, any other with a radius as that sphere; the Sun a point: no penumbra)"},
    {"self_shadowing", "bool", "false",
     "the body's shadows on itself: every lit facet tested against its own facets seen along the light (an occlusion "
     "map made for each evaluation; its cost in docs/forces.md) — a concave shape's shade"},
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
