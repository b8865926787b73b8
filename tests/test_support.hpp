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

// a ⊖ b in the coordinates z = (x, θ, γ, Π) of the tangent (docs/equations.md eq. 21.1):
// differences, and log(R_bᵀ R_a) for attitudes.
inline Eigen::VectorXd state_minus(const State& a, const State& b) {
  const auto n = a.x.cols(), m = a.Pi.cols();
  Eigen::VectorXd d(6 * n + 6 * m);
  for (Eigen::Index i = 0; i < n; ++i) {
    d.segment(3 * i, 3) = a.x.col(i) - b.x.col(i);
    d.segment(3 * n + 3 * m + 3 * i, 3) = a.p.col(i) - b.p.col(i);
  }
  for (Eigen::Index r = 0; r < m; ++r) {
    const auto k = static_cast<std::size_t>(r);
    d.segment(3 * n + 3 * r, 3) = log_so3(b.R[k].transpose() * a.R[k]);
    d.segment(6 * n + 3 * m + 3 * r, 3) = a.Pi.col(r) - b.Pi.col(r);
  }
  return d;
}

}  // namespace noether::test
