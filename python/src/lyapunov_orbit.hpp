#pragma once
// noether._noether.lyapunov_orbit: `noether orbit equilibrium --lyapunov` for Python
// (docs/python.md, docs/relative-equilibria.md): the periodic orbit of a body's libration.
#include <noether/registry.hpp>

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace noether::python {

// The scene from a file (`text` empty) or YAML text named `name`.
pybind11::dict lyapunov_orbit(PluginRegistry& registry, const std::string& file, const std::string& text,
                              const std::string& name, const std::vector<std::string>& overrides,
                              const std::string& body, double degrees, double tolerance);

}  // namespace noether::python
