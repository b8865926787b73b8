#pragma once
// noether._noether.relative_periodic_orbit: `noether orbit refine` + `orbit stability` on a scene
// with rigid bodies, for Python (docs/python.md, docs/relative-equilibria.md §"Relative periodic
// orbits"): the orbit shot on the scene's integrator and its multipliers, as a dict.
#include <noether/registry.hpp>

#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

namespace noether::python {

// The scene from a file (`text` empty) or YAML text named `name`.
pybind11::dict relative_periodic_orbit(PluginRegistry& registry, const std::string& file, const std::string& text,
                                       const std::string& name, const std::vector<std::string>& overrides,
                                       std::optional<double> period, int turns, double tolerance);

}  // namespace noether::python
