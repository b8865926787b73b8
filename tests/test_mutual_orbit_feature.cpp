// MutualOrbitFeature (run/mutual_orbit_feature.cpp): a two-body-like scene's mutual period timed
// from the frames — against Kepler's third law, hardly moved by sparser frames, afresh after an
// impulse, before and after each impulse (ΔP), and continued by a saved and loaded simulation as
// by the uninterrupted run, bit for bit.
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

// The crossings interpolated by a cubic Hermite in the angle and its rate: on this orbit of
// e ≈ 0.6, timed from periapsis (where the angle turns fastest), frames 5 times sparser (25 an
// orbit) move the period by less than 2e-5 of it (linear interpolation: 9e-5); on Dimorphos'
// orbit after DART (e ≈ 0.02), 600 s frames against 30 s, by 1e-9 (linear: 2e-7, twice ΔP's
// error at a 30 s step).
TEST(MutualOrbitFeature, ItsPeriodHardlyDependsOnTheFrames) {
  const RunSummary dense = run_scene(kepler(), registry(), RunOptions{});
  const RunSummary sparse = run_scene(kepler({"run.output_every=0.25"}), registry(), RunOptions{});
  ASSERT_EQ(sparse.mutual_revolutions, dense.mutual_revolutions);
  EXPECT_NEAR(sparse.mutual_period, dense.mutual_period, 2e-5 * dense.mutual_period);
}

// Frames 2.5 time units apart on this 6.3-unit orbit (the angle turns by more than π between some
// near periapsis, where the nearest branch loses a revolution): not measured, said, rather than
// an aliased period; 0.25 apart is measured.
TEST(MutualOrbitFeature, FramesTooFarApartAreNotMeasured) {
  const RunSummary sparse = run_scene(kepler({"run.output_every=2.5"}), registry(), RunOptions{});
  EXPECT_TRUE(sparse.mutual_undersampled);
  EXPECT_EQ(sparse.mutual_revolutions, 0);
  EXPECT_TRUE(std::isnan(sparse.mutual_period));
  EXPECT_NE(format_summary(sparse).find("not measured: the frames are too far apart to follow the orbit of sun–planet"),
            std::string::npos);
  EXPECT_FALSE(run_scene(kepler({"run.output_every=0.25"}), registry(), RunOptions{}).mutual_undersampled);
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

// Two impulses (at t = 7 and 16, the second of two at one instant): the periods before and after
// each are Kepler's of each stretch, timed from the jump before, and ΔP their difference; the
// two impulses at t = 16 are one jump.
TEST(MutualOrbitFeature, ThePeriodBeforeAndAfterEachImpulse) {
  const Scene scene = kepler({"run.t_end=40",
                              "impulses=[{body: planet, time: 7, delta_v: [0, -0.1, 0]}, "
                              "{body: planet, time: 16, delta_v: [0, 0.05, 0]}, {body: planet, time: 16, delta_v: [0, 0, 0.01]}]"});
  Simulation sim(scene, registry());
  sim.integrate(7.0);
  const State first = sim.state();
  sim.integrate(40.0);
  const RunSummary s = sim.finish();
  const State& second = s.final_state;  // (no impulse after t = 16)
  ASSERT_EQ(s.period_changes.size(), 2u);
  const double P0 = kepler_period(scene, scene.initial), P1 = kepler_period(scene, first),
               P2 = kepler_period(scene, second);
  const PeriodChange &a = s.period_changes[0], &b = s.period_changes[1];
  EXPECT_EQ(a.t, 7.0);
  EXPECT_EQ(b.t, 16.0);
  EXPECT_EQ(a.revolutions_before, 1);  // 7 time units of a 6.4-unit orbit
  EXPECT_NEAR(a.before, P0, 1e-4 * P0);  // (the step's error, as Kepler's period above)
  EXPECT_NEAR(a.after, P1, 1e-4 * P1);
  EXPECT_EQ(a.after, b.before);
  EXPECT_NEAR(b.after, P2, 1e-4 * P2);
  EXPECT_EQ(b.after, s.mutual_period);
  EXPECT_EQ(b.revolutions_after, s.mutual_revolutions);
  EXPECT_NEAR(a.change(), P1 - P0, 1e-3 * std::abs(P1 - P0));
  // Errors estimated when the run finished (lgvi: a fixed step), kept in the summary.
  EXPECT_TRUE(a.change_error.estimated()) << a.change_error.why_not;
  EXPECT_TRUE(b.before_error.estimated());
  // JSON carries them.
  EXPECT_NE(format_summary_json(s).find("\"period_changes\": [{\"t\": 7, "), std::string::npos) << format_summary_json(s);
}

// A stretch too short to time (the impulse before one revolution): said, not a number.
TEST(MutualOrbitFeature, APeriodChangeNeedsARevolutionOnEachSide) {
  const RunSummary s =
      run_scene(kepler({"impulses=[{body: planet, time: 3, delta_v: [0, -0.1, 0]}]"}), registry(), RunOptions{});
  ASSERT_EQ(s.period_changes.size(), 1u);
  EXPECT_FALSE(s.period_changes[0].measured());
  EXPECT_TRUE(std::isnan(s.period_changes[0].change()));
  EXPECT_NE(format_summary(s).find("period change at t = 3 T      not measured: 0 whole revolutions timed before it"),
            std::string::npos)
      << format_summary(s);
}

// Saved between two impulses and loaded: the stretch the first one ended is kept (ΔP of the
// loaded run is the uninterrupted run's, bit for bit).
TEST(MutualOrbitFeature, ASavedSimulationKeepsItsStretches) {
  const Scene scene = kepler({"impulses=[{body: planet, time: 7, delta_v: [0, -0.1, 0]}]"});
  Simulation whole(scene, registry());
  whole.integrate(30.0);
  const RunSummary expected = whole.finish();
  const auto file = std::filesystem::temp_directory_path() / ("noether-stretch-" + std::to_string(::getpid()) + ".h5");
  {
    Simulation first(scene, registry());
    first.integrate(11.0);
    first.save(file);
  }
  auto loaded = Simulation::load(file, registry());
  loaded->integrate(30.0);
  const RunSummary got = loaded->finish();
  std::filesystem::remove(file);
  ASSERT_EQ(got.period_changes.size(), 1u);
  ASSERT_EQ(expected.period_changes.size(), 1u);
  EXPECT_EQ(got.period_changes[0].before, expected.period_changes[0].before);
  EXPECT_EQ(got.period_changes[0].after, expected.period_changes[0].after);
}
