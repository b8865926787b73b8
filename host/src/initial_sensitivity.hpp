#pragma once
// The derivative of a scene's initial state z(t0) with respect to keys of its bodies' initial
// states (run.sensitivities; docs/derivatives.md, "Sensitivities"): the columns the tangent
// starts with, which the integrator's tangent map then carries to every frame,
// ∂z(t)/∂p = M(t) ∂z(t0)/∂p.
#include <noether/scene.hpp>

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace noether {

struct InitialSensitivity {
  // One per column, each a key `--set` takes: "bodies.alpha.velocity.1", "bodies.moon.orbit.e",
  // "bodies.alpha.attitude.x" (a right rotation about the body's x axis, in radians).
  std::vector<std::string> names;
  // ∂z(t0)/∂p: rows in the order of State::tangent_coordinates (docs/equations.md eq. 21.1).
  Eigen::MatrixXd columns;
};

// For each key (docs/derivatives.md lists those accepted): a vector key gives one column per
// component, a component or a scalar one. The scene's map from its keys to z(t0) — barycentric
// shift, relative_to, orbital elements, units — is differenced (central, 1e-6 of the key's
// scale; one-sided at a bound such as e = 0), an attitude's columns are exact. SceneError naming
// the key for a key that is not of an initial state (a mass, G, a shape: parameters of the
// dynamics), that the scene cannot take, or that names no body.
InitialSensitivity initial_sensitivity(const Scene& scene, const std::vector<std::string>& keys);

}  // namespace noether
