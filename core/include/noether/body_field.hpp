#pragma once
// BodyField: the gravity field one body of a scene exerts on a massless particle
// (docs/equations.md §38): exact where noether has the body's exact field and the particle is
// near it — an ellipsoid's everywhere (MacMillan 1930), a polyhedron's inside its series radius
// (Werner & Scheeres 1997) —, elsewhere the spherical-harmonic series (§32) of the body's Stokes
// coefficients (its shape's inertia integrals, its given field, or its inertia alone), and a
// point mass's G M / r. The series radius of a polyhedron is measured, not guessed: the smallest
// radius, on a ladder of spheres about the centre of mass, from which outwards the series'
// acceleration agrees with the exact one to the tolerance at every point tried (38.2).
#include <noether/gravity_field.hpp>
#include <noether/spherical_harmonic_field.hpp>
#include <noether/system.hpp>

#include <optional>
#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct BodyFieldOptions {
  int degree = 16;          // of the series (shapes and given fields; an inertia alone has 2)
  double tolerance = 1e-10; // the series' acceleration against the exact one, relative (38.2)
};

class BodyField {
 public:
  BodyField(const Body& body, double G, const BodyFieldOptions& options = {});

  struct Value {
    Vec3 acceleration = Vec3::Zero();  // −∇Φ, body frame
    double potential = 0.0;            // Φ < 0, per unit mass
  };
  // At r (body frame, from the centre of mass). Not thread-safe (the series holds scratch): one
  // copy per thread.
  Value operator()(const Vec3& r);

  // The body's surface, where a particle lands: its solid's, else the sphere of Body::radius
  // (none when that is 0). `surface_gap` > 0 outside, ≤ 0 on or inside it (eq. 16.5).
  bool has_surface() const { return solid_ || sphere_radius_ > 0.0; }
  double bounding_radius() const { return solid_ ? solid_->radius : sphere_radius_; }
  double surface_gap(const Vec3& r) const;

  // Beyond this distance from the centre of mass the series is used (∞: the exact field
  // everywhere; 0: the series everywhere).
  double series_radius() const { return series_radius_; }
  int degree() const { return degree_; }
  // "exact (ellipsoid 103 × 79 × 66)", "exact within 1342 m, else degree 16", "point mass".
  std::string describe() const;

 private:
  std::shared_ptr<const Solid> solid_;
  double sphere_radius_ = 0.0;
  double gm_ = 0.0;
  int degree_ = 0;
  double series_radius_ = 0.0;
  std::optional<SphericalHarmonicField> series_;
  std::optional<EllipsoidField> ellipsoid_;
  std::optional<PolyhedronField> polyhedron_;
};

}  // namespace noether

#pragma GCC visibility pop
