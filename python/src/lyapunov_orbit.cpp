#include "lyapunov_orbit.hpp"
#include "state_arrays.hpp"

#include <noether/error.hpp>
#include <noether/lyapunov_orbit.hpp>
#include <noether/scene.hpp>
#include <noether/scene_with_state.hpp>

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <numbers>

namespace py = pybind11;

namespace noether::python {

py::dict lyapunov_orbit(PluginRegistry& registry, const std::string& file, const std::string& text,
                        const std::string& name, const std::vector<std::string>& overrides, const std::string& body,
                        double degrees, double tolerance) {
  const Scene scene = text.empty() ? load_scene(file, overrides) : parse_scene(text, name, overrides);
  const int index = scene.system.index_of(body);
  if (index < 0) throw SceneError("lyapunov_orbit(body=...): no body '" + body + "' in the scene");
  if (scene.system.rigid_index(static_cast<std::size_t>(index)) < 0)
    throw SceneError("lyapunov_orbit: body '" + body + "' is a point mass; it has no attitude to librate");
  if (!(degrees > 0 && degrees < 45))
    throw SceneError("lyapunov_orbit(degrees=...): between 0 and 45 degrees (small amplitudes grow out of the mode)");
  const auto model = FullBodyModel::from_scene(scene, registry);
  py::dict out;
  LyapunovOrbit ly;
  OrbitMultipliers mu;
  {
    py::gil_scoped_release release;
    const auto eq = find_relative_equilibrium(model, scene.initial);
    if (!eq.converged) throw SceneError("lyapunov_orbit: no relative equilibrium found near the scene's state");
    const auto st = linear_stability(model, eq, tolerance);
    const NormalMode* mode = libration_mode(st, body);
    if (!mode) throw SceneError("lyapunov_orbit: no oscillating mode is dominated by the libration of '" + body + "'");
    ly = noether::lyapunov_orbit(model, scene.integrator, eq, *mode, degrees * std::numbers::pi / 180);
    if (ly.orbit.closed()) mu = lyapunov_multipliers(model, scene.integrator, ly, tolerance);
  }
  out["period"] = ly.orbit.period;
  out["linear_period"] = ly.linear_period;
  out["angle"] = ly.orbit.angle;
  out["initial_closure"] = ly.orbit.initial_closure;
  out["closure"] = ly.orbit.closure;
  out["iterations"] = ly.orbit.iterations;
  out["jacobian"] = ly.orbit.jacobian;
  out["converged"] = ly.orbit.closed();
  out["step"] = ly.step;
  out["steps"] = ly.steps;
  if (!ly.orbit.closed()) return out;
  out["multipliers"] = complex_array(mu.multipliers);
  out["family"] = complex_array(mu.family);
  out["verdict"] = mu.verdict;
  out["monodromy"] = mu.monodromy;  // "tangent map" or "differences"
  Scene written = scene;
  written.integrator = lyapunov_integrator(scene.integrator, ly);
  out["scene"] = scene_with_state(written, ly.orbit.state, ly.orbit.period,
                                  frames_keeping_step(written, ly.orbit.period),
                                  "Lyapunov orbit of the libration of " + body + " (noether.lyapunov_orbit)");
  return out;
}

}  // namespace noether::python
