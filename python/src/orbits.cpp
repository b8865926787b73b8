// noether._noether's orbit solvers (docs/python.md, docs/relative-equilibria.md): relative
// equilibria, Lyapunov orbits and relative periodic orbits, each in its own file.
#include "bindings.hpp"
#include "lyapunov_orbit.hpp"
#include "registry.hpp"
#include "relative_equilibrium.hpp"
#include "relative_periodic_orbit.hpp"

#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;
using noether::python::registry;

void noether::python::bind_orbits(py::module_& m) {
  m.def("relative_equilibrium",
        [](const std::string& file, const std::string& text, const std::string& name,
           const std::vector<std::string>& overrides, const std::string& fix, std::optional<double> value,
           const std::vector<std::string>& pair, bool align, double tolerance) {
          return noether::python::relative_equilibrium(registry(), file, text, name, overrides, fix, value, pair, align,
                                                       tolerance);
        });
  m.def("lyapunov_orbit",
        [](const std::string& file, const std::string& text, const std::string& name,
           const std::vector<std::string>& overrides, const std::string& body, double degrees, double tolerance) {
          return noether::python::lyapunov_orbit(registry(), file, text, name, overrides, body, degrees, tolerance);
        });
  m.def("relative_periodic_orbit",
        [](const std::string& file, const std::string& text, const std::string& name,
           const std::vector<std::string>& overrides, std::optional<double> period, int turns, double tolerance) {
          return noether::python::relative_periodic_orbit(registry(), file, text, name, overrides, period, turns,
                                                          tolerance);
        });

}
