// The potential checker passes every bundled potential and catches a moment with a sign error.
#include "test_support.hpp"

#include <noether/potential_check.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

using namespace noether;

namespace {
const char* kScene = R"(G: 0.7
bodies:
  - {name: alpha, mass: 1.5, inertia: [0.0004, 0.0238, 0.0238], position: [0.67, 0, 0.2],
     shape: {dumbbell: {length: 0.25}}, attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, mass: 3, inertia: [0.0030, 0.1905, 0.1905], position: [-0.33, 0, -0.1],
     shape: {dumbbell: {length: 0.25}}, angular_velocity: [1, 2, 3]}
  - {name: probe, mass: 0.01, position: [-0.8, -0.9, 0.5]}
potential: {plugin: sphere-cluster}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";

// Solid shapes for the mutual-series, mutual-exact and spherical-harmonics models (the last with
// the octahedron's field): an ellipsoid, an octahedron off its principal axes, and a point mass.
std::string shapes_scene() {
  return R"(G: 0.7
bodies:
  - {name: alpha, density: 1, shape: {ellipsoid: {semi_axes: [0.5, 0.35, 0.25]}},
     position: [0.67, 0, 0.2], attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, density: 0.1, position: [-2.5, 0.5, -0.4], angular_velocity: [1, 2, 3],
     shape: {polyhedron: {file: )" + test::source_path("examples/shapes/hou2017_B.obj") + R"(, units: m, frame: mesh}}}
  - {name: probe, mass: 0.01, position: [-0.8, -1.9, 1.5]}
potential: {plugin: mutual-series, order: 6}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";
}

PotentialCheckReport check(const std::string& plugin) {
  PluginRegistry registry({NOETHER_TEST_PLUGIN_DIR, NOETHER_FIXTURE_PLUGIN_DIR});
  if (plugin.rfind("mutual-", 0) == 0 || plugin == "spherical-harmonics") {
    const std::string parameters = plugin == "mutual-series"         ? ", order: 6}"
                                   : plugin == "spherical-harmonics" ? ", body: beta, degree: 6}"
                                                                     : "}";
    const Scene scene = parse_scene(shapes_scene(), "check", {"potential={plugin: " + plugin + parameters});
    return check_potential(scene.system, *make_scene_potential(scene, registry), scene.initial);
  }
  // An external field needs its parameters and does not conserve momentum.
  const bool external = plugin == "central-field";
  const Scene scene = parse_scene(kScene, "check",
                                  {external ? "potential={plugin: central-field, mu: 2, center: [0.1, 0.2, 0.3]}"
                                            : "potential.plugin=" + plugin});
  PotentialCheckOptions options;
  options.third_law = !external;
  return check_potential(scene.system, *make_scene_potential(scene, registry), scene.initial, options);
}
}  // namespace

TEST(PotentialCheck, EveryBundledPotentialPasses) {
  for (const auto& name : test::bundled_plugins().names()) {
    auto registry = test::bundled_plugins();
    if (registry.info(name).kind != PluginKind::Potential) continue;
    const auto report = check(name);
    EXPECT_TRUE(report.passed()) << name << "\n" << report.format();
    const std::size_t laws = name == "central-field" ? 0 : 2;
    // Every bundled model has its own force Jacobian: its symmetry (20.3), and it against differences.
    const std::size_t jacobian = 2;
    // scene + 3 perturbed: forces, moments, Jacobian, laws
    EXPECT_EQ(report.rows.size(), 4u * (3 + 2 + jacobian + laws)) << name << "\n" << report.format();
  }
}

TEST(PotentialCheck, CatchesAMomentWithTheWrongSign) {
  const auto report = check("bad-moment-sign");
  EXPECT_FALSE(report.passed());
  for (const auto& row : report.rows) {
    if (row.quantity == "moment") {
      EXPECT_FALSE(row.pass) << row.state << " " << row.body;
      EXPECT_GT(row.error, 0.1);  // ‖M_fd − (−M)‖ = 2‖M‖, relative to the largest moment
    } else if (row.quantity == "force") {
      EXPECT_TRUE(row.pass) << row.state << " " << row.body;  // forces are right
    }
  }
  EXPECT_NE(report.format().find("CHECK FAILED"), std::string::npos);
}
