#pragma once
// A scene body's exterior gravity field as Stokes coefficients (`noether shape stokes`,
// noether.stokes in Python; docs/gravity-fields.md): from its shape's inertia integrals, from
// its own field, or from its inertia alone (degree ≤ 2).
#include <noether/scene.hpp>
#include <noether/stokes_coefficients.hpp>

#include <string>

namespace noether {

struct BodyStokes {
  StokesCoefficients coefficients;  // in the scene's units (mass, reference radius)
  std::string source;               // "ellipsoid 285 × 231.5 × 174.5", "field of degree 8", ...
  double gm = 0.0;                  // G M in the scene's units
  // C/(M R²): the moment of inertia about the body's z axis over M R² (gravity.polar_moment of a
  // scene that gives this body by these coefficients).
  double polar_moment = 0.0;
};

// The coefficients of `body` to `degree` about its centre of mass in its body frame, at the
// reference radius R (0: the body's radius, the sphere that holds it). Throws SceneError for a
// body that has no field to that degree (a point mass above 0, an inertia alone above 2, a
// field of lower degree).
BodyStokes body_stokes(const Scene& scene, const std::string& body, int degree, double reference_radius,
                       bool normalized);

}  // namespace noether
