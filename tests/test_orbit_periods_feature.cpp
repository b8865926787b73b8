// Every bound pair's orbit period (run/orbit_periods_feature.cpp; docs/user-guide.md "Orbit
// periods"): a moon about its planet about the Sun, the moon's period against Kepler's and its
// error, estimated by the run at half the step, against the true one; the pair chosen by
// boundness where the Sun pulls harder; an impulse timing it afresh; a saved simulation that
// keeps it.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

using namespace noether;
using test::registry;

namespace {

// The Sun (1), a planet (1e-3) on a circle of radius 1, a moon (1e-9) about the planet at
// a_moon (e = 0.05, starting at the true anomaly nu); G = 1. `run`: more keys of run, `more`:
// more of the scene.
Scene moon_system(double a_moon, double step, double nu = 0.0, const std::string& run = ", t_end: 1",
                  const std::string& more = "") {
  char text[1024];
  std::snprintf(text, sizeof text, R"(G: 1
bodies:
  - {name: sun, mass: 1, position: [0, 0, 0]}
  - {name: planet, mass: 1.0e-3, orbit: {around: sun, a: 1, e: 0}}
  - {name: moon, mass: 1.0e-9, orbit: {around: planet, a: %.17g, e: 0.05, nu: %.17g}}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: %.17g}
run: {output_every: 0.001%s}
%s)",
                a_moon, nu, step, run.c_str(), more.c_str());
  return parse_scene(text, "moon system");
}

const OrbitPeriod& period_of(const RunSummary& s, const std::string& body) {
  for (const OrbitPeriod& o : s.orbit_periods)
    if (o.body == body) return o;
  throw std::runtime_error("no orbit period for " + body);
}

}  // namespace

// The moon at a = 0.005 (P = 2π √(a³ / G (m_p + m_m)) = 0.0702, the Sun's tide changing it by
// ~(P / P_planet)² ~ 1e-4): 14 revolutions in a time unit, its period within 1e-3 of Kepler's;
// its error at h = 2e-4 estimated within a factor 2 of its difference from a run at 2.5e-5 — and
// the binary's pair (sun–planet, the mutual orbit) is not timed twice.
TEST(OrbitPeriods, AMoonsPeriodAndItsError) {
  const double a = 0.005, kepler = 2 * std::numbers::pi * std::sqrt(a * a * a / (1e-3 + 1e-9));
  const RunSummary reference = run_scene(moon_system(a, 2.5e-5), registry(), {});
  const RunSummary s = run_scene(moon_system(a, 2e-4), registry(), {});
  ASSERT_EQ(s.orbit_periods.size(), 1u);
  const OrbitPeriod& moon = period_of(s, "moon");
  EXPECT_EQ(moon.about, "planet");
  EXPECT_EQ(moon.revolutions, 14);
  EXPECT_NEAR(moon.period, kepler, 1e-3 * kepler);
  ASSERT_TRUE(moon.error.estimated()) << moon.error.why_not;
  const double truth = std::abs(moon.period - period_of(reference, "moon").period);
  EXPECT_GT(moon.error.error, truth / 2);
  EXPECT_LT(moon.error.error, truth * 2);
  // The summary prints it, with its error.
  EXPECT_NE(format_summary(s).find("orbit period                  moon about planet: "), std::string::npos);
  // run.trust.period below its error fails the run by name.
  const RunSummary strict =
      run_scene(moon_system(a, 2e-4, 0.0, ", t_end: 1, trust: {period: " + std::to_string(0.5 * moon.error.error / moon.period) + "}"),
                registry(), {});
  ASSERT_FALSE(strict.verdict.trustworthy);
  EXPECT_EQ(strict.verdict.reasons.front().find("the orbit period of moon about planet is not resolved"), 0u)
      << strict.verdict.reasons.front();
}

// At a = 0.033, half the planet's Hill radius, starting at apoapsis between the planet and the
// Sun, the Sun pulls the moon harder than the planet (1 / 0.965² = 1.07 against 1e-3 / 0.0347² =
// 0.83) — the verdict's energy scales take it about the Sun —, yet it is bound to the planet: its
// period is timed about the planet (1.042 against Kepler's 1.19: the Sun's tide at half the Hill
// radius shortens it by 12 %).
TEST(OrbitPeriods, APairIsChosenByBoundnessNotPull) {
  const RunSummary s = run_scene(moon_system(0.033, 2e-4, 180.0, ", t_end: 3"), registry(), {});
  const OrbitPeriod& moon = period_of(s, "moon");
  EXPECT_EQ(moon.about, "planet");
  const double kepler = 2 * std::numbers::pi * std::sqrt(std::pow(0.033, 3) / 1e-3);
  EXPECT_NEAR(moon.period, kepler, 0.2 * kepler);
  EXPECT_GE(moon.revolutions, 2);
  bool judged_about_the_sun = false;
  for (const OrbitScale& o : s.orbits) judged_about_the_sun |= o.body == "moon" && o.about == "sun";
  EXPECT_TRUE(judged_about_the_sun);
}

// An impulse times the orbit afresh (as the mutual orbit): after a prograde kick at t = 0.5 the
// moon's period is the new orbit's, longer than before; a saved and loaded simulation reports
// what one that went on does.
TEST(OrbitPeriods, AnImpulseTimesItAfreshAndASavedSimulationKeepsIt) {
  const Scene plain = moon_system(0.005, 2e-4);
  const Scene kicked =
      moon_system(0.005, 2e-4, 0.0, ", t_end: 1", "impulses:\n  - {body: moon, time: 0.5, delta_v: [0, 0.02, 0], frame: rtn, around: planet}\n");
  const double before = period_of(run_scene(plain, registry(), {}), "moon").period;
  Simulation whole(kicked, registry());
  whole.integrate(1.0);
  const OrbitPeriod after = period_of(whole.finish(), "moon");
  EXPECT_GT(after.period, 1.01 * before);
  EXPECT_LT(after.revolutions, 8);  // timed from the kick

  const auto file = std::filesystem::temp_directory_path() / "noether-orbit-periods-save.h5";
  {
    Simulation first(kicked, registry());
    first.integrate(0.75);
    first.save(file);
  }
  auto loaded = Simulation::load(file, registry());
  loaded->integrate(1.0);
  const OrbitPeriod got = period_of(loaded->finish(), "moon");
  std::filesystem::remove(file);
  EXPECT_DOUBLE_EQ(got.period, after.period);
  EXPECT_EQ(got.revolutions, after.revolutions);
}
