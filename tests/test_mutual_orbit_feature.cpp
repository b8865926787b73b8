// MutualOrbitFeature (run/mutual_orbit_feature.cpp): a two-body-like scene's mutual period timed
// from the frames — against Kepler's third law, afresh after an impulse, and continued by a saved
// and loaded simulation as by the uninterrupted run, bit for bit.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <unistd.h>

using namespace noether;
using test::registry;

namespace {

// The Kepler orbit of test::kepler_scene timed over 30 time units (about 4.7 revolutions).
Scene kepler(std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), {"run.t_end=30", "run.output_every=0.05"});
  return test::kepler_scene(overrides);
}

// Kepler's period of bodies 0 and 1 at `state`: 2π sqrt(a³/μ), a = −μ/(2ε) (two-body energy ε).
double kepler_period(const Scene& scene, const State& state) {
  const System& sys = scene.system;
  const double mu = sys.G() * (sys.body(0).mass + sys.body(1).mass);
  const Vec3 r = state.x.col(1) - state.x.col(0);
  const Vec3 v = state.p.col(1) / sys.body(1).mass - state.p.col(0) / sys.body(0).mass;
  const double a = -mu / (2 * (0.5 * v.squaredNorm() - mu / r.norm()));
  return 2 * std::numbers::pi * std::sqrt(a * a * a / mu);
}

}  // namespace

// The period timed from the frames is Kepler's (to the frames' interpolation of each crossing).
TEST(MutualOrbitFeature, TimesKeplersPeriod) {
  const Scene scene = kepler();
  const RunSummary s = run_scene(scene, registry(), RunOptions{});
  EXPECT_EQ(s.mutual_pair, "sun–planet");
  EXPECT_EQ(s.mutual_revolutions, 4);
  EXPECT_NEAR(s.mutual_period, kepler_period(scene, scene.initial), 1e-4 * s.mutual_period);
}

// An impulse at t = 5 that shortens the orbit: the period is the new orbit's, timed from the
// impulse, not a mixture with the old one.
TEST(MutualOrbitFeature, AnImpulseTimesTheOrbitAfresh) {
  const Scene scene = kepler({"impulses=[{body: planet, time: 5, delta_v: [0, -0.2, 0]}]"});
  Simulation sim(scene, registry());
  sim.integrate(5.0);
  const State after = sim.state();  // at the impulse's time, the impulse applied
  const double before_period = kepler_period(scene, scene.initial), after_period = kepler_period(scene, after);
  ASSERT_GT(std::abs(after_period - before_period), 0.1 * before_period);
  sim.integrate(30.0);
  const RunSummary s = sim.finish();
  EXPECT_GE(s.mutual_revolutions, 3);
  EXPECT_NEAR(s.mutual_period, after_period, 1e-4 * after_period);
}

// Saved at t = 13.3 (two revolutions timed) and loaded: the loaded simulation's period and
// revolutions are the uninterrupted run's, bit for bit (before, it timed the orbit afresh from
// the load).
TEST(MutualOrbitFeature, ASavedSimulationKeepsItsClock) {
  const Scene scene = kepler();
  Simulation whole(scene, registry());
  whole.integrate(30.0);
  const RunSummary expected = whole.finish();
  const auto file = std::filesystem::temp_directory_path() / ("noether-mutual-" + std::to_string(::getpid()) + ".h5");
  {
    Simulation first(scene, registry());
    first.integrate(13.3);
    ASSERT_EQ(first.summary().mutual_revolutions, 2);
    first.save(file);
  }
  auto loaded = Simulation::load(file, registry());
  loaded->integrate(30.0);
  const RunSummary got = loaded->finish();
  std::filesystem::remove(file);
  EXPECT_EQ(got.mutual_revolutions, expected.mutual_revolutions);
  EXPECT_EQ(got.mutual_period, expected.mutual_period);
  EXPECT_EQ(got.mutual_pair, expected.mutual_pair);
}
