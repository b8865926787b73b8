// The events as a run feature (run/event_feature.hpp) and the stepping loop's step cuts
// (StepCut, noether/stepping.hpp): the run's events are the feature's cut, which stops it where
// the loop's own watch of the same events does, bit for bit; a cut of another kind stops a step
// where its function crosses zero (the head-on fall's closed-form time, docs/equations.md
// eq. 16.4); ties go to the first cut.
#include "test_support.hpp"

#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include "run/event_feature.hpp"
#include "run/regula_falsi.hpp"
#include "run/run_features.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;

namespace {

// Radial Kepler fall from rest at r0 under μ: the time to reach separation d (16.4).
double fall_time(double r0, double mu, double d) {
  const double u = d / r0;
  return std::sqrt(r0 * r0 * r0 / (2 * mu)) * (std::sqrt(u * (1 - u)) + std::acos(std::sqrt(u)));
}

Scene fall(const std::vector<std::string>& overrides = {}) {
  return load_scene(test::source_path("examples/collision.yaml"), overrides);
}

struct Frames final : Observer {
  std::vector<State> states;
  void observe(const State& s, const Forces&, bool) override { states.push_back(s); }
};

// The stepping loop run on the scene's model with `schedule`, from its initial state.
StopInfo run_loop(const Scene& scene, Schedule schedule, State& state) {
  auto registry = test::bundled_plugins();
  auto potential = make_scene_potential(scene, registry);
  auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
  Frames frames;
  state = scene.initial;
  return advance(*integrator, *potential, scene.system, state, schedule, frames);
}

// A cut where the two bodies' separation falls to d, its function written here (not the
// events'): r − d.
class SeparationCut final : public StepCut {
 public:
  SeparationCut(double d, std::string name) : d_(d), name_(std::move(name)) {}
  void arm(const System&, const State&) override {}
  std::optional<double> cut(const System&, const Step& step) override {
    const auto gap = [this](const State& s) { return (s.x.col(0) - s.x.col(1)).norm() - d_; };
    const double g1 = gap(step.reached);
    if (g1 > 0) return std::nullopt;
    ++cuts;
    return detail::illinois_root([&](double tau) { return gap(step.at(tau)); }, step.t_prev, step.t,
                                 gap(step.previous), g1, 1e-14);
  }
  void describe(const System&, double t, StopInfo& stop) const override {
    stop.reason = name_ + " at t = " + std::to_string(t);
    stop.event = name_;
  }
  int cuts = 0;

 private:
  double d_;
  std::string name_;
};

}  // namespace

TEST(EventFeature, TheRunStopsWhereTheSteppingLoopsOwnWatchDoes) {
  for (const char* integrator : {"{plugin: lgvi, step: 1.0e-4}", "{plugin: rk, method: dopri5, rtol: 1.0e-10, atol: 1.0e-12}"}) {
    SCOPED_TRACE(integrator);
    const Scene scene = fall({std::string("integrator=") + integrator});
    // The run: the events are its feature's cut, the schedule's own Events off.
    auto registry = test::bundled_plugins();
    Simulation sim(scene, registry, {});
    const StopInfo by_feature = sim.integrate(scene.run.t_end);
    // The stepping loop given the same events itself.
    State state;
    const StopInfo by_loop =
        run_loop(scene, Schedule{scene.run.t_end, scene.run.output_every,
                                 Events{scene.run.close_approach, scene.run.collisions, scene.run.escape}},
                 state);
    EXPECT_EQ(by_feature.event, "collision");
    EXPECT_EQ(by_feature.reason, by_loop.reason);
    EXPECT_EQ(by_feature.t, by_loop.t);  // bit for bit
    EXPECT_EQ(sim.state().x, state.x);
    EXPECT_EQ(sim.state().p, state.p);
    EXPECT_NEAR(by_feature.t, fall_time(1.0, 1.0, 0.1), 5e-8);
  }
}

TEST(EventFeature, AScenesWithoutWatchedPairsHasNone) {
  auto registry = test::bundled_plugins();
  for (const auto& [overrides, made] :
       std::vector<std::pair<std::vector<std::string>, bool>>{{{}, true},
                                                              {{"run.collisions=false"}, false},
                                                              {{"run.collisions=false", "run.close_approach=0.3"}, true}}) {
    const Scene scene = fall(overrides);
    auto potential = make_scene_potential(scene, registry);
    auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
    const auto features =
        detail::make_run_features({scene, *integrator, scene.initial, *potential, registry, false, nullptr, 1});
    bool has_events = false;
    for (const auto& f : features) has_events = has_events || (f->name() == "events" && f->step_cut());
    EXPECT_EQ(has_events, made) << (overrides.empty() ? "" : overrides.back());
  }
  // Without them, the fall goes on through the bodies to t_end (point masses pass each other).
  Simulation sim(fall({"run.collisions=false", "run.t_end=0.5"}), registry, {});
  EXPECT_TRUE(sim.integrate(0.5).event.empty());
  EXPECT_EQ(sim.time(), 0.5);
}

TEST(EventFeature, ACutOfAnotherKindStopsTheStepWhereItsFunctionCrossesZero) {
  // The fall with the collisions off: a cut at separation 0.3 alone, then beside an identical
  // one (the first wins a tie), then beside the close approach at 0.3 (the events, first).
  const Scene scene = fall({"run.collisions=false", "integrator={plugin: lgvi, step: 1.0e-4, order: 4}"});
  const double exact = fall_time(1.0, 1.0, 0.3);
  SeparationCut first(0.3, "first"), second(0.3, "second");
  Schedule schedule{scene.run.t_end, scene.run.output_every, Events{0.0, false, {}}};
  schedule.cuts = {&first, &second};
  State state;
  const StopInfo stop = run_loop(scene, schedule, state);
  EXPECT_EQ(stop.event, "first");
  EXPECT_EQ(first.cuts, 1);   // the step that crossed: the loop stopped at once
  EXPECT_EQ(second.cuts, 1);  // every cut saw it
  EXPECT_NEAR(stop.t, exact, 1e-9);
  EXPECT_EQ(state.t, stop.t);
  EXPECT_NEAR((state.x.col(0) - state.x.col(1)).norm(), 0.3, 1e-9);  // the state at the cut is the method's own
  // The events' close approach at the same separation: the same crossing, to round-off, and the
  // events come first in a tie.
  SeparationCut third(0.3, "third");
  Schedule with_events{scene.run.t_end, scene.run.output_every, Events{0.3, false, {}}};
  with_events.cuts = {&third};
  const StopInfo approach = run_loop(scene, with_events, state);
  EXPECT_EQ(approach.event, "close approach");
  EXPECT_NEAR(approach.t, stop.t, 1e-12);
}
