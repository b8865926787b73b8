// Models and workspaces (docs/writing-a-plugin.md): one potential, shared by several threads
// each with a workspace of its own, gives bit for bit what one thread gives — for every
// bundled potential, for a sum of potentials, and for whole integrations sharing one model.
#include "test_support.hpp"

#include <noether/integrator.hpp>
#include <noether/potential.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <thread>

using namespace noether;

namespace {

constexpr int kThreads = 4;

struct ModelCase {
  const char* name;
  const char* scene;
  const char* potential;  // a --set override, or "" for the scene's own
};

const ModelCase kModels[] = {
    {"point-mass", "examples/figure-eight.yaml", ""},
    {"sphere-cluster", "examples/dumbbells.yaml", ""},
    {"sum of two", "examples/dumbbells.yaml", "potential=[{plugin: sphere-cluster}, {plugin: point-mass}]"},
    {"mutual-series order 8", "examples/kw4-ellipsoids.yaml", "potential={plugin: mutual-series, order: 8}"},
    {"mutual-series tolerance", "examples/kw4-heliocentric.yaml", ""},
    {"mutual-exact", "examples/octahedra-hou.yaml", "potential={plugin: mutual-exact, tolerance: 1e-6, max_level: 3}"},
};

// State k: the initial state with every body moved by a few per cent of the scene's size and
// every attitude turned, differently for each k.
State perturbed(const Scene& scene, int k) {
  State s = scene.initial;
  const double scale = s.x.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < s.x.cols(); ++i)
    s.x.col(i) += 0.01 * scale * Vec3(std::sin(k + i), std::cos(2.0 * k + i), 0.5 * std::sin(3.0 * k));
  for (std::size_t r = 0; r < s.R.size(); ++r) s.R[r] = s.R[r] * exp_so3(Vec3(0.1 * k, 0.05 * static_cast<double>(r), -0.07 * k));
  return s;
}

bool same(const Forces& a, const Forces& b) { return a.U == b.U && a.f == b.f && a.M == b.M; }

TEST(Workspace, OneModelEvaluatedFromSeveralThreadsGivesWhatOneThreadGives) {
  auto registry = test::bundled_plugins();
  for (const ModelCase& c : kModels) {
    std::vector<std::string> set;
    if (*c.potential) set.push_back(c.potential);
    const Scene scene = load_scene(test::source_path(c.scene), set);
    const std::shared_ptr<const Potential> model = make_scene_potential(scene, registry);
    constexpr int kStates = 6;
    // Reference: each state with a fresh workspace that first saw the initial state (where a
    // model that chooses makes its choice), on this thread.
    std::vector<Forces> reference(kStates);
    for (int k = 0; k < kStates; ++k) {
      PotentialEvaluator evaluate(model);
      Forces f;
      f.resize(scene.system);
      evaluate(scene.initial, f);
      reference[static_cast<std::size_t>(k)].resize(scene.system);
      evaluate(perturbed(scene, k), reference[static_cast<std::size_t>(k)]);
    }
    // Threads: one workspace each, all states in a different order, three rounds.
    std::vector<int> mismatches(kThreads, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        PotentialEvaluator evaluate(model);
        Forces f;
        f.resize(scene.system);
        evaluate(scene.initial, f);
        for (int round = 0; round < 3; ++round)
          for (int j = 0; j < kStates; ++j) {
            const int k = (j + t) % kStates;
            evaluate(perturbed(scene, k), f);
            if (!same(f, reference[static_cast<std::size_t>(k)])) ++mismatches[static_cast<std::size_t>(t)];
          }
      });
    for (auto& th : threads) th.join();
    for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[static_cast<std::size_t>(t)], 0) << c.name << ", thread " << t;
  }
}

class Last final : public Observer {
 public:
  void observe(const State& state, const Forces& forces, bool) override { last = state, U = forces.U; }
  State last;
  double U = 0;
};

// Whole runs: integrators on several threads share one potential (the tolerance-driven
// mutual-series, which chooses and watches per workspace) and reach the state, energy and
// pair models a run on its own reaches.
TEST(Workspace, IntegratorsOnSeveralThreadsShareOneModel) {
  auto registry = test::bundled_plugins();
  const Scene scene = load_scene(test::source_path("examples/kw4-heliocentric.yaml"), {"run.t_end=6240"});
  const std::shared_ptr<const Potential> model = make_scene_potential(scene, registry);
  const Schedule schedule{scene.run.t_end, scene.run.output_every, {}, {}};
  auto run = [&](Last& out, std::vector<PairModel>& pairs) {
    auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, model, scene.integrator.params);
    State s = scene.initial;
    advance(*integrator, *model, scene.system, s, schedule, out);
    ASSERT_NE(integrator->potential_evaluator(), nullptr);
    pairs = integrator->potential_evaluator()->pair_models();
  };
  Last alone;
  std::vector<PairModel> alone_pairs;
  run(alone, alone_pairs);
  ASSERT_EQ(alone_pairs.size(), 3u);
  std::vector<Last> results(kThreads);
  std::vector<std::vector<PairModel>> pairs(kThreads);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < kThreads; ++t) threads.emplace_back([&, t] { run(results[t], pairs[t]); });
  for (auto& th : threads) th.join();
  for (std::size_t t = 0; t < kThreads; ++t) {
    EXPECT_EQ(results[t].last.x, alone.last.x) << "thread " << t;
    EXPECT_EQ(results[t].last.Pi, alone.last.Pi) << "thread " << t;
    EXPECT_EQ(results[t].U, alone.U) << "thread " << t;
    ASSERT_EQ(pairs[t].size(), alone_pairs.size());
    for (std::size_t p = 0; p < alone_pairs.size(); ++p) EXPECT_EQ(pairs[t][p].order, alone_pairs[p].order);
  }
}

TEST(Workspace, AnotherPotentialsWorkspaceIsRefusedByName) {
  auto registry = test::bundled_plugins();
  const Scene kw4 = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"));
  const Scene dumbbells = test::dumbbell_scene();
  const auto series = make_scene_potential(kw4, registry);
  const auto cluster = make_scene_potential(dumbbells, registry);
  const auto wrong = cluster->make_workspace();
  Forces f;
  f.resize(kw4.system);
  try {
    series->evaluate(kw4.initial, f, *wrong);
    FAIL() << "a sphere-cluster workspace was accepted by mutual-series";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mutual-series: evaluated with a workspace another potential made"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
