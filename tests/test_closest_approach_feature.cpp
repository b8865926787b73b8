// Each pair's closest approach as a run feature (host/src/run/closest_approach_feature.hpp): a
// hyperbolic flyby's periapsis distance and time against Kepler's closed form, located between
// coarse frames, with errors (the run at half the step, and the frames' interpolation bound) that
// cover the true ones; a pair receding from the start or still closing at the end said so; a
// saved and loaded simulation ends with the uninterrupted run's closest approaches, bit for bit.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <unistd.h>

using namespace noether;
using test::registry;

namespace {

// A hyperbola of e = 1.5, q = 0.5 about G M = 1.001 (a point mass of 1e-3 about one of 1, G = 1),
// started at true anomaly −100°: its periapsis passage at t_p from the hyperbolic Kepler equation.
constexpr double kE = 1.5, kQ = 0.5, kMu = 1.001;

double periapsis_time() {
  const double a = kQ / (kE - 1.0), nu0 = -100.0 * std::numbers::pi / 180.0;
  const double H0 = 2.0 * std::atanh(std::sqrt((kE - 1.0) / (kE + 1.0)) * std::tan(nu0 / 2.0));
  const double M0 = kE * std::sinh(H0) - H0;
  return -M0 / std::sqrt(kMu / (a * a * a));
}

Scene flyby(const std::vector<std::string>& overrides = {}) {
  const double p = kQ * (1.0 + kE), nu = -100.0 * std::numbers::pi / 180.0;
  const double r = p / (1.0 + kE * std::cos(nu)), s = std::sqrt(kMu / p);
  const double x = r * std::cos(nu), y = r * std::sin(nu);
  const double vx = s * (kE * std::sin(nu) * std::cos(nu) - (1.0 + kE * std::cos(nu)) * std::sin(nu));
  const double vy = s * (kE * std::sin(nu) * std::sin(nu) + (1.0 + kE * std::cos(nu)) * std::cos(nu));
  std::ostringstream o;
  o.precision(17);
  o << "G: 1\nbodies:\n  - {name: star, mass: 1, position: [0, 0, 0]}\n"
    << "  - {name: probe, mass: 1.0e-3, position: [" << x << ", " << y << ", 0], velocity: [" << vx << ", " << vy
    << ", 0]}\nbarycentric: true\npotential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 0.004}\n"
    << "run: {t_end: 4, output_every: 0.1}\n";
  return parse_scene(o.str(), "flyby", overrides);
}

}  // namespace

// The periapsis between frames 0.1 apart (≈ 1/5 of the passage's time scale): distance and time
// against Kepler's; each error estimate covers the true error and is not a gross overstatement.
TEST(ClosestApproachFeature, AFlybysPeriapsisBetweenFramesIsKeplers) {
  const double tp = periapsis_time();
  for (const char* frames : {"run.output_every=0.1", "run.output_every=0.02"}) {
    Simulation sim(flyby({frames}), registry(), RunOptions{});
    sim.integrate(4.0);
    const RunSummary s = sim.finish();
    ASSERT_EQ(s.closest_approaches.size(), 1u);
    const ClosestApproach& c = s.closest_approaches[0];
    std::printf("%s: q %.12g (true %.12g, off %.3g, estimated %.3g of which frames %.3g); t %.10g (true %.10g, off "
                "%.3g, estimated %.3g)\n",
                frames, c.distance, kQ, c.distance - kQ, c.distance_error.error, c.frames_error, c.t, tp, c.t - tp,
                c.time_error.error);
    EXPECT_EQ(c.pair, "star–probe");
    EXPECT_EQ(c.where, ClosestApproach::Where::kEncounter);
    ASSERT_TRUE(c.distance_error.estimated() && c.time_error.estimated());
    EXPECT_LE(std::abs(c.distance - kQ), c.distance_error.error);
    EXPECT_LE(std::abs(c.t - tp), c.time_error.error);
    EXPECT_LE(c.distance_error.error, 30 * std::abs(c.distance - kQ) + 1e-9);
    EXPECT_EQ(s.min_distance, c.distance);
    EXPECT_EQ(s.min_distance_pair, "star–probe");
  }
}

// Stopped before periapsis the pair is still closing (the end); started after it, receding (the
// start): neither is an encounter, and neither gets an error estimate.
TEST(ClosestApproachFeature, TheStartAndTheEndAreSaidSo) {
  Simulation closing(flyby({"run.t_end=0.9", "run.output_every=0.1"}), registry(), RunOptions{});
  closing.integrate(0.9);
  const RunSummary a = closing.finish();
  EXPECT_EQ(a.closest_approaches[0].where, ClosestApproach::Where::kEnd);
  EXPECT_EQ(a.closest_approaches[0].t, 0.9);
  EXPECT_FALSE(a.closest_approaches[0].distance_error.estimated());
  // The state after periapsis, as the scene's start: receding from there.
  Simulation past(flyby(), registry(), RunOptions{});
  past.integrate(3.0);
  const State after = past.state();
  Scene scene = flyby({"run.t_end=1", "run.output_every=0.1"});
  scene.initial = after;
  scene.initial.t = 0.0;
  Simulation receding(scene, registry(), RunOptions{});
  receding.integrate(1.0);
  const RunSummary b = receding.finish();
  EXPECT_EQ(b.closest_approaches[0].where, ClosestApproach::Where::kStart);
  EXPECT_EQ(b.closest_approaches[0].t, 0.0);
}

// Saved before the periapsis and loaded, the run ends with the uninterrupted run's closest
// approach to the bit (the running values kept in /checkpoint/summary).
TEST(ClosestApproachFeature, ASavedSimulationKeepsIt) {
  Simulation whole(flyby(), registry(), RunOptions{});
  whole.integrate(4.0);
  const RunSummary w = whole.summary();
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("noether-closest-" + std::to_string(getpid()) + ".h5");
  for (const double at : {0.7, 1.6}) {  // before and after the periapsis (t_p ≈ 1.044)
    {
      Simulation first(flyby(), registry(), RunOptions{});
      first.integrate(at);
      first.save(file);
    }
    auto loaded = Simulation::load(file, registry());
    loaded->integrate(4.0);
    const RunSummary l = loaded->summary();
    ASSERT_EQ(l.closest_approaches.size(), 1u);
    EXPECT_EQ(l.closest_approaches[0].distance, w.closest_approaches[0].distance) << "saved at " << at;
    EXPECT_EQ(l.closest_approaches[0].t, w.closest_approaches[0].t) << "saved at " << at;
    std::filesystem::remove(file);
  }
}

// The verdict judges an encounter's distance by run.trust.closest_approach, and names the remedy:
// frames closer together where the interpolation is most of the error, else a smaller step.
TEST(ClosestApproachFeature, TheVerdictNamesTheRemedy) {
  const auto verdict = [](const std::vector<std::string>& sets) {
    Simulation sim(flyby(sets), registry(), RunOptions{});
    sim.integrate(4.0);
    std::string reasons;
    for (const std::string& r : sim.finish().verdict.reasons) reasons += r + "\n";
    return reasons;
  };
  EXPECT_EQ(verdict({}), "");  // 1.1e-4 of 0.5 < 1e-3
  const std::string frames = verdict({"run.trust.closest_approach=1e-5"});
  EXPECT_NE(frames.find("the closest approach of star–probe at t = 1.04426 T is not resolved: its estimated error 0.000111 is "),
            std::string::npos) << frames;
  EXPECT_NE(frames.find("frames closer together (a smaller run.output_every) locate it"), std::string::npos) << frames;
  const std::string step = verdict({"run.output_every=0.02", "run.trust.closest_approach=1e-6"});
  EXPECT_NE(step.find("(run.trust.closest_approach; the run repeated at half the step, Richardson order 2); a step of "
                      "about"), std::string::npos) << step;
}
