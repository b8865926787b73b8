#pragma once
// Helpers shared by the tests: paths of the source tree and of the built plugins.
#include <noether/lie.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/stepping.hpp>

#include <string>

namespace noether::test {

inline std::string source_path(const std::string& relative) {
  return std::string(NOETHER_SOURCE_DIR) + "/" + relative;
}

// A registry of the plugins built in this tree only (no NOETHER_PLUGIN_PATH, no install).
inline PluginRegistry bundled_plugins() { return PluginRegistry({NOETHER_TEST_PLUGIN_DIR}); }

// An integrator's configuration from YAML text, as a scene's `integrator:` gives one.
inline PluginConfig plugin_config(const std::string& yaml) {
  const Params p = parse_params(yaml, "test");
  return PluginConfig{p.at("plugin").as_string(), p};
}

inline Scene dumbbell_scene(const std::vector<std::string>& overrides = {}) {
  return load_scene(source_path("examples/dumbbells.yaml"), overrides);
}

}  // namespace noether::test
