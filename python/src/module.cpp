// noether._noether: the Python bindings of the host library (docs/python.md). The Python package
// noether (python/noether/__init__.py) wraps these in the API users see. This file makes the
// module and its exceptions; each part is bound by its own file (bindings.hpp).
#include "bindings.hpp"

#include <noether/error.hpp>
#include <noether/version.hpp>

#include <pybind11/pybind11.h>

namespace py = pybind11;

PYBIND11_MODULE(_noether, m) {
  m.doc() = "noether's core and host library (use the package `noether`, not this module)";
  m.attr("__version__") = NOETHER_VERSION;

  // noether::Error and its kinds as Python exceptions, with the same messages.
  static py::exception<noether::Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<noether::SceneError> scene_error(m, "SceneError", error.ptr());
  static py::exception<noether::PluginError> plugin_error(m, "PluginError", error.ptr());
  static py::exception<noether::IntegrationError> integration_error(m, "IntegrationError", error.ptr());
  static py::exception<noether::OutputError> output_error(m, "OutputError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const noether::SceneError& e) {
      scene_error(e.what());
    } catch (const noether::PluginError& e) {
      plugin_error(e.what());
    } catch (const noether::IntegrationError& e) {
      integration_error(e.what());
    } catch (const noether::OutputError& e) {
      output_error(e.what());
    } catch (const noether::Error& e) {
      error(e.what());
    }
  });

  noether::python::bind_commands(m);
  noether::python::bind_orbits(m);
  noether::python::bind_simulation(m);
}
