#pragma once
// The parts of noether._noether, each bound by its own file (python/src/module.cpp calls them):
// the Simulation class, the commands as functions, the orbit solvers.
#include <pybind11/pybind11.h>

namespace noether::python {

void bind_simulation(pybind11::module_& m);  // _Simulation (simulation.cpp)
void bind_commands(pybind11::module_& m);    // plugins, output_series, compare, fit, stokes, observe, view_html (commands.cpp)
void bind_orbits(pybind11::module_& m);      // relative_equilibrium, lyapunov_orbit, relative_periodic_orbit (orbits.cpp)

}  // namespace noether::python
