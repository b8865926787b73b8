#pragma once
// Helpers shared by the tests: paths and files of the source tree, the built plugins, scenes.
#include <noether/error.hpp>
#include <noether/lie.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/stepping.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace noether::test {

inline std::string source_path(const std::string& relative) {
  return std::string(NOETHER_SOURCE_DIR) + "/" + relative;
}

// A file of the archived reference data that lies beside the clone, never in it
// (../shared/data/RELATIVE, or $NOETHER_SHARED_DATA/RELATIVE), or "" when it is absent: the test
// then skips, saying so (GTEST_SKIP() << absent_data(relative)).
inline std::string shared_data(const std::string& relative) {
  const char* given = std::getenv("NOETHER_SHARED_DATA");
  const std::string root = given && *given ? std::string(given) : std::string(NOETHER_SOURCE_DIR) + "/../shared/data";
  const std::string path = root + "/" + relative;
  return std::ifstream(path).good() ? path : std::string();
}
inline std::string absent_data(const std::string& relative) {
  return "../shared/data/" + relative + " is absent (archived data is not in the repository: it lies beside the "
         "clone, or where NOETHER_SHARED_DATA points)";
}

// A registry of the plugins built in this tree only (no NOETHER_PLUGIN_PATH, no install).
// A file of the source tree as text ("" if it does not read).
inline std::string source_text(const std::string& relative) {
  std::ifstream in(source_path(relative));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The SceneError a scene's text (with overrides) gets, or "no error".
inline std::string scene_error(const std::string& text, const std::vector<std::string>& overrides = {},
                               const std::string& file = "s.yaml") {
  try {
    parse_scene(text, file, overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

inline PluginRegistry bundled_plugins() { return PluginRegistry({NOETHER_TEST_PLUGIN_DIR}); }
// One registry of the bundled plugins for a whole test binary (made on first use).
inline PluginRegistry& registry() {
  static PluginRegistry r = bundled_plugins();
  return r;
}

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

// A fast-spinning, slightly triaxial primary (spin 5, tilted 20° from the orbit normal) and a
// point-mass moon from r = 1 on an orbit of a ≈ 1.25, e ≈ 0.2 (n ≈ 0.74): the tide the moon raises spins the
// primary down and pushes the moon out.
inline Scene tidal_scene(const std::vector<std::string>& overrides = {}) {
  return parse_scene(R"(G: 1
bodies:
  - name: planet
    mass: 1
    inertia: [0.0324, 0.036, 0.0396]
    radius: 0.3
    position: [0, 0, 0]
    velocity: [0, 0, 0]
    attitude: {euler_angles: [0, 20, 0]}
    angular_velocity: [0, 0, 5]
  - {name: moon, mass: 0.1, position: [1, 0, 0], velocity: [0, 1.15, 0]}
barycentric: true
potential: {plugin: point-mass}
forces: [{plugin: tides, body: planet, k2: 0.5, time_lag: 0.1}]
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 50, output_every: 0.5}
)",
                     "tidal", overrides);
}

inline Scene dumbbell_scene(const std::vector<std::string>& overrides = {}) {
  return load_scene(source_path("examples/dumbbells.yaml"), overrides);
}

// K ellipsoids (semi-axes 1, 0.8, 0.6; unit mass, G = 1) on a cubic lattice of the given
// spacing, each turned and spinning differently, drifting slowly: a scene of K(K−1)/2 pairs
// for the many-body tests and benchmarks. `potential`: the scene's potential, as YAML; `body`:
// each body's mass and shape, as YAML (kLatticeDumbbell: dumbbells for sphere-cluster).
inline constexpr const char* kLatticeEllipsoid = "mass: 1, shape: {ellipsoid: {semi_axes: [1, 0.8, 0.6]}}";
inline constexpr const char* kLatticeDumbbell = "mass: 1, inertia: [0.002, 0.16, 0.16], shape: {dumbbell: {length: 0.8}}";
inline Scene ellipsoid_lattice_scene(int K, const std::string& potential, double spacing = 4.0,
                                     const std::string& body = kLatticeEllipsoid) {
  int side = 1;
  while (side * side * side < K) ++side;
  std::string text = "G: 1\nbodies:\n";
  for (int k = 0; k < K; ++k) {
    const int i = k % side, j = (k / side) % side, l = k / (side * side);
    const double a = 0.37 * k, b = 0.11 * k;
    text += "  - {name: e" + std::to_string(k) + ", " + body + ", position: [" +
            std::to_string(spacing * i + 0.1 * std::sin(a)) + ", " + std::to_string(spacing * j + 0.1 * std::cos(a)) +
            ", " + std::to_string(spacing * l) + "], velocity: [" + std::to_string(0.01 * std::cos(b)) + ", " +
            std::to_string(0.01 * std::sin(b)) + ", 0], attitude: {euler_angles: [" + std::to_string(17.0 * k) + ", " +
            std::to_string(5.0 * (k % 7)) + ", " + std::to_string(3.0 * (k % 5)) + "]}, angular_velocity: [0.01, 0, " +
            std::to_string(0.1 + 0.01 * k) + "]}\n";
  }
  text += "potential: " + potential + "\nintegrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 0.1, output_every: 0.1}\n";
  return parse_scene(text, "ellipsoid lattice", {});
}

// A primary (ellipsoid, semi-axes 2, 1.6, 1.2, mass 100, G = 1) and K − 1 small ellipsoids
// (0.2, 0.16, 0.12; mass 0.01) on circular orbits of radius 12 + 4k, each in its own plane: a
// scene where most pairs are far apart (the median pair's closest expected approach is ~600 times
// the sum of its radii at K = 128, the nearest ~2 times), for tolerance-chosen orders.
inline Scene satellite_swarm_scene(int K, const std::string& potential) {
  auto number = [](double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return std::string(buffer);
  };
  auto vec = [&](const Vec3& v) { return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]"; };
  std::string text = "G: 1\nbodies:\n  - {name: primary, mass: 100, shape: {ellipsoid: {semi_axes: [2, 1.6, 1.2]}}, "
                     "position: [0, 0, 0], velocity: [0, 0, 0], angular_velocity: [0, 0, 0.3]}\n";
  for (int k = 1; k < K; ++k) {
    const double r = 12.0 + 4.0 * k, u = std::fmod(1.9 * k, 2 * M_PI);
    const Mat3 turn = (Eigen::AngleAxisd(std::fmod(2.3 * k, 2 * M_PI), Vec3::UnitZ()) *
                       Eigen::AngleAxisd(std::fmod(0.7 * k, M_PI), Vec3::UnitX())).toRotationMatrix();
    const Vec3 x = turn * Vec3(r * std::cos(u), r * std::sin(u), 0.0);
    const Vec3 v = turn * (std::sqrt(100.0 / r) * Vec3(-std::sin(u), std::cos(u), 0.0));
    text += "  - {name: s" + std::to_string(k) + ", mass: 0.01, shape: {ellipsoid: {semi_axes: [0.2, 0.16, 0.12]}}, position: " +
            vec(x) + ", velocity: " + vec(v) + ", attitude: {euler_angles: [" + std::to_string(17.0 * k) + ", " +
            std::to_string(5.0 * (k % 7)) + ", 0]}, angular_velocity: [0, 0, " + std::to_string(0.1 + 0.01 * k) + "]}\n";
  }
  text += "potential: " + potential + "\nintegrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 0.1, output_every: 0.1}\n";
  return parse_scene(text, "satellite swarm", {});
}

}  // namespace noether::test
