#pragma once
// The derivative of a scene with respect to its keys (run.sensitivities; docs/derivatives.md,
// "Sensitivities"): the columns a tangent starts with, ∂z(t0)/∂p, which the integrator's tangent
// map then carries to every frame — ∂z(t)/∂p = M(t) ∂z(t0)/∂p for keys of the initial state,
// plus the step's own dependence on p for parameters of the dynamics (docs/equations.md §22).
#include <noether/parameter_derivatives.hpp>
#include <noether/scene.hpp>

#include <Eigen/Dense>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace noether {

struct SceneSensitivity {
  // One per column, each a key `--set` takes: "bodies.alpha.velocity.1", "bodies.moon.orbit.e",
  // "bodies.alpha.attitude.x" (a right rotation about the body's x axis, in radians),
  // "bodies.beta.mass", "G". Keys of the initial state first, parameters of the dynamics last
  // (each group in the order asked).
  std::vector<std::string> names;
  // ∂z(t0)/∂p: rows in the order of State::tangent_coordinates (docs/equations.md eq. 21.1).
  Eigen::MatrixXd columns;
  // The parameters of the dynamics among the keys (the last parameters->size() columns); null
  // when there are none.
  std::shared_ptr<const ParameterDerivatives> parameters;
};

// The model a scene makes (its potentials, from the registry), and its forces beyond the
// potential (`forces:`).
using PotentialMaker = std::function<std::shared_ptr<const Potential>(const Scene&)>;
using ForcingMaker = std::function<std::shared_ptr<const Forcing>(const Scene&)>;

// For each key (docs/derivatives.md lists those accepted): a vector key gives one column per
// component, a component or a scalar one. The scene's map from its keys to z(t0) — barycentric
// shift, relative_to, orbital elements, units, momenta γ = m v — is differenced (central, 1e-6
// of the key's scale; one-sided at a bound such as e = 0), an attitude's columns are exact. For
// a parameter of the dynamics (a mass or density, G, principal moments, an ellipsoid's
// semi-axes) the scene is made at p ± d, p ± 2d instead (d = 1e-4 |p|): its start, masses and
// inertias differenced on that stencil, its models made by `make_potential` for ∂(f, M)/∂p
// (22.1), their choices (a tolerance's orders) checked against those of `model`, the run's.
// A number of a force beyond the potential ("forces.0.k2": a tide's Love number, its time lag,
// a radiation pressure) is a parameter of the dynamics that moves the forces alone. In a scene
// with forces, every parameter's stencil also holds the forces `make_forcing` makes there, for
// ∂(f^F, M^F)/∂p (33.9). SceneError naming the key for a key the scene cannot take, that names
// no body or force, or whose model choices change within the stencil.
SceneSensitivity scene_sensitivity(const Scene& scene, const std::vector<std::string>& keys, const Potential& model,
                                   const PotentialMaker& make_potential, const ForcingMaker& make_forcing);

// The value in the scene, as written, of one column's key (as SceneSensitivity::names writes
// it: "bodies.beta.mass", "bodies.alpha.velocity.1", "bodies.moon.orbit.e", "impulses.0.delta_v.1",
// "impulses.0.time", "G", "forces.0.k2"): what `--set COLUMN=value` replaces. SceneError naming
// the column when it has no single value (an attitude's rotation) or is not a key sensitivities
// take.
double sensitivity_key_value(const Scene& scene, const std::string& column);

}  // namespace noether
