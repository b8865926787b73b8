// The cannonball radiation force (plugins/forces/cannonball; docs/forces.md, "Cannonball
// radiation"; docs/equations.md §40): its push against (40.1) and its shadow (40.3) at chosen
// states, and an orbit about the Sun under it closing after the period of the Kepler problem of
// G M (1 − β) (40.2), for a point mass and for a massless particle, to 8e-6 au (the LGVI's phase
// error) — where without the light the same start misses by 0.78 au.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/particles.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

using namespace noether;
using test::registry;

namespace {

constexpr double kAu = 1.495978707e11, kPressure = 4.5606e-6, kSunMass = 1.98847e30, kG = 6.674e-11;
constexpr double kAreaToMass = 60.0, kReflectivity = 0.5;  // dust: β ≈ 0.07
const double kBeta = (1.0 + kReflectivity) * kPressure * kAu * kAu * kAreaToMass / (kG * kSunMass);  // (40.2)

std::string light(const std::string& extra = "") {
  std::ostringstream o;
  o.precision(17);
  o << "{plugin: cannonball, sun: sun, area_to_mass: " << kAreaToMass << ", reflectivity: " << kReflectivity
    << ", pressure: " << kPressure << ", distance: " << kAu << extra << "}";
  return o.str();
}

// A grain at 1 au on the circular orbit of G M (1 − β) about the Sun (a point mass at rest at the
// origin; the grain's 1 kg moves it by 1e-30 of the orbit), and a particle on the same orbit half
// a turn ahead.
Scene dust(const std::vector<std::string>& more = {}) {
  const double v = std::sqrt(kG * kSunMass * (1.0 - kBeta) / kAu);
  std::ostringstream o;
  o.precision(17);
  o << "units: SI\nG: " << kG << "\nbodies:\n"
    << "  - {name: sun, mass: " << kSunMass << ", radius: 6.957e8, position: [0, 0, 0], velocity: [0, 0, 0]}\n"
    << "  - {name: grain, mass: 1, position: [" << kAu << ", 0, 0], velocity: [0, " << v << ", 0]}\n"
    << "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 10000}\n"
    << "run: {t_end: 10000, output_every: 10000}\n"
    << "particles: {states: [[" << -kAu << ", 0, 0, 0, " << -v << ", 0]], check: 0}\n";
  std::vector<std::string> overrides{"forces=[" + light(", bodies: [grain], particles: true") + "]"};
  overrides.insert(overrides.end(), more.begin(), more.end());
  return parse_scene(o.str(), "dust", overrides);
}

Vec3 push(const Scene& scene, const State& s) {
  const auto force = registry().make_force(scene.forces[0].plugin, scene.system, scene.forces[0].params);
  Forces f;
  f.resize(scene.system);
  force->evaluate(s, f, *force->make_workspace());
  EXPECT_EQ(f.M.size() == 0 || f.M.isZero(), true) << "a cannonball has no torque";
  return f.f.col(1);
}

}  // namespace

// (40.1): |f| = m C_R P0 (d0/d)² A/m away from the Sun, at 1 au and at 2 au; none on the Sun.
TEST(Cannonball, ThePushIsTheCannonballsAwayFromTheSun) {
  const Scene scene = dust();
  State s = scene.initial;
  const double expected = (1.0 + kReflectivity) * kPressure * kAreaToMass;  // m = 1 kg at d = d0
  Vec3 f = push(scene, s);
  EXPECT_NEAR(f.x(), expected, 1e-15 * expected);
  EXPECT_EQ(f.y(), 0.0);
  s.x.col(1) = Vec3(0, -2 * kAu, 0);
  f = push(scene, s);
  EXPECT_NEAR(f.y(), -expected / 4, 1e-15 * expected);
  EXPECT_EQ(f.x(), 0.0);
}

// (40.3): a planet of radius 6.4e6 m between the grain and the Sun shades it (no push); moved
// aside by more than its radius it does not; eclipses: false ignores it.
TEST(Cannonball, AnotherBodysShadowTakesTheLight) {
  const std::string planet = "bodies+={name: planet, mass: 6e24, radius: 6.4e6, position: [1.4e11, 0, 0]}";
  Scene scene = dust({planet});
  State s = scene.initial;
  EXPECT_TRUE(push(scene, s).isZero());
  s.x.col(2) = Vec3(1.4e11, 6.5e6, 0);  // its limb 1e5 m beside the ray
  EXPECT_GT(push(scene, s).x(), 0.0);
  s.x.col(2) = Vec3(1.6e11, 0, 0);  // behind the grain: no shadow on it
  EXPECT_GT(push(scene, s).x(), 0.0);
  scene = dust({planet, "forces.0.eclipses=false"});
  EXPECT_GT(push(scene, scene.initial).x(), 0.0);
}

// (40.2): started on the circular orbit of G M (1 − β), the grain and the particle close after its
// period; without the light the same start (too slow for G M) falls inwards and misses by 0.78 au.
TEST(Cannonball, AnOrbitUnderTheLightIsKeplersOfTheReducedMass) {
  const double period = 2 * std::numbers::pi * std::sqrt(std::pow(kAu, 3) / (kG * kSunMass * (1.0 - kBeta)));
  const double steps = std::round(period / 10000.0), h = period / steps;
  char step[64], end[64];
  std::snprintf(step, sizeof step, "integrator.step=%.17g", h);
  std::snprintf(end, sizeof end, "run.t_end=%.17g", period);
  for (const bool lit : {true, false}) {
    std::vector<std::string> sets{step, end, std::string(end).replace(4, 5, "output_every")};
    if (!lit) sets.push_back("forces.0.area_to_mass=1e-30");
    Simulation sim(dust(sets), registry(), RunOptions{});
    sim.integrate(period);
    const Vec3 start(kAu, 0, 0), grain = sim.state().x.col(1) - sim.state().x.col(0);
    const Vec3 particle = sim.particles()->positions().col(0) - sim.state().x.col(0);
    const double grain_miss = (grain - start).norm() / kAu, particle_miss = (particle + start).norm() / kAu;
    std::printf("%s: beta %.4g, period %.6g s: grain misses by %.3g au, particle by %.3g au\n",
                lit ? "lit" : "dark", kBeta, period, grain_miss, particle_miss);
    if (lit) {
      EXPECT_LT(grain_miss, 2e-5);  // the LGVI's phase error at 3000 steps a turn
      EXPECT_LT(particle_miss, 2e-5);
    } else {
      EXPECT_GT(grain_miss, 0.05);
      EXPECT_GT(particle_miss, 0.05);
    }
  }
}

TEST(Cannonball, RefusesWhatItCannotModel) {
  const Scene scene = dust();
  const auto error = [&](const std::string& keys) {
    try {
      Params p = test::plugin_config("{plugin: cannonball, sun: sun, pressure: 4.5606e-6, distance: 1.5e11, " + keys +
                                     "}").params;
      registry().make_force("cannonball", scene.system, p);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto has = [](const std::string& what, const std::string& part) {
    return what.find(part) != std::string::npos;
  };
  EXPECT_TRUE(has(error("area_to_mass: 1"), "it pushes nothing: list 'bodies', or set 'particles: true'"));
  EXPECT_TRUE(has(error("area_to_mass: 1, bodies: [grain], reflectivity: 1.5"), "'reflectivity' ρ must be in [0, 1]"));
  EXPECT_TRUE(has(error("area_to_mass: 1, bodies: [sun]"), "'sun' is the Sun"));
  EXPECT_TRUE(has(error("area_to_mass: 1, bodies: [moon]"), "no body named 'moon'"));
  EXPECT_TRUE(has(error("area_to_mass: -1, bodies: [grain]"), "'area_to_mass' must be positive"));
  EXPECT_TRUE(has(error("area_to_mass: 1, bodies: [grain], position: [1, 0, 0]"), "not both"));
}
