// G and the bodies' constants: masses, inertias, shapes, fields, radii (scene_sections.hpp;
// docs/user-guide.md "Scenes"). Their initial values are initial_state.cpp's.
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"

#include <noether/error.hpp>

#include <cmath>
#include <sstream>

namespace noether::detail {

// G: as given, or from the declared units (eq. 17.1), or 1. A G that contradicts the declared
// units by more than 1 % is a unit mistake, not a choice of constant.
double scene_gravitational_constant(const Params& root, const Units& units) {
  if (!root.has("G")) return units.declared ? units.gravitational_constant() : 1.0;  // no literal: see the schema
  const double G = root.at("G").as_double();
  if (units.declared && std::isfinite(G) && G > 0.0) {
    const double expected = units.gravitational_constant();
    if (std::abs(G - expected) > 0.01 * expected) {
      std::ostringstream msg;
      msg.precision(6);
      msg << root.at("G").here() << "G = " << G << " contradicts the declared units ("
          << units.describe() << "), in which G = " << expected << " " << units.of_G()
          << "; omit G to use that value, or fix 'units'";
      throw SceneError(msg.str());
    }
  }
  return G;
}

System parse_bodies(const Params& root, const Units& units, double G, const std::filesystem::path& folder,
                    std::vector<std::string>& notes) {
  const SceneSection& body_keys = scene_section("bodies[]");
  const Params& bodies = root.at("bodies");
  if (!bodies.is_sequence() || bodies.size() == 0)
    throw SceneError(bodies.here() + "'bodies' must be a non-empty list of bodies");
  std::vector<Body> list;
  for (const auto& b : bodies.items()) {
    if (!b.is_map()) throw SceneError(b.here() + "each body must be a mapping");
    body_keys.check(b, "body '" + b.get("name", std::string("?")) + "'");
    Body body;
    body.name = b.at("name").as_string();
    if (const std::string why = System::name_problem(body.name); !why.empty())  // with the line
      throw SceneError(b.at("name").here() + "body " + std::to_string(list.size()) + " is named '" + body.name +
                       "': " + why);
    if (b.has("shape")) {
      const Params& shape = b.at("shape");
      if (!shape.is_map() || shape.size() != 1)
        throw SceneError(shape.here() + "body '" + body.name + "': 'shape' must name one of "
                         "ellipsoid, polyhedron, dumbbell or spheres");
      scene_section("bodies[].shape").check(shape, "the shape of body '" + body.name + "'");
      if (shape.has("ellipsoid") || shape.has("polyhedron"))
        body.solid = scale_solid(*parse_solid(shape, body.name, folder, units), b, body.name);
      // A sphere cluster's keys (its values are the sphere-cluster potential's to check).
      if (shape.has("dumbbell"))
        scene_section("bodies[].shape.dumbbell").check(shape.at("dumbbell"), "dumbbell of body '" + body.name + "'");
      if (shape.has("spheres") && shape.at("spheres").is_sequence())
        for (const Params& sphere : shape.at("spheres").items())
          if (sphere.is_map())
            scene_section("bodies[].shape.spheres[]").check(sphere, "a sphere of body '" + body.name + "'");
    }
    FieldBody field;
    if (b.has("gravity")) {
      field = parse_field_body(b, body.name, folder, units, G);
      notes.insert(notes.end(), field.notes.begin(), field.notes.end());
      body.field = field.field;
      body.radius = field.radius;
    }
    if (b.has("radius")) {
      if (body.solid)
        throw SceneError(b.at("radius").here() + "body '" + body.name + "': 'radius' comes from "
                         "the shape (" + std::to_string(body.solid->radius) + "); remove it");
      body.radius = b.at("radius").as_double();
      if (!std::isfinite(body.radius) || body.radius < 0.0)
        throw SceneError(b.at("radius").here() + "body '" + body.name +
                         "': radius must be non-negative");
    }
    if (body.solid) body.radius = body.solid->radius;
    if (b.has("density") && !body.solid)
      throw SceneError(b.at("density").here() + "body '" + body.name + "': 'density' needs a "
                       "shape (ellipsoid or polyhedron)");
    body.mass = body.solid ? body.solid->mass : body.field ? field.mass : b.at("mass").as_double();
    if (!std::isfinite(body.mass) || body.mass <= 0.0)
      throw SceneError(b.at("mass").here() + "body '" + body.name + "': mass must be positive, not " +
                       b.at("mass").as_string());
    body.rigid = b.has("inertia") || body.solid || body.field;
    if (body.solid) {
      body.inertia = body.solid->inertia;
    } else if (body.field) {
      body.inertia = field.inertia;
    } else if (body.rigid) {
      body.inertia = inertia(b.at("inertia"));
      validate_inertia(body.inertia, b.at("inertia").here() + "body '" + body.name + "'");
    }
    if (b.has("shape")) body.shape = b.at("shape");
    if (!body.rigid)
      for (const char* key : {"attitude", "angular_velocity", "angular_momentum"})
        if (b.has(key))
          throw SceneError(b.at(key).here() + "body '" + body.name + "' has no 'inertia', so it" +
                           " is a point mass and cannot have '" + key +
                           "'; add 'inertia' to make it a rigid body");
    if (b.has("angular_velocity") && b.has("angular_momentum"))
      throw SceneError(b.here() + "body '" + body.name +
                       "': give 'angular_velocity' or 'angular_momentum', not both");
    list.push_back(std::move(body));
  }
  try {
    return System(G, std::move(list));  // validates what is left: G, unique names
  } catch (const SceneError& e) {
    throw SceneError((root.has("G") ? root.at("G").here() : bodies.here()) + e.what());
  }
}

}  // namespace noether::detail
