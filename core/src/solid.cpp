#include <noether/error.hpp>
#include <noether/solid.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

namespace noether {

namespace {

Mat3 inertia_from_second_moment(const Mat3& S) { return S.trace() * Mat3::Identity() - S; }

void check_density(double density, const std::string& what) {
  if (!std::isfinite(density) || density <= 0.0) {
    std::ostringstream msg;
    msg << what << ": density must be positive, not " << density;
    throw SceneError(msg.str());
  }
}

// The principal axes as columns, permuted and signed to lie closest to the identity.
Mat3 principal_axes_near_identity(const Mat3& J) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
  const Mat3 V = eig.eigenvectors();
  std::array<int, 3> perm{0, 1, 2}, best = perm;
  double best_score = -1.0;
  do {
    double score = 0.0;
    for (int i = 0; i < 3; ++i) score += std::abs(V(i, perm[static_cast<std::size_t>(i)]));
    if (score > best_score) best_score = score, best = perm;
  } while (std::next_permutation(perm.begin(), perm.end()));
  Mat3 Q;
  for (int i = 0; i < 3; ++i) {
    Q.col(i) = V.col(best[static_cast<std::size_t>(i)]);
    if (Q(i, i) < 0.0) Q.col(i) *= -1.0;
  }
  if (Q.determinant() < 0.0) {  // keep a rotation: flip the axis least aligned with its own
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(Q(i, i)) < std::abs(Q(k, k))) k = i;
    Q.col(k) *= -1.0;
  }
  return Q;
}

}  // namespace

InertiaIntegrals Solid::integrals(int order) const {
  if (kind == Kind::Ellipsoid) return ellipsoid_integrals(mass, semi_axes, order);
  return polyhedron_integrals(mesh, density, order);
}

std::string Solid::describe() const {
  std::ostringstream s;
  if (kind == Kind::Ellipsoid)
    s << "ellipsoid " << semi_axes.x() << " × " << semi_axes.y() << " × " << semi_axes.z();
  else
    s << "polyhedron " << mesh.source << " (" << mesh.vertices.cols() << " vertices, "
      << mesh.faces.size() << " faces)";
  return s.str();
}

std::shared_ptr<const Solid> make_ellipsoid(const Vec3& semi_axes, double density) {
  check_density(density, "ellipsoid");
  if (!semi_axes.allFinite() || semi_axes.minCoeff() <= 0.0) {
    std::ostringstream msg;
    msg << "ellipsoid semi-axes must be positive, not [" << semi_axes.transpose() << "]";
    throw SceneError(msg.str());
  }
  auto s = std::make_shared<Solid>();
  s->kind = Solid::Kind::Ellipsoid;
  s->density = density;
  s->semi_axes = semi_axes;
  s->volume = 4.0 / 3.0 * M_PI * semi_axes.prod();
  s->mass = density * s->volume;
  const Vec3 sq = semi_axes.cwiseAbs2();
  s->inertia = (s->mass / 5.0 * Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y())).asDiagonal();
  s->radius = semi_axes.maxCoeff();
  return s;
}

std::shared_ptr<const Solid> make_polyhedron(Mesh mesh, double density, bool principal_axes) {
  check_density(density, mesh.source);
  validate_mesh(mesh);
  auto s = std::make_shared<Solid>();
  s->kind = Solid::Kind::Polyhedron;
  s->density = density;
  // Mass properties about the file's origin, then about the centre of mass.
  const InertiaIntegrals raw = polyhedron_integrals(mesh, density, 2);
  s->mass = raw.mass();
  s->volume = s->mass / density;
  const Vec3 c = Vec3(raw(1, 0, 0), raw(0, 1, 0), raw(0, 0, 1)) / s->mass;
  const Mat3 S = raw.second_moment() - s->mass * c * c.transpose();
  Mat3 J = inertia_from_second_moment(S);
  Mat3 Q = Mat3::Identity();
  const double products = std::max({std::abs(J(0, 1)), std::abs(J(0, 2)), std::abs(J(1, 2))});
  if (principal_axes && products > 1e-12 * J.diagonal().maxCoeff()) {
    Q = principal_axes_near_identity(J);
    J = Q.transpose() * J * Q;
    J = 0.5 * (J + J.transpose()).eval();
    J(0, 1) = J(1, 0) = J(0, 2) = J(2, 0) = J(1, 2) = J(2, 1) = 0.0;  // principal by construction
  }
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i) {
    mesh.vertices.col(i) = Q.transpose() * (mesh.vertices.col(i) - c);
    s->radius = std::max(s->radius, mesh.vertices.col(i).norm());
  }
  s->inertia = J;
  s->offset = c;
  s->rotation = Q;
  s->mesh = std::move(mesh);
  return s;
}

std::shared_ptr<const Solid> stretched_polyhedron(const Solid& polyhedron, const Vec3& scale) {
  if (polyhedron.kind != Solid::Kind::Polyhedron) throw Error("stretched_polyhedron: not a polyhedron");
  if (!scale.allFinite() || scale.minCoeff() <= 0.0)
    throw SceneError(polyhedron.mesh.source + ": the scale factors must be positive");
  Mesh mesh = polyhedron.mesh;  // body frame: centred, on the body axes
  mesh.vertices = scale.asDiagonal() * mesh.vertices;
  // Stretching along the body axes keeps the centre of mass at the origin and the products of
  // inertia zero where they were: the axes are kept (principal_axes false), not searched again.
  auto s = std::const_pointer_cast<Solid>(make_polyhedron(std::move(mesh), polyhedron.density, false));
  s->offset = polyhedron.offset + polyhedron.rotation * s->offset.cwiseQuotient(scale.cwiseProduct(polyhedron.stretch));
  s->rotation = polyhedron.rotation;
  s->stretch = polyhedron.stretch.cwiseProduct(scale);
  return s;
}

}  // namespace noether
