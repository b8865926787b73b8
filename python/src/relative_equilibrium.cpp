#include "relative_equilibrium.hpp"
#include "state_arrays.hpp"

#include <noether/error.hpp>
#include <noether/relative_equilibrium.hpp>
#include <noether/scene.hpp>
#include <noether/scene_with_state.hpp>

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <numbers>

namespace py = pybind11;

namespace noether::python {

namespace {

std::size_t index_of(const System& system, const std::string& name) {
  const int i = system.index_of(name);
  if (i < 0) throw SceneError("relative_equilibrium(pair=...): no body '" + name + "' in the scene");
  return static_cast<std::size_t>(i);
}

}  // namespace

py::dict relative_equilibrium(PluginRegistry& registry, const std::string& file, const std::string& text,
                              const std::string& name, const std::vector<std::string>& overrides,
                              const std::string& fix, std::optional<double> value,
                              const std::vector<std::string>& pair, bool align, double tolerance) {
  const Scene scene = text.empty() ? load_scene(file, overrides) : parse_scene(text, name, overrides);
  const auto model = FullBodyModel::from_scene(scene, registry);
  EquilibriumOptions options;
  if (fix == "separation") options.fix = EquilibriumFamily::separation;
  else if (fix == "angular-momentum") options.fix = EquilibriumFamily::angular_momentum;
  else if (fix == "rate") options.fix = EquilibriumFamily::rate;
  else throw SceneError("relative_equilibrium(fix=...): 'separation', 'angular-momentum' or 'rate', not '" + fix + "'");
  if (value) options.value = *value;
  if (!pair.empty()) {
    if (pair.size() != 2) throw SceneError("relative_equilibrium(pair=...): two body names");
    options.body_a = index_of(scene.system, pair[0]);
    options.body_b = index_of(scene.system, pair[1]);
  }
  options.align = align;
  RelativeEquilibrium eq;
  EquilibriumStability st;
  {
    py::gil_scoped_release release;
    eq = find_relative_equilibrium(model, scene.initial, options);
    if (eq.converged) st = linear_stability(model, eq, tolerance);
  }
  py::dict out;
  out["converged"] = eq.converged;
  out["residual"] = eq.residual;
  out["iterations"] = eq.iterations;
  out["rate"] = eq.rate;
  out["period"] = 2 * std::numbers::pi / eq.rate;
  out["axis"] = std::vector<double>{eq.axis.x(), eq.axis.y(), eq.axis.z()};
  out["separation"] = eq.separation;
  out["angular_momentum"] = eq.angular_momentum;
  out["energy"] = eq.energy;
  out["overlapping"] = eq.contact > 0 && eq.separation <= eq.contact;
  // The state, as Simulation shows one: positions, velocities, attitudes, body-frame Ω.
  out["positions"] = rows(eq.state.x);
  out["velocities"] = velocities(scene.system, eq.state);
  out["attitudes"] = attitudes(eq.state);
  out["angular_velocities"] = angular_velocities(scene.system, eq.state);
  if (!eq.converged) return out;  // the state Newton ended on, for a look; no scene, no modes
  char desc[200];
  std::snprintf(desc, sizeof desc, "relative equilibrium (noether.relative_equilibrium): rate %.12g, period %.12g",
                eq.rate, 2 * std::numbers::pi / eq.rate);
  out["scene"] = scene_with_state(scene, eq.state, 2 * std::numbers::pi / eq.rate, 200, desc);
  py::list modes;
  for (const auto& m : st.modes) {
    py::dict d;
    d["frequency"] = m.frequency;
    d["period"] = m.frequency > 0 ? 2 * std::numbers::pi / m.frequency : INFINITY;
    d["growth"] = m.eigenvalue.real();
    d["motion"] = m.kind;
    d["share"] = m.weight;
    d["in_plane"] = m.in_plane;
    modes.append(d);
  }
  out["modes"] = modes;
  out["eigenvalues"] = complex_array(st.eigenvalues);
  out["verdict"] = st.verdict;
  out["in_plane_verdict"] = st.in_plane_verdict;
  out["out_of_plane_verdict"] = st.out_of_plane_verdict;
  out["energetic_verdict"] = st.energetic_verdict;
  out["energetic_index"] = st.energetic_index;
  out["invariance_defect"] = st.invariance_defect;
  return out;
}

}  // namespace noether::python
