// One body's gravity field on a massless particle (body_field.hpp; docs/equations.md §38).
#include <noether/body_field.hpp>
#include <noether/error.hpp>
#include <noether/stokes_coefficients.hpp>
#include <noether/surface_distance.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace noether {

namespace {

// n points of the Fibonacci lattice on the unit sphere (nearly even, no pole clusters).
Eigen::Matrix3Xd fibonacci_sphere(int n) {
  Eigen::Matrix3Xd u(3, n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n, s = std::sqrt(1.0 - z * z), phi = golden * k;
    u.col(k) = Vec3(s * std::cos(phi), s * std::sin(phi), z);
  }
  return u;
}

constexpr int kLadderPoints = 200;     // points on each sphere of the ladder (38.2)
constexpr double kLadderTop = 32.0;    // the ladder's largest radius, in bounding radii
constexpr double kLadderRatio = 1.05;  // between its rungs
constexpr int kLadderConfirm = 3;      // rungs beyond the first that passes, which must pass too

}  // namespace

BodyField::BodyField(const Body& body, double G, const BodyFieldOptions& options) {
  if (options.degree < 0 || options.degree > multi_index::kMaxDegree)
    throw SceneError("the particles' field degree must be 0.." + std::to_string(multi_index::kMaxDegree) + ", not " +
                     std::to_string(options.degree));
  if (!(options.tolerance > 0.0 && options.tolerance < 1.0))
    throw SceneError("the particles' field tolerance must be in (0, 1)");
  gm_ = G * body.mass;
  solid_ = body.solid;
  sphere_radius_ = body.radius;
  if (solid_ && solid_->kind == Solid::Kind::Ellipsoid) {  // exact everywhere: MacMillan's closed form
    ellipsoid_.emplace(solid_->semi_axes, G * solid_->density);
    series_radius_ = std::numeric_limits<double>::infinity();
    return;
  }
  if (!solid_ && !body.field && !body.rigid) return;  // a point mass: G M / r
  // The series (32.1) about the centre of mass, at the body's radius.
  const double R = body.radius > 0.0 ? body.radius : 1.0;
  StokesCoefficients cs;
  if (solid_) {
    degree_ = options.degree;
    cs = stokes_from_integrals(solid_->integrals(degree_), solid_->radius, degree_, false);
  } else if (body.field) {
    degree_ = std::min(options.degree, body.field->degree);
    cs = truncated(*body.field, degree_, false);
  } else {  // an inertia alone: MacCullagh's degree 2
    degree_ = 2;
    cs = stokes_from_integrals(integrals_from_inertia(body.mass, body.inertia), R, 2, false);
  }
  series_.emplace(cs, G);
  if (!solid_) return;  // no exact field to fall back on: the series everywhere (0)
  polyhedron_.emplace(solid_->mesh, G * solid_->density);
  // (38.2): up the ladder of spheres from the bounding one, to the first radius from which the
  // series meets the tolerance at every point of this sphere and of the next kLadderConfirm ones
  // (farther out the exact field's own round-off grows — its terms cancel as 1/r² against r — so
  // the ladder is not walked down from afar).
  const Eigen::Matrix3Xd u = fibonacci_sphere(kLadderPoints);
  series_radius_ = std::numeric_limits<double>::infinity();
  int passed = 0;
  for (double r = solid_->radius * kLadderRatio; r < kLadderTop * solid_->radius; r *= kLadderRatio) {
    double worst = 0.0;
    for (int k = 0; k < kLadderPoints && worst <= options.tolerance; ++k) {
      const Vec3 x = r * u.col(k);
      const Vec3 exact = (*polyhedron_)(x).g;
      worst = std::max(worst, (series_->operator()(x).acceleration - exact).norm() / exact.norm());
    }
    if (worst > options.tolerance) {
      passed = 0;
      series_radius_ = std::numeric_limits<double>::infinity();
      continue;
    }
    if (passed++ == 0) series_radius_ = r;
    if (passed > kLadderConfirm) break;
  }
  if (passed <= kLadderConfirm) series_radius_ = std::numeric_limits<double>::infinity();
}

BodyField::Value BodyField::operator()(const Vec3& r) {
  Value out;
  if (ellipsoid_) {
    const FieldValue f = (*ellipsoid_)(r);
    out.acceleration = f.g;
    out.potential = f.phi;
  } else if (polyhedron_ && !(r.squaredNorm() >= series_radius_ * series_radius_)) {
    const FieldValue f = (*polyhedron_)(r);
    out.acceleration = f.g;
    out.potential = f.phi;
  } else if (series_) {
    const auto v = (*series_)(r);
    out.acceleration = v.acceleration;
    out.potential = -v.potential;
  } else {  // a point mass
    const double r2 = r.squaredNorm(), inv = 1.0 / std::sqrt(r2);
    out.potential = -gm_ * inv;
    out.acceleration = -gm_ * inv * inv * inv * r;
  }
  return out;
}

double BodyField::surface_gap(const Vec3& r) const {
  if (solid_) return noether::surface_gap(*solid_, r);
  return r.norm() - sphere_radius_;
}

std::string BodyField::describe() const {
  std::ostringstream s;
  s.precision(4);
  if (ellipsoid_) {
    s << "exact (" << solid_->describe() << ")";
  } else if (polyhedron_) {
    if (std::isinf(series_radius_))
      s << "exact (" << solid_->describe() << "; the series of degree " << degree_ << " nowhere within tolerance)";
    else
      s << "exact within r = " << series_radius_ << " (" << solid_->describe() << "), beyond it the series of degree "
        << degree_;
  } else if (series_) {
    s << "spherical harmonics of degree " << degree_;
  } else {
    s << "point mass";
  }
  return s.str();
}

}  // namespace noether
