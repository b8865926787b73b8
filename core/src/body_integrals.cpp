// A body's inertia integrals from what the scene gave (body_integrals.hpp).
#include <noether/body_integrals.hpp>
#include <noether/error.hpp>
#include <noether/stokes_coefficients.hpp>

namespace noether {

InertiaIntegrals body_integrals(const Body& body, int order, const std::string& plugin, bool for_tolerance) {
  if (body.solid) return body.solid->integrals(order);
  const std::string N = std::to_string(order);
  if (body.field) {  // its coefficients' integrals (docs/equations.md (31.3))
    const int degree = body.field->degree;
    if (order > degree)
      throw SceneError(plugin + ": body '" + body.name + "' is given by its gravity field to degree " +
                       std::to_string(degree) + ", so " +
                       (for_tolerance ? "a tolerance, which needs its integrals to max_order + 2 = " + N +
                                            ", needs max_order ≤ " + std::to_string(degree - 2)
                                      : "order " + N + " cannot be evaluated; use order ≤ " + std::to_string(degree)));
    return field_integrals(truncated(*body.field, order, body.field->normalized), 0.5 * body.inertia.trace());
  }
  if (body.rigid) {
    if (!body.shape.is_null() && order > 2)
      throw SceneError(body.shape.here() + plugin + ": body '" + body.name +
                       "' is a point cluster; its shape is not a solid: use sphere-cluster, "
                       "or give it an ellipsoid or polyhedron shape");
    if (order > 2)
      throw SceneError(plugin + ": body '" + body.name + "' has an inertia but no shape, so its integrals beyond degree " +
                       "2 are unknown and " +
                       (for_tolerance ? "a tolerance needs its higher integrals" : "order " + N + " cannot be evaluated") +
                       "; give it a shape (ellipsoid or polyhedron), or use order ≤ 2");
    return integrals_from_inertia(body.mass, body.inertia);
  }
  return point_integrals({body.mass}, {Vec3::Zero()}, 0);
}

double integrals_radius(const Body& body) {
  if (body.solid) return body.solid->radius;
  if (body.field) return body.radius;
  return 0.0;
}

}  // namespace noether
