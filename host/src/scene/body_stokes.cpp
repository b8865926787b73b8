// A scene body's Stokes coefficients (body_stokes.hpp; docs/equations.md (31.1)).
#include <noether/body_stokes.hpp>
#include <noether/error.hpp>

#include <cmath>

namespace noether {

BodyStokes body_stokes(const Scene& scene, const std::string& name, int degree, double reference_radius,
                       bool normalized) {
  const int index = scene.system.index_of(name);
  if (index < 0) {
    std::string names;
    for (const Body& b : scene.system.bodies()) names += (names.empty() ? "" : ", ") + b.name;
    throw SceneError(scene.file + ": no body named '" + name + "' (the scene has " + names + ")");
  }
  const Body& body = scene.system.body(static_cast<std::size_t>(index));
  if (degree < 0 || degree > multi_index::kMaxDegree)
    throw SceneError("the degree must be 0.." + std::to_string(multi_index::kMaxDegree) + ", not " + std::to_string(degree));
  const double R = reference_radius > 0.0 ? reference_radius : body.radius;
  if (!(R > 0.0) || !std::isfinite(R))
    throw SceneError("body '" + name + "' has no radius: give the reference radius (--radius)");
  BodyStokes out;
  InertiaIntegrals T;
  if (body.solid) {
    T = body.solid->integrals(degree);
    out.source = body.solid->describe();
  } else if (body.field) {
    if (degree > body.field->degree)
      throw SceneError("body '" + name + "' is given by its field to degree " + std::to_string(body.field->degree) +
                       "; its coefficients above it are unknown");
    T = field_integrals(truncated(*body.field, degree, body.field->normalized), 0.5 * body.inertia.trace());
    out.source = "its gravity field (degree " + std::to_string(body.field->degree) + ")";
  } else {
    const int known = body.rigid ? 2 : 0;
    if (degree > known)
      throw SceneError("body '" + name + "' is " + (body.rigid ? "known by its mass and inertia" : "a point mass") +
                       ": its coefficients above degree " + std::to_string(known) +
                       " are unknown (give it a shape or a field)");
    T = body.rigid ? integrals_from_inertia(body.mass, body.inertia) : point_integrals({body.mass}, {Vec3::Zero()}, 0);
    out.source = body.rigid ? "its inertia" : "a point mass";
  }
  out.coefficients = stokes_from_integrals(T, R, degree, normalized);
  out.gm = scene.system.G() * body.mass;
  out.polar_moment = body.inertia(2, 2) / (body.mass * R * R);
  return out;
}

}  // namespace noether
