#pragma once
// The plugin registry of the Python module: one for the process, so that plugins stay loaded as
// long as anything made from them lives.
#include <noether/registry.hpp>

namespace noether::python {

inline PluginRegistry& registry() {
  static auto* r = new PluginRegistry();  // never destroyed: plugin code may outlive exit
  return *r;
}

}  // namespace noether::python
