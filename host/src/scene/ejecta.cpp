// Ejecta thrown from a body's surface (ejecta.hpp; docs/equations.md §39).
#include <noether/ejecta.hpp>
#include <noether/error.hpp>
#include <noether/solid.hpp>

#include <noether/orthonormal_basis.hpp>
#include "scene/portable_random.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace noether {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// The distance t > 0 at which the ray t u from the origin crosses triangle abc (Möller & Trumbore
// 1997), or −1 when it misses. The edges count as the triangle's, so that a ray through an edge
// or a vertex hits a face on either side.
double ray_hits_triangle(const Vec3& u, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = u.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return -1.0;  // the ray lies in the face's plane
  const Vec3 s = -a;
  const double beta = s.dot(p) / det;
  const Vec3 q = s.cross(e1);
  const double gamma = u.dot(q) / det;
  constexpr double slack = 1e-12;
  if (beta < -slack || gamma < -slack || beta + gamma > 1.0 + slack) return -1.0;
  return e2.dot(q) / det;
}

}  // namespace

SurfacePoint surface_point_along(const Body& body, const Vec3& u) {
  SurfacePoint out;
  if (body.solid && body.solid->kind == Solid::Kind::Ellipsoid) {
    // x = t u with Σ x_i²/a_i² = 1; the normal is ∇(Σ x_i²/a_i²) ∝ x_i/a_i².
    const Vec3 a2 = body.solid->semi_axes.cwiseAbs2();
    out.point = u / std::sqrt((u.cwiseAbs2().array() / a2.array()).sum());
    out.normal = (out.point.array() / a2.array()).matrix().normalized();
  } else if (body.solid) {
    // The outermost crossing: a shape that is not star-shaped about its centre is crossed more
    // than once, and particles leave from the outside.
    const Mesh& mesh = body.solid->mesh;
    double best = -1.0;
    for (const auto& f : mesh.faces) {
      const Vec3 a = mesh.vertices.col(f[0]), b = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
      const double t = ray_hits_triangle(u, a, b, c);
      if (t > best) {
        best = t;
        out.normal = (b - a).cross(c - a).normalized();
      }
    }
    if (!(best > 0.0)) throw SceneError("body '" + body.name + "': no face of its mesh crosses the site's direction");
    out.point = best * u;
  } else if (body.radius > 0.0) {
    out.point = body.radius * u;
    out.normal = u;
  } else {
    throw SceneError("body '" + body.name +
                     "' has no surface to throw ejecta from: give it a shape (ellipsoid, polyhedron) or a radius");
  }
  return out;
}

double ejecta_speed(const EjectaSettings& e, double q) {
  // (39.1) inverted: the fraction faster than v is 1 − q.
  const double lo = std::pow(e.speed_min, -e.exponent), hi = std::pow(e.speed_max, -e.exponent);
  return std::pow(lo - q * (lo - hi), -1.0 / e.exponent);
}

void launch_ejecta(const EjectaSettings& e, const System& system, const State& state, std::vector<Vec3>& position,
                   std::vector<Vec3>& velocity) {
  const Body& body = system.body(e.body);
  const double lat = e.latitude * kDegree, lon = e.longitude * kDegree;
  const Vec3 u(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
  const SurfacePoint site = surface_point_along(body, u);
  const double radius = body.solid ? body.solid->radius : body.radius;
  const Vec3 s = site.point + (e.height > 0.0 ? e.height : 1e-6 * radius) * site.normal;
  Vec3 e1, e2;
  complete_basis(site.normal, e1, e2);
  const auto b = static_cast<Eigen::Index>(e.body);
  const int k = system.rigid_index(e.body);
  const Mat3 R = k >= 0 ? state.R[static_cast<std::size_t>(k)] : Mat3::Identity();
  const Vec3 Omega = k >= 0 ? Vec3(body.inertia_inverse * state.Pi.col(k)) : Vec3::Zero();
  const Vec3 x_b = state.x.col(b), v_b = state.p.col(b) / body.mass;
  const double sc = std::cos(e.cone * kDegree), ss = std::sin(e.cone * kDegree);
  for (std::size_t i = 0; i < e.count; ++i) {
    // (39.2): draws from (seed, i) — stream 0 the speed's quantile, 1 the azimuth.
    const double v = ejecta_speed(e, uniform01(e.seed, i, 0));
    const double phi = 2.0 * std::numbers::pi * uniform01(e.seed, i, 1);
    const Vec3 d = sc * site.normal + ss * (std::cos(phi) * e1 + std::sin(phi) * e2);
    position.push_back(x_b + R * s);
    velocity.push_back(v_b + R * (Omega.cross(s) + v * d));
  }
}

}  // namespace noether
