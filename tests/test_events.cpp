// Events of the stepping loop (docs/equations.md §16): every integrator stops at the same
// collision and close approach of a head-on fall, whose time is known in closed form.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/lie.hpp>
#include <noether/simulation.hpp>

#include "run/event_watch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace noether;

namespace {

// Radial Kepler fall from rest at r0 under μ: the time to reach separation d (16.4).
double fall_time(double r0, double mu, double d) {
  const double u = d / r0;
  return std::sqrt(r0 * r0 * r0 / (2 * mu)) * (std::sqrt(u * (1 - u)) + std::acos(std::sqrt(u)));
}

struct Case {
  const char* integrator;
  double time_tolerance;  // the method's accuracy on this fall
};

const Case kCases[] = {
    {"{plugin: lgvi, step: 1.0e-4}", 5e-8},
    {"{plugin: lgvi, step: 1.0e-4, order: 4}", 1e-9},
    {"{plugin: rk, method: rk4, step: 1.0e-3}", 1e-8},
    {"{plugin: rk, method: dopri5, rtol: 1.0e-10, atol: 1.0e-12}", 1e-8},
    {"{plugin: rk, method: rkf78, rtol: 1.0e-12, atol: 1.0e-14}", 1e-9},
    {"{plugin: cvode, rtol: 1.0e-10, atol: 1.0e-12}", 2e-8},
    {"{plugin: jm-hybrid, step: 1.0e-4, Kc: 0.5}", 5e-8},
};

RunSummary fall(const std::string& integrator, const std::vector<std::string>& more = {}) {
  std::vector<std::string> overrides{"integrator=" + integrator};
  overrides.insert(overrides.end(), more.begin(), more.end());
  auto registry = test::bundled_plugins();
  return run_scene(load_scene(test::source_path("examples/collision.yaml"), overrides), registry, {});
}

double separation(const State& s) { return (s.x.col(0) - s.x.col(1)).norm(); }

}  // namespace

TEST(Events, EveryIntegratorStopsAtTheCollision) {
  const double exact = fall_time(1.0, 1.0, 0.1);
  for (const auto& c : kCases) {
    SCOPED_TRACE(c.integrator);
    const RunSummary s = fall(c.integrator);
    EXPECT_NE(s.stop_reason.find("collision: bodies 'left' and 'right' came within 0.1"), std::string::npos)
        << s.stop_reason;
    EXPECT_NEAR(s.final_state.t, exact, c.time_tolerance);
    // The state at the event is the method's own (a shortened step or dense output), at contact.
    EXPECT_NEAR(separation(s.final_state), 0.1, 1e-6);
    EXPECT_LT(s.final_state.t, 2.0);
  }
}

TEST(Events, EveryIntegratorStopsAtTheCloseApproach) {
  const double exact = fall_time(1.0, 1.0, 0.3);
  for (const auto& c : kCases) {
    SCOPED_TRACE(c.integrator);
    const RunSummary s = fall(c.integrator, {"run.close_approach=0.3"});
    EXPECT_NE(s.stop_reason.find("close approach: bodies 'left' and 'right' came within 0.3"), std::string::npos)
        << s.stop_reason;
    EXPECT_NEAR(s.final_state.t, exact, c.time_tolerance);
    EXPECT_NEAR(separation(s.final_state), 0.3, 1e-6);
  }
}

// Outputs before the event are all written, in order, and the event frame is the last.
TEST(Events, OutputsBeforeTheEventAreKept) {
  const RunSummary s = fall("{plugin: rk, method: dopri5, rtol: 1.0e-10, atol: 1.0e-12}");
  EXPECT_EQ(s.frames, 12u);  // t = 0, 0.1, ..., 1.0, and the event at 1.0953
}

TEST(Events, CollisionsCanBeSwitchedOff) {
  // Without the event the fall goes on through the contact distance (to t_end = 1.09, before
  // the singular encounter at 1.1107).
  const RunSummary s = fall("{plugin: rk, method: dopri5, rtol: 1.0e-10, atol: 1.0e-12}",
                            {"run.collisions=false", "run.t_end=1.09", "run.output_every=0.01"});
  EXPECT_TRUE(s.stop_reason.empty()) << s.stop_reason;
  EXPECT_DOUBLE_EQ(s.final_state.t, 1.09);
}

// A pair that starts closer than the threshold is not an event at t0; it becomes one only
// after it has separated and comes back.
TEST(Events, APairStartingInsideTheThresholdIsNotAnEvent) {
  const RunSummary s = fall("{plugin: rk, method: dopri5, rtol: 1.0e-10, atol: 1.0e-12}",
                            {"run.close_approach=2", "run.t_end=0.5"});
  EXPECT_TRUE(s.stop_reason.empty()) << s.stop_reason;
}

TEST(Events, ABodyWithAShapeTakesItsRadiusFromTheShape) {
  const Scene scene = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"));
  for (const auto& b : scene.system.bodies()) {
    ASSERT_TRUE(b.solid) << b.name;
    EXPECT_EQ(b.radius, b.solid->radius) << b.name;
    EXPECT_GT(b.radius, 0.0);
  }
  EXPECT_THROW(load_scene(test::source_path("examples/kw4-ellipsoids.yaml"), {"bodies.0.radius=1"}),
               SceneError);
  EXPECT_THROW(load_scene(test::source_path("examples/collision.yaml"), {"bodies.0.radius=-1"}),
               SceneError);
}

// The stepping loop's quick test of a watched pair at every step (Watch::clear: centres'
// squared distance against the threshold's square) agrees with the event function g itself:
// clear means g > 0, and g > 0 beyond round-off means clear — on the collision and close
// approach of the falling spheres, the shaped collision of KW4's ellipsoids (where clear is the
// bounding spheres being apart), and an escape, at 2000 random separations about each threshold.
TEST(Events, TheQuickTestOfAPairAgreesWithItsEventFunction) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const char* file : {"examples/collision.yaml", "examples/kw4-ellipsoids.yaml"}) {
    SCOPED_TRACE(file);
    const Scene scene = load_scene(test::source_path(file));
    const System& system = scene.system;
    Events events;
    events.close_approach = 1.3 * (system.body(0).radius + system.body(1).radius);
    events.escape = Escape{0, 1, 2.0 * events.close_approach, false};
    const std::vector<Watch> watched = watches(system, events);
    ASSERT_EQ(watched.size(), 3u);  // close approach, collision, escape
    State s = scene.initial;
    int clear = 0, near = 0;
    for (int k = 0; k < 2000; ++k) {
      for (auto& R : s.R) R = exp_so3(Vec3(unit(random), unit(random), unit(random)));
      const Vec3 direction = Vec3(unit(random), unit(random), unit(random)).normalized();
      for (const Watch& w : watched) {
        const double r = w.threshold * (1.0 + 0.5 * unit(random));
        s.x.col(1) = s.x.col(0) + r * direction;
        const double g = w.gap(system, s);
        if (w.clear(s)) {
          ++clear;
          EXPECT_GT(g, 0.0) << w.name() << " at r = " << r;
        } else if (w.kind != Watch::Kind::kCollision || !w.samples) {
          ++near;
          EXPECT_LE(g, 1e-12 * w.threshold) << w.name() << " at r = " << r;  // not clear: g ≤ 0
        }
      }
    }
    EXPECT_GT(clear, 2000);  // both sides of each threshold were tried
    EXPECT_GT(near, 1000);
  }
}
