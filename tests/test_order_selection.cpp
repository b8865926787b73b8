// Orders chosen from a tolerance (docs/equations.md §15, docs/choosing-a-model.md): the
// chosen order meets the tolerance against the exact reference along simulated orbits and is
// (mostly) the lowest that does; far pairs are point masses; a pair that comes closer than its
// order was chosen for is reported when the estimate there exceeds the tolerance.
#include "broken_run.hpp"
#include "order_selection_check.hpp"

#include <noether/diagnostics.hpp>

#include <gtest/gtest.h>

using namespace noether;
using namespace noether::test;

namespace {

const std::vector<double> kTolerances = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};

// Every chosen order meets its tolerance at ≥ 95 % of the configurations; where
// `mostly_minimal`, two orders lower fails it for most tolerances. Measured (docs/choosing-a-
// model.md): 100 % within everywhere; minimal at 7 of 8 tolerances on the KW4 ellipsoids, 5 of
// 7 on Didymos, 0 of 5 on Hou's octahedra (ratio 0.82 at the assumed closest separation, where
// the estimate is 2–5 orders conservative).
void expect_acceptance(const std::vector<ToleranceRow>& rows, int expect_chosen, bool mostly_minimal) {
  int chosen = 0, minimal = 0;
  for (const auto& r : rows) {
    if (r.order < 0) continue;
    ++chosen;
    EXPECT_GE(r.within, 0.95) << "tolerance " << r.tolerance << " order " << r.order;
    minimal += r.minimal;
  }
  EXPECT_GE(chosen, expect_chosen);
  if (mostly_minimal) EXPECT_GT(2 * minimal, chosen) << "the chosen order should mostly be the lowest that works";
}

}  // namespace

TEST(OrderSelection, Kw4EllipsoidsMeetTheTolerance) {
  expect_acceptance(check_tolerances("examples/kw4-ellipsoids.yaml", 62400, kTolerances, 16), 8, true);
}

TEST(OrderSelection, DidymosMeetsTheTolerance) {
  expect_acceptance(check_tolerances("examples/didymos.yaml", 42900, kTolerances, 16), 7, true);
}

TEST(OrderSelection, HouOctahedraMeetTheTolerance) {
  expect_acceptance(check_tolerances("examples/octahedra-hou.yaml", 78900, kTolerances, 20), 5, false);
}

TEST(OrderSelection, FarPairsArePointMasses) {
  // The KW4 ellipsoids 1 au from a solar-mass point: at 1e-10 the two pairs with the Sun are
  // point masses, the binary gets a series.
  const Scene base = load_scene(source_path("examples/kw4-ellipsoids.yaml"));
  std::string text = R"(G: 6.674e-11
bodies:
  - {name: sun, mass: 1.989e30, position: [-1.495978707e11, 0, 0], velocity: [0, -29784.7, 0]}
  - {name: alpha, mass: 2.353e12, shape: {ellipsoid: {semi_axes: [766, 747.5, 673.5]}},
     position: [106.7776748392283, -79.91484525723472, 36.21423834405145],
     velocity: [-0.006935245176848875, -0.01120679059485531, -0.004281746382636655]}
  - {name: beta, mass: 1.35e11, shape: {ellipsoid: {semi_axes: [285, 231.5, 174.5]}},
     position: [-1861.095, 1392.886, -631.2007], velocity: [0.1208788, 0.1953302, 0.07462921]}
potential: {plugin: mutual-series, tolerance: 1e-10, max_order: 16}
integrator: {plugin: lgvi, step: 60}
run: {t_end: 600, output_every: 60}
)";
  const Scene scene = parse_scene(text, "sun-and-binary");
  auto registry = bundled_plugins();
  auto potential = make_scene_potential(scene, registry);
  Forces f;
  f.resize(scene.system);
  PotentialEvaluator evaluate(potential);
  evaluate(scene.initial, f);
  const auto models = evaluate.pair_models();
  ASSERT_EQ(models.size(), 3u);
  for (const auto& m : models) {
    std::printf("%s–%s: %s, estimated %.1e at %.4g\n", m.body_a.c_str(), m.body_b.c_str(), m.model.c_str(),
                m.estimated_error, m.separation);
    if (m.body_a == "sun" || m.body_b == "sun") {
      EXPECT_EQ(m.model, "point masses");
    } else {
      EXPECT_GT(m.order, 6);
    }
  }
  // At 50 times their size the two ellipsoids are not point masses to 1e-10: their quadrupole
  // still pulls at 3e-5 (3 C20 (ρ/R)²); point masses suffice at 1e-4.
  for (const auto& [tol, point_masses] : {std::pair{1e-4, true}, std::pair{1e-6, false}}) {
    const auto scene50 = load_scene(source_path("examples/kw4-ellipsoids.yaml"),
                                    {"potential={plugin: mutual-series, tolerance: " + std::to_string(tol) + "}",
                                     "bodies.beta.position=[54000, 0, 0]", "bodies.alpha.position=[0, 0, 0]",
                                     "bodies.beta.velocity=[0, 0.05547, 0]", "bodies.alpha.velocity=[0, 0, 0]"});
    auto p50 = make_scene_potential(scene50, registry);
    Forces f50;
    f50.resize(scene50.system);
    PotentialEvaluator evaluate50(p50);
    evaluate50(scene50.initial, f50);
    EXPECT_EQ(evaluate50.pair_models().at(0).order == 0, point_masses) << tol;
  }
}

TEST(OrderSelection, WarnsWhenAPairComesCloserThanItsOrderWasChosenFor) {
  // tests/cli/scenes/close-pass.yaml: orders chosen for 3 km, periapsis 1.8 km. Independently,
  // along the same trajectory, the first state closer than 3 km whose estimate exceeds the
  // tolerance; the plugin re-estimates each time the separation has shrunk by 1 %, so it
  // reports that state or one at most 1 % closer — never earlier.
  const Scene scene = load_scene(source_path("tests/cli/scenes/close-pass.yaml"));
  const RunSummary summary = [&] {
    auto registry = bundled_plugins();
    return run_scene(scene, registry, {});
  }();
  ASSERT_EQ(summary.pair_models.size(), 1u);
  const PairModel& m = summary.pair_models[0];
  ASSERT_TRUE(m.exceeded);
  EXPECT_GT(m.exceeded_error, m.tolerance);
  EXPECT_LT(m.exceeded_separation, m.separation);

  struct Collect final : Observer {
    std::vector<State> states;
    void observe(const State& s, const Forces&, bool) override { states.push_back(s); }
  } collect;
  auto registry = bundled_plugins();
  auto potential = make_scene_potential(scene, registry);
  auto integrator = registry.make_integrator("lgvi", scene.system, potential, scene.integrator.params);
  State s = scene.initial;
  advance(*integrator, *potential, scene.system, s, {scene.run.t_end, scene.run.output_every}, collect);
  const auto &A = scene.system.body(0).solid, &B = scene.system.body(1).solid;
  const auto TA = A->integrals(m.order + 2), TB = B->integrals(m.order + 2);
  SeriesBank bank;
  double t_first = -1, R_first = 0;
  for (const State& st : collect.states) {
    const Vec3 R = st.R[0].transpose() * (st.x.col(1) - st.x.col(0));
    if (R.norm() >= m.separation) continue;
    const double e = series_error_estimate(bank, m.order, scene.system.G(), TA, TB, A->radius, B->radius, R,
                                           st.R[0].transpose() * st.R[1]);
    if (e > m.tolerance) {
      t_first = st.t, R_first = R.norm();
      break;
    }
  }
  std::printf("exceeded: reported at t = %.0f, R = %.2f; first state over the tolerance t = %.0f, R = %.2f\n",
              m.exceeded_time, m.exceeded_separation, t_first, R_first);
  ASSERT_GT(t_first, 0);
  EXPECT_GE(m.exceeded_time, t_first);
  EXPECT_GE(m.exceeded_separation, 0.99 * R_first - 1e-9);
}

// The orders are chosen where the scene starts (Potential::choose_models, made by
// make_scene_potential), not where a workspace first evaluates: a model made for the KW4
// ellipsoids 54 km apart at 1e-6 evaluates with the orders it chose there at any state — here
// the binary 2.5 km apart, where a model that chooses at its first evaluation takes a higher one
// — and its forces there are those of that fixed order, bit for bit.
TEST(OrderSelection, ChosenWhereTheSceneStartsWhateverAWorkspaceSeesFirst) {
  auto registry = bundled_plugins();
  const auto kw4 = source_path("examples/kw4-ellipsoids.yaml");
  const Scene far = load_scene(kw4, {"potential={plugin: mutual-series, tolerance: 1e-6}", "bodies.beta.position=[54000, 0, 0]",
                                     "bodies.alpha.position=[0, 0, 0]", "bodies.beta.velocity=[0, 0.05547, 0]",
                                     "bodies.alpha.velocity=[0, 0, 0]"});
  const Scene near = load_scene(kw4, {"potential={plugin: mutual-series, tolerance: 1e-6}"});
  const auto chosen_far = make_scene_potential(far, registry);
  const auto order_of = [&](const std::shared_ptr<const Potential>& model, const State& first) {
    PotentialEvaluator evaluate(model);
    Forces f;
    f.resize(near.system);
    evaluate(first, f);
    const auto models = evaluate.pair_models();  // none for a fixed order
    return std::pair{models.empty() ? -1 : models[0].order, f};
  };
  const auto [far_order, far_forces] = order_of(chosen_far, near.initial);
  const int near_order = order_of(registry.make_potential("mutual-series", near.system, near.potentials[0].params),
                                  near.initial).first;
  std::printf("chosen 54 km apart: order %d; 2.5 km apart: order %d\n", far_order, near_order);
  EXPECT_LT(far_order, near_order);
  EXPECT_EQ(far_order, order_of(make_scene_potential(far, registry), far.initial).first);
  const auto fixed = load_scene(kw4, {"potential={plugin: mutual-series, order: " + std::to_string(far_order) + "}"});
  const Forces fixed_forces = order_of(make_scene_potential(fixed, registry), near.initial).second;
  EXPECT_EQ((far_forces.f - fixed_forces.f).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((far_forces.M - fixed_forces.M).cwiseAbs().maxCoeff(), 0.0);
}

// A tolerance exceeded before a break stays reported by the run that continues it — resumed from
// its output, or saved and loaded — with the time it was first exceeded, as the uninterrupted run
// reports it (the continued run's own watch would fire again later, at another time). The close
// pass (tests/cli/scenes/close-pass.yaml) exceeds at t = 58320; the break is at 58800.
TEST(OrderSelection, AnExceededToleranceSurvivesABreak) {
  const Scene scene = load_scene(source_path("tests/cli/scenes/close-pass.yaml"));
  auto registry = bundled_plugins();
  Simulation whole(scene, registry);
  whole.integrate(60000);
  const RunSummary uninterrupted = whole.finish();
  ASSERT_EQ(uninterrupted.pair_models.size(), 1u);
  ASSERT_TRUE(uninterrupted.pair_models[0].exceeded);
  const double first = uninterrupted.pair_models[0].exceeded_time;
  ASSERT_LT(first, 58800);
  const BrokenRun broken(scene, registry, 58800, "exceeded");
  const auto expect_reported = [&](Simulation& continued, const char* how) {
    continued.integrate(60000);
    const RunSummary s = continued.finish();
    ASSERT_EQ(s.pair_models.size(), 1u) << how;
    EXPECT_TRUE(s.pair_models[0].exceeded) << how;
    EXPECT_EQ(s.pair_models[0].exceeded_time, first) << how;
    EXPECT_EQ(s.pair_models[0].exceeded_separation, uninterrupted.pair_models[0].exceeded_separation) << how;
    EXPECT_FALSE(s.verdict.trustworthy) << how;
  };
  expect_reported(*Simulation::load(broken.saved, registry), "saved and loaded");
  expect_reported(*Simulation::resume(broken.output, registry, RunOptions{}, 60000), "resumed");
}
