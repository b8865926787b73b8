#include <noether/error.hpp>
#include <noether/gravity_field.hpp>

#include <boost/math/special_functions/ellint_rd.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>

#include <cmath>
#include <map>

namespace noether {

PolyhedronField::PolyhedronField(const Mesh& mesh, double G_density)
    : Grho_(G_density), vertices_(mesh.vertices) {
  // Outward unit normal of every face, and the faces on either side of every edge.
  std::vector<Vec3> normal;
  std::map<std::pair<int, int>, int> face_of_directed_edge;
  for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
    const auto& f = mesh.faces[k];
    const Vec3 a = mesh.vertices.col(f[0]), b = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
    const Vec3 n = (b - a).cross(c - a).normalized();
    normal.push_back(n);
    faces_.push_back({f, n * n.transpose()});
    for (int e = 0; e < 3; ++e)
      face_of_directed_edge[{f[static_cast<std::size_t>(e)], f[static_cast<std::size_t>((e + 1) % 3)]}] =
          static_cast<int>(k);
  }
  for (const auto& [edge, fa] : face_of_directed_edge) {
    if (edge.first > edge.second) continue;  // each undirected edge once
    const auto other = face_of_directed_edge.find({edge.second, edge.first});
    if (other == face_of_directed_edge.end())
      throw SceneError(mesh.source + ": open edge; the polyhedron field needs a closed mesh");
    const int fb = other->second;
    const Vec3 p = mesh.vertices.col(edge.first), q = mesh.vertices.col(edge.second);
    const Vec3 t = (q - p).normalized();  // along the edge as face A traverses it
    const Vec3 nA = normal[static_cast<std::size_t>(fa)], nB = normal[static_cast<std::size_t>(fb)];
    // Edge normals in each face's plane, pointing out of the face: t × n for face A, which
    // traverses p → q; face B traverses q → p, so its edge normal is (−t) × n_B.
    const Vec3 nAe = t.cross(nA), nBe = (-t).cross(nB);
    edges_.push_back({edge.first, edge.second, (q - p).norm(), nA * nAe.transpose() + nB * nBe.transpose()});
  }
}

FieldValue PolyhedronField::operator()(const Vec3& r, bool with_gradient) const {
  // Werner & Scheeres 1997 (8), (15): r_i = vertex − field point.
  const Eigen::Index nv = vertices_.cols();
  thread_local Eigen::Matrix3Xd rv;
  thread_local Eigen::VectorXd len;
  rv = vertices_.colwise() - r;
  len = rv.colwise().norm();
  (void)nv;
  double edge_sum = 0.0, face_sum = 0.0, omega_sum = 0.0;
  Vec3 g_edge = Vec3::Zero(), g_face = Vec3::Zero();
  Mat3 dg_edge = Mat3::Zero(), dg_face = Mat3::Zero();
  for (const Edge& e : edges_) {
    const double ri = len(e.i), rj = len(e.j);
    const double Le = std::log((ri + rj + e.length) / (ri + rj - e.length));
    const Vec3 Er = e.E * rv.col(e.i);
    edge_sum += rv.col(e.i).dot(Er) * Le;
    g_edge += Er * Le;
    if (with_gradient) dg_edge += e.E * Le;
  }
  for (const Face& f : faces_) {
    const Vec3 r1 = rv.col(f.v[0]), r2 = rv.col(f.v[1]), r3 = rv.col(f.v[2]);
    const double l1 = len(f.v[0]), l2 = len(f.v[1]), l3 = len(f.v[2]);
    const double omega = 2.0 * std::atan2(r1.dot(r2.cross(r3)),
                                          l1 * l2 * l3 + l1 * r2.dot(r3) + l2 * r3.dot(r1) + l3 * r1.dot(r2));
    const Vec3 Fr = f.F * r1;
    face_sum += r1.dot(Fr) * omega;
    g_face += Fr * omega;
    omega_sum += omega;
    if (with_gradient) dg_face += f.F * omega;
  }
  FieldValue v;
  v.phi = -0.5 * Grho_ * (edge_sum - face_sum);
  v.g = Grho_ * (-g_edge + g_face);
  if (with_gradient) v.dg = Grho_ * (dg_edge - dg_face);
  v.inside = std::abs(omega_sum) > 2.0 * M_PI;  // 4π inside, 0 outside
  return v;
}

EllipsoidField::EllipsoidField(const Vec3& semi_axes, double G_density)
    : a2_(semi_axes.cwiseAbs2()), k_(M_PI * G_density * semi_axes.prod()) {}

FieldValue EllipsoidField::operator()(const Vec3& r, bool with_gradient) const {
  const Vec3 r2 = r.cwiseAbs2();
  FieldValue v;
  double lambda = 0.0;
  if ((r2.array() / a2_.array()).sum() <= 1.0) {
    v.inside = true;
  } else {
    // λ: the largest root of Σ x_i²/(a_i² + λ) = 1. The left side is convex and
    // decreasing, so Newton from below the root increases monotonically to it.
    lambda = std::max(0.0, r2.sum() - a2_.maxCoeff());
    for (int it = 0; it < 200; ++it) {
      const Eigen::Array3d d = a2_.array() + lambda;
      const double f = (r2.array() / d).sum() - 1.0;
      const double df = -(r2.array() / (d * d)).sum();
      const double step = -f / df;
      lambda += step;
      if (std::abs(step) <= 1e-16 * std::max(lambda, a2_.minCoeff())) break;
    }
  }
  using boost::math::ellint_rd;
  using boost::math::ellint_rf;
  const Eigen::Array3d d = a2_.array() + lambda;
  const double I0 = 2.0 * ellint_rf(d[0], d[1], d[2]);
  const Vec3 I(2.0 / 3.0 * ellint_rd(d[1], d[2], d[0]), 2.0 / 3.0 * ellint_rd(d[0], d[2], d[1]),
               2.0 / 3.0 * ellint_rd(d[0], d[1], d[2]));
  v.phi = -k_ * (I0 - r2.dot(I));
  v.g = -2.0 * k_ * r.cwiseProduct(I);
  if (with_gradient) {
    // (26.1): ∂g/∂r = −2k [diag(I_i) − 2 q qᵀ / (Δ Σ_k x_k²/d_k²)], q_i = x_i/d_i, Δ = √(d₀d₁d₂):
    // I_i(λ) moves with λ, and ∂λ/∂x_j = 2 q_j / Σ_k x_k²/d_k² (outside; λ = const inside).
    v.dg = I.asDiagonal();
    if (!v.inside) {
      const Vec3 q = (r.array() / d).matrix();
      v.dg -= (2.0 / (std::sqrt(d.prod()) * q.squaredNorm())) * q * q.transpose();
    }
    v.dg *= -2.0 * k_;
  }
  return v;
}

void gauss_legendre01(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  nodes.resize(static_cast<std::size_t>(n));
  weights.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    nodes[static_cast<std::size_t>(i)] = 0.5 * (1.0 - x);
    weights[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - x * x) * dp * dp);
  }
}

SurfaceRule polyhedron_surface_rule(const Mesh& mesh, int n) {
  std::vector<double> s, w;
  gauss_legendre01(n, s, w);
  SurfaceRule rule;
  rule.points.reserve(mesh.faces.size() * static_cast<std::size_t>(n * n));
  rule.areas.reserve(rule.points.capacity());
  for (const auto& f : mesh.faces) {
    const Vec3 a = mesh.vertices.col(f[0]), b = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
    const Vec3 twice_area = (b - a).cross(c - a);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double u = s[static_cast<std::size_t>(i)], v = s[static_cast<std::size_t>(j)] * (1.0 - u);
        rule.points.push_back(a + u * (b - a) + v * (c - a));
        rule.areas.push_back(twice_area * (w[static_cast<std::size_t>(i)] * w[static_cast<std::size_t>(j)] * (1.0 - u)));
      }
  }
  return rule;
}

SurfaceRule ellipsoid_surface_rule(const Vec3& ax, int n_theta, int n_phi) {
  std::vector<double> s, w;
  gauss_legendre01(n_theta, s, w);
  SurfaceRule rule;
  for (int i = 0; i < n_theta; ++i) {
    const double u = 2.0 * s[static_cast<std::size_t>(i)] - 1.0, wu = 2.0 * w[static_cast<std::size_t>(i)];
    const double st = std::sqrt(std::max(0.0, 1.0 - u * u));
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * M_PI * j / n_phi, cp = std::cos(phi), sp = std::sin(phi);
      rule.points.emplace_back(ax.x() * st * cp, ax.y() * st * sp, ax.z() * u);
      rule.areas.push_back(Vec3(ax.y() * ax.z() * st * cp, ax.x() * ax.z() * st * sp, ax.x() * ax.y() * u) *
                           (wu * 2.0 * M_PI / n_phi));
    }
  }
  return rule;
}

}  // namespace noether
