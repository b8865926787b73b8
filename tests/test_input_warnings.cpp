// The scene's input warnings (host/src/scene/input_warnings.hpp) and the start's conflicts
// (host/src/scene/start_apart.hpp): values that look like a unit slipped — a spin in deg/day
// for rad/s, a step in s for a scene in h, a density in g/cm³, a mesh in m read as km — are
// warned with the numbers and the unit meant, and the bundled scenes as they are are not; a
// pair that overlaps at the start because of a mesh's unit is refused with that unit named
// (issue 63, item 4).
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/scene.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace noether;

namespace {

Scene example(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return load_scene(test::source_path("examples/" + name), overrides);
}

std::string joined(const std::vector<std::string>& warnings) {
  std::string out;
  for (const std::string& w : warnings) out += w + "\n";
  return out;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

// Didymos' 2.26 h spin (7.72e-4 rad/s, 3823 deg/day) typed as 3823 rad/s: 5.6e6 times its
// breakup rate √(GM/R³) = 6.84e-4 rad/s, and the deg/day reading named with its value.
TEST(InputWarnings, ASpinInDegreesPerDayTypedAsRadiansPerSecond) {
  EXPECT_EQ(joined(example("didymos.yaml").warnings), "");
  const Scene slip = example("didymos.yaml", {"bodies.didymos.angular_velocity=[0, 0, 3823]"});
  const std::string w = joined(slip.warnings);
  EXPECT_TRUE(has(w, "body 'didymos' spins at |Ω| = 3.82e+03 rad/s, 5.59e+06 times its breakup rate √(GM/R³) = "
                     "0.000684 rad/s")) << w;
  EXPECT_TRUE(has(w, "read as deg/day it would be 0.000772 rad/s")) << w;
  EXPECT_TRUE(has(w, "--set bodies.didymos.angular_velocity:1: ")) << w;  // where it was given
}

// A spacecraft is held by its structure: a 1000 kg box spinning at 60 rpm is not warned, though it
// spins far beyond its own self-gravity's breakup rate.
TEST(InputWarnings, ASpacecraftMaySpinFast) {
  const Scene scene = parse_scene(R"(units: SI
bodies:
  - {name: box, density: 500, shape: {ellipsoid: {semi_axes: [0.8, 0.8, 0.8]}}, position: [0, 0, 0],
     angular_velocity: [0, 0, 6.283]}
  - {name: moon, mass: 1.0e11, position: [1.0e4, 0, 0]}
potential: {plugin: mutual-series, order: 2}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 1}
)",
                                  "spacecraft");
  EXPECT_EQ(joined(scene.warnings), "");
}

// The dumbbells' alpha spins at 9 (period 0.698): a step of 0.5 is fewer than two steps a turn.
// A scene in hours stepped by 30 (seconds meant) is told what 30 s is in hours.
TEST(InputWarnings, AStepLongerThanHalfTheShortestPeriod) {
  EXPECT_EQ(joined(test::dumbbell_scene().warnings), "");
  const std::string w = joined(test::dumbbell_scene({"integrator.step=0.5"}).warnings);
  EXPECT_TRUE(has(w, "integrator.step = 0.5 T is longer than half the shortest period the scene starts with (the "
                     "spin of 'alpha', 0.698 T)")) << w;
  const Scene hours = parse_scene(R"(units: {length: km, mass: kg, time: h}
bodies:
  - {name: sun, mass: 2.0e30, position: [0, 0, 0]}
  - {name: earth, mass: 6.0e24, orbit: {around: sun, a: 1.496e8, e: 0.0167}}
  - {name: moon, mass: 7.3e22, orbit: {around: earth, a: 384400, e: 0.055}}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 600}
run: {t_end: 6000, output_every: 6000}
)",
                                  "hours");
  const std::string h = joined(hours.warnings);
  EXPECT_TRUE(has(h, "hours:7: integrator.step = 600 h is longer than half the shortest period the scene starts "
                     "with (the orbit of 'moon' and 'earth', 653 h)")) << h;  // 2π √(a³ / G(M + m))
  EXPECT_TRUE(has(h, "the scene's time unit is h (600 s would be 0.167 h)")) << h;
}

// KW4 Alpha's 2.353e12 kg given as a mass over a mesh read in km is 1970 kg/m³; 2353 kg is a
// mesh in m read as km (1.97e-6 kg/m³: in m it would give 1970). Didymos' density typed as 2.2
// (g/cm³) is asked about.
TEST(InputWarnings, ADensityNoBodyHas) {
  EXPECT_EQ(joined(example("kw4-alpha-orbiter.yaml", {"bodies.alpha.mass=2.353e12"}).warnings), "");
  const std::string mesh = joined(example("kw4-alpha-orbiter.yaml", {"bodies.alpha.mass=2353"}).warnings);
  EXPECT_TRUE(has(mesh, "body 'alpha': its mass 2.35e+03 kg in the volume of its mesh (read in km), 1.2e+09 m³, is a "
                        "density of 1.97e-06 kg/m³, outside the 50–25000 kg/m³ of comets to metals; read in m the "
                        "mesh would give 1.97e+03 kg/m³")) << mesh;
  const std::string grams = joined(example("didymos.yaml", {"bodies.didymos.density=2.2"}).warnings);
  EXPECT_TRUE(has(grams, "body 'didymos': its density 2.2 kg/m³ is outside the 50–25000 kg/m³ of comets to metals; "
                         "densities are in kg/m³ — was it in g/cm³ (2.2e+03 kg/m³)?")) << grams;
}

// Didymos' mesh (in m) read as km is 1000 times too large and swallows Dimorphos: refused, with
// the mesh's unit named; two spheres of `radius` closer than their radii are refused too.
TEST(StartApart, AnOverlapNamesTheMeshUnit) {
  const std::string km = test::scene_error(test::source_text("examples/didymos.yaml"),
                                           {"bodies.didymos.shape.polyhedron.units=km"},
                                           test::source_path("examples/didymos.yaml"));
  EXPECT_TRUE(has(km, "bodies 'didymos' and 'dimorphos' overlap at the start")) << km;
  EXPECT_TRUE(has(km, "the mesh of 'didymos' is read in km (shape.polyhedron.units: a mesh in the wrong units is 1000 "
                      "times too large or small)")) << km;
  const std::string spheres = test::scene_error(test::source_text("examples/collision.yaml"),
                                                {"bodies.left.position=[-0.04, 0, 0]", "bodies.right.position=[0.04, 0, 0]"});
  EXPECT_TRUE(has(spheres, "bodies 'left' and 'right' overlap at the start: 0.02 inside each other's surface")) << spheres;
}
