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

// An inclined Kepler orbit of e ≈ 0.6 (a ≈ 1.01, period ≈ 6.4) about a star 1000 times heavier,
// the LGVI at h = 0.001 (the derivative tests' first scene).
inline Scene kepler_scene(const std::vector<std::string>& overrides = {}) {
  return parse_scene(R"(G: 1
bodies:
  - {name: sun, mass: 1, position: [0, 0, 0], velocity: [0, 0, 0]}
  - {name: planet, mass: 1.0e-3, position: [0.4, 0, 0], velocity: [0, 2.0, 0.1]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.001}
run: {t_end: 2, output_every: 1}
)",
                     "kepler", overrides);
}

inline Scene dumbbell_scene(const std::vector<std::string>& overrides = {}) {
  return load_scene(source_path("examples/dumbbells.yaml"), overrides);
}

}  // namespace noether::test
