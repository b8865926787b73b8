#include "relative_periodic_orbit.hpp"
#include "state_arrays.hpp"

#include <noether/error.hpp>
#include <noether/relative_periodic_orbit.hpp>
#include <noether/scene.hpp>
#include <noether/scene_with_state.hpp>

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <numbers>

namespace py = pybind11;

namespace noether::python {

py::dict relative_periodic_orbit(PluginRegistry& registry, const std::string& file, const std::string& text,
                                 const std::string& name, const std::vector<std::string>& overrides,
                                 std::optional<double> period, int turns, double tolerance) {
  const Scene scene = text.empty() ? load_scene(file, overrides) : parse_scene(text, name, overrides);
  if (period && !(*period > 0)) throw SceneError("relative_periodic_orbit(period=...): must be positive");
  const double T = period ? *period : scene.run.t_end;
  const auto model = FullBodyModel::from_scene(scene, registry);
  RelativePeriodicOrbit orbit;
  OrbitMultipliers mu;
  {
    py::gil_scoped_release release;
    // α0: the line of centres' turn over T, plus whole turns (as `orbit stability --turns`).
    const double alpha = relative_closure(model, scene.integrator, scene.initial, T).angle + 2 * std::numbers::pi * turns;
    orbit = shoot_relative_periodic_orbit(model, scene.integrator, scene.initial, T, alpha);
    if (orbit.closed()) mu = relative_orbit_multipliers(model, scene.integrator, orbit, tolerance);
  }
  py::dict out;
  out["period"] = T;
  out["angle"] = orbit.angle;
  out["axis"] = std::vector<double>{orbit.axis.x(), orbit.axis.y(), orbit.axis.z()};
  out["initial_closure"] = orbit.initial_closure;
  out["closure"] = orbit.closure;
  out["iterations"] = orbit.iterations;
  out["jacobian"] = orbit.jacobian;
  out["converged"] = orbit.closed();
  out["integrator"] = scene.integrator.plugin;
  if (!orbit.closed()) return out;  // no orbit: no multipliers, no scene
  out["multipliers"] = complex_array(mu.multipliers);
  out["max_modulus"] = mu.max_modulus;
  out["verdict"] = mu.verdict;
  out["energy_conserved"] = mu.energy_conserved;
  out["monodromy"] = mu.monodromy;  // "tangent map" or "differences"
  out["energy_defect"] = mu.energy_defect;
  out["invariance_defect"] = mu.invariance_defect;
  out["scene"] = scene_with_state(scene, orbit.state, T, frames_keeping_step(scene, T),
                                  "relative periodic orbit (noether.relative_periodic_orbit)");
  return out;
}

}  // namespace noether::python
