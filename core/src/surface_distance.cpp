// Distances to a solid's surface (surface_distance.hpp; docs/equations.md §16).
#include <noether/surface_distance.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace noether {

namespace {

// The point of triangle abc nearest to p, by the Voronoi regions of its vertices, edges and
// face (Ericson 2005, Real-Time Collision Detection, §5.1.5).
Vec3 nearest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

double polyhedron_gap(const Mesh& mesh, const Vec3& p) {
  double nearest = std::numeric_limits<double>::infinity(), winding = 0.0;
  for (const auto& f : mesh.faces) {
    const Vec3 a = mesh.vertices.col(f[0]), b = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
    nearest = std::min(nearest, (nearest_on_triangle(p, a, b, c) - p).squaredNorm());
    winding += triangle_solid_angle(p, a, b, c);
  }
  const double distance = std::sqrt(nearest);
  return std::abs(winding) > 2.0 * std::numbers::pi ? -distance : distance;  // 4π inside, 0 outside
}

// Outside the ellipsoid Σ (x_i/a_i)² = 1: the distance to its nearest point x_i = a_i² y_i /
// (t + a_i²), t > 0 the root of Σ (a_i y_i / (t + a_i²))² = 1 (Eberly 2013, "Distance from a
// point to an ellipse, an ellipsoid, or a hyperellipsoid"), by bisection: eq. 16.6.
double ellipsoid_outside_distance(const Vec3& a, const Vec3& y) {
  auto F = [&](double t) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i) s += std::pow(a[i] * y[i] / (t + a[i] * a[i]), 2);
    return s - 1.0;
  };
  double lo = 0.0, hi = a.maxCoeff() * y.norm();
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (F(mid) > 0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  Vec3 x;
  for (int i = 0; i < 3; ++i) x[i] = a[i] * a[i] * y[i] / (t + a[i] * a[i]);
  return (x - y).norm();
}

double ellipsoid_gap(const Vec3& axes, const Vec3& p) {
  const double rho = p.cwiseQuotient(axes).norm();
  if (rho > 1.0) return ellipsoid_outside_distance(axes, p);
  if (rho == 0.0) return -axes.minCoeff();
  return -p.norm() * (1.0 / rho - 1.0);  // the radial distance to the surface, inside
}

}  // namespace

double surface_gap(const Solid& solid, const Vec3& p) {
  return solid.kind == Solid::Kind::Ellipsoid ? ellipsoid_gap(solid.semi_axes, p) : polyhedron_gap(solid.mesh, p);
}

Eigen::Matrix3Xd surface_samples(const Solid& solid, int n) {
  if (solid.kind == Solid::Kind::Polyhedron) return solid.mesh.vertices;
  Eigen::Matrix3Xd out(3, n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n, r = std::sqrt(1.0 - z * z), phi = golden * k;
    out.col(k) = Vec3(r * std::cos(phi), r * std::sin(phi), z).cwiseProduct(solid.semi_axes);
  }
  return out;
}

}  // namespace noether
