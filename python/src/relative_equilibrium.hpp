#pragma once
// noether._noether.relative_equilibrium: `noether orbit equilibrium` for Python (docs/python.md,
// docs/relative-equilibria.md) — the equilibrium, its modes and both verdicts as a dict.
#include <noether/registry.hpp>

#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

namespace noether::python {

// The scene from a file (`text` empty) or YAML text named `name`; `pair` two body names.
pybind11::dict relative_equilibrium(PluginRegistry& registry, const std::string& file, const std::string& text,
                                    const std::string& name, const std::vector<std::string>& overrides,
                                    const std::string& fix, std::optional<double> value,
                                    const std::vector<std::string>& pair, bool align, double tolerance);

}  // namespace noether::python
