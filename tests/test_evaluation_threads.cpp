// Threads inside one evaluation (noether/evaluation_threads.hpp; docs/user-guide.md, "Threads"):
// mutual-series evaluates its pairs on several threads and sums them in pair order, so a run is
// the same bit for bit for any number of threads — forces, force Jacobians, whole runs and their
// state-transition matrices; and an error is the one the single-threaded evaluation gives.
// Radiation does the same with blocks of facets.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/force_jacobian.hpp>
#include <noether/lie.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

using namespace noether;

namespace {

Forces evaluate(const Scene& scene, const Potential& potential, int threads) {
  const EvaluationThreads in_scope(threads);
  Forces f;
  f.resize(scene.system);
  auto workspace = potential.make_workspace();
  potential.evaluate(scene.initial, f, *workspace);
  return f;
}

bool bitwise_equal(const Forces& a, const Forces& b) {
  return a.U == b.U && a.f == b.f && a.M == b.M;  // Eigen's == compares every entry exactly
}

// The lattices the forces' and the force Jacobian's tests share, each with its potential: 27
// ellipsoids (351 pairs) at order 4, and 6 at a tolerance (the pairs' orders chosen and watched).
struct Lattice {
  std::string potential;
  Scene scene;
  std::shared_ptr<const Potential> model;
};
std::vector<Lattice> lattices(PluginRegistry& registry) {
  std::vector<Lattice> out;
  for (const auto& [K, potential] : {std::pair{27, "{plugin: mutual-series, order: 4}"},
                                     std::pair{6, "{plugin: mutual-series, tolerance: 1e-4, min_separation: 3}"}}) {
    Scene scene = test::ellipsoid_lattice_scene(K, potential);
    auto model = registry.make_potential("mutual-series", scene.system, scene.potentials[0].params);
    out.push_back({potential, std::move(scene), std::move(model)});
  }
  return out;
}

}  // namespace

TEST(EvaluationThreads, EveryIndexOnceAndTheLowestIndexsErrorRethrown) {
  for (const int threads : {1, 2, 3, 8}) {
    SCOPED_TRACE(threads);
    std::vector<std::atomic<int>> seen(101);
    parallel_for_each(seen.size(), threads, [&](std::size_t i, int thread) {
      EXPECT_GE(thread, 0);
      EXPECT_LT(thread, threads);
      ++seen[i];
    });
    for (const auto& s : seen) EXPECT_EQ(s.load(), 1);
    try {
      parallel_for_each(50, threads, [](std::size_t i, int) {
        if (i == 17 || i == 18 || i == 40) throw std::runtime_error("index " + std::to_string(i));
      });
      FAIL() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "index 17");
    }
  }
  EXPECT_EQ(evaluation_threads(), 1);
  {
    const EvaluationThreads outer(4);
    EXPECT_EQ(evaluation_threads(), 4);
    {
      const EvaluationThreads inner(0);  // below 1 counts as 1
      EXPECT_EQ(evaluation_threads(), 1);
    }
    EXPECT_EQ(evaluation_threads(), 4);
  }
  EXPECT_EQ(evaluation_threads(), 1);
}

// The lattices' forces and moments with 2, 3 and 5 threads are the single thread's, bit for bit.
TEST(EvaluationThreads, MutualSeriesForcesAreTheSameForAnyNumberOfThreads) {
  auto registry = test::bundled_plugins();
  for (const Lattice& lattice : lattices(registry)) {
    SCOPED_TRACE(lattice.potential);
    const Forces one = evaluate(lattice.scene, *lattice.model, 1);
    EXPECT_GT(one.f.norm(), 0.0);
    for (const int threads : {2, 3, 5})
      EXPECT_TRUE(bitwise_equal(one, evaluate(lattice.scene, *lattice.model, threads))) << threads;
  }
}

// The force Jacobian K (docs/equations.md §25; what every step of a state-transition matrix needs)
// with 2, 3 and 5 threads is the single thread's, bit for bit, on the same lattices and on a swarm
// whose pairs' orders differ; and a run
// carrying the STM (LGVI, 10 steps of 8 ellipsoids at order 4) ends with the same matrix.
TEST(EvaluationThreads, MutualSeriesForceJacobianIsTheSameForAnyNumberOfThreads) {
  auto registry = test::bundled_plugins();
  for (const Lattice& lattice : lattices(registry)) {
    SCOPED_TRACE(lattice.potential);
    auto jacobian = [&](int threads) {
      const EvaluationThreads in_scope(threads);
      auto workspace = lattice.model->make_workspace();
      return force_jacobian(*lattice.model, lattice.scene.initial, *workspace);
    };
    const ForceJacobian one = jacobian(1);
    EXPECT_TRUE(one.analytic);
    EXPECT_GT(one.K.norm(), 0.0);
    for (const int threads : {2, 3, 5}) EXPECT_TRUE(one.K == jacobian(threads).K) << threads;
  }
  {  // a swarm whose pairs' orders differ (most pairs far): threads take uneven pairs
    const Scene swarm = test::satellite_swarm_scene(32, "{plugin: mutual-series, tolerance: 1e-8}");
    const auto model = registry.make_potential("mutual-series", swarm.system, swarm.potentials[0].params);
    auto workspace = model->make_workspace();
    const ForceJacobian one = force_jacobian(*model, swarm.initial, *workspace);
    int lowest = 99, highest = 0;
    for (const PairModel& m : model->pair_models(*workspace)) lowest = std::min(lowest, m.order), highest = std::max(highest, m.order);
    EXPECT_LT(lowest, highest);
    const EvaluationThreads in_scope(2);
    auto threaded = model->make_workspace();
    EXPECT_TRUE(one.K == force_jacobian(*model, swarm.initial, *threaded).K);
    EXPECT_TRUE(bitwise_equal(evaluate(swarm, *model, 1), evaluate(swarm, *model, 2)));
  }
  Scene scene = test::ellipsoid_lattice_scene(8, "{plugin: mutual-series, order: 4}", 3.0);
  scene.run.stm = true;
  std::vector<Eigen::MatrixXd> stm;
  for (const int threads : {1, 2}) {
    RunOptions options;
    options.threads = threads;
    stm.push_back(run_scene(scene, registry, options).final_state.tangent);
  }
  EXPECT_EQ(stm[0].rows(), State::tangent_rows(scene.system));
  EXPECT_TRUE(stm[0] == stm[1]);
}

// A whole run (LGVI, 10 steps of 8 ellipsoids) with --threads 1 and 2: every final coordinate and
// the summary's energy error bit for bit.
TEST(EvaluationThreads, ARunIsTheSameForAnyNumberOfThreads) {
  auto registry = test::bundled_plugins();
  const Scene scene = test::ellipsoid_lattice_scene(8, "{plugin: mutual-series, order: 2}", 3.0);
  std::vector<RunSummary> runs;
  for (const int threads : {1, 2}) {
    RunOptions options;
    options.threads = threads;
    runs.push_back(run_scene(scene, registry, options));
    EXPECT_EQ(runs.back().threads, threads);
  }
  const State &a = runs[0].final_state, &b = runs[1].final_state;
  EXPECT_EQ(a.t, b.t);
  EXPECT_TRUE(a.x == b.x && a.p == b.p && a.Pi == b.Pi);
  for (std::size_t k = 0; k < a.R.size(); ++k) EXPECT_TRUE(a.R[k] == b.R[k]) << k;
  EXPECT_EQ(runs[0].max_abs_energy_error, runs[1].max_abs_energy_error);
  EXPECT_GT(runs[0].max_abs_energy_error, 0.0);
}

// sphere-cluster's pairs the same way: 27 dumbbells (351 pairs) at 1, 2, 3 and 5 threads, bit for
// bit; two dumbbells (one pair) exactly as before the pairs were shared (the dumbbell scene's
// numbers in docs/ are unchanged); a collision is the first pair's for any number.
TEST(EvaluationThreads, SphereClusterForcesAreTheSameForAnyNumberOfThreads) {
  auto registry = test::bundled_plugins();
  const Scene scene = test::ellipsoid_lattice_scene(27, "{plugin: sphere-cluster}", 3.0, test::kLatticeDumbbell);
  const auto potential = registry.make_potential("sphere-cluster", scene.system, scene.potentials[0].params);
  const Forces one = evaluate(scene, *potential, 1);
  EXPECT_LT(one.U, 0.0);
  for (const int threads : {2, 3, 5}) EXPECT_TRUE(bitwise_equal(one, evaluate(scene, *potential, threads))) << threads;
  Scene crash = scene;  // bodies 4 and 9 in one place and attitude, then 2 and 20: pair (2, 20) comes first
  crash.initial.x.col(9) = crash.initial.x.col(4);
  crash.initial.R[9] = crash.initial.R[4];
  crash.initial.x.col(20) = crash.initial.x.col(2);
  crash.initial.R[20] = crash.initial.R[2];
  for (const int threads : {1, 2, 5}) {
    const EvaluationThreads in_scope(threads);
    Forces f;
    f.resize(crash.system);
    auto workspace = potential->make_workspace();
    try {
      potential->evaluate(crash.initial, f, *workspace);
      ADD_FAILURE() << "no collision at " << threads << " threads";
    } catch (const IntegrationError& e) {
      EXPECT_NE(std::string(e.what()).find("'e2' and one of body 'e20'"), std::string::npos) << e.what();
    }
  }
}

// Radiation on KW4 Alpha's radar shape (9168 facets, 144 blocks of 64) sums its blocks in order:
// its force and torque at 12 attitudes (the Sun on every side) on 1, 2, 3 and 5 threads, bit for
// bit; and 20 steps of the YORP scene with --threads 1 and 2 end in the same state and balance.
TEST(EvaluationThreads, RadiationIsTheSameForAnyNumberOfThreads) {
  auto registry = test::bundled_plugins();
  Scene scene = load_scene(test::source_path("examples/kw4-yorp.yaml"),
                           {"run.t_end=1200", "run.output_every=1200"});
  // With and without Alpha's shadows on itself (the occlusion map is made on the calling thread):
  // the same bits on any number of threads, and the shadows move the torque (Alpha is not convex).
  double moved = 0.0;
  std::vector<Forces> plain;
  for (const bool shadows : {false, true}) {
    Params params = scene.forces[0].params;
    params.set("self_shadowing", Params::scalar(shadows ? "true" : "false"));
    const auto force = registry.make_force("radiation", scene.system, params);
    for (int k = 0; k < 12; ++k) {
      State s = scene.initial;
      s.R[0] = exp_so3(Vec3(0.3 * k, 1.0 - 0.2 * k, 0.5 * k));
      std::vector<Forces> by_threads;
      for (const int threads : {1, 2, 3, 5}) {
        const EvaluationThreads in_scope(threads);
        Forces f;
        f.resize(scene.system);
        auto workspace = force->make_workspace();
        force->evaluate(s, f, *workspace);
        by_threads.push_back(f);
      }
      ASSERT_GT(by_threads[0].M.norm(), 0.0);
      for (const Forces& f : by_threads)
        EXPECT_TRUE(f.f == by_threads[0].f && f.M == by_threads[0].M) << "attitude " << k << ", shadows " << shadows;
      if (!shadows) plain.push_back(by_threads[0]);
      else moved = std::max(moved, (by_threads[0].M - plain[static_cast<std::size_t>(k)].M).norm() / plain[static_cast<std::size_t>(k)].M.norm());
    }
  }
  std::printf("Alpha's own shadows move the light's torque by up to %.2e of it over 12 attitudes\n", moved);
  EXPECT_GT(moved, 1e-6);
  std::vector<State> ends;
  for (const int threads : {1, 2}) {
    RunOptions options;
    options.threads = threads;
    ends.push_back(run_scene(scene, registry, options).final_state);
  }
  EXPECT_TRUE(ends[0].x == ends[1].x && ends[0].p == ends[1].p && ends[0].Pi == ends[1].Pi);
  EXPECT_TRUE(ends[0].R[0] == ends[1].R[0]);
  EXPECT_TRUE(ends[0].force_balance == ends[1].force_balance);
  EXPECT_GT(ends[0].force_balance.col(0).norm(), 0.0);
}

// Two ellipsoids at one position (pairs 0–3 and 1–5 of 8): every thread count reports the pair
// the single thread meets first.
TEST(EvaluationThreads, AnErrorIsTheOneOfTheFirstPair) {
  auto registry = test::bundled_plugins();
  Scene scene = test::ellipsoid_lattice_scene(8, "{plugin: mutual-series, order: 2}");
  scene.initial.x.col(3) = scene.initial.x.col(0);
  scene.initial.x.col(5) = scene.initial.x.col(1);
  const auto model = registry.make_potential("mutual-series", scene.system, scene.potentials[0].params);
  for (const int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    try {
      evaluate(scene, *model, threads);
      FAIL() << "no error";
    } catch (const IntegrationError& e) {
      EXPECT_NE(std::string(e.what()).find("bodies 'e0' and 'e3' are at the same position"), std::string::npos)
          << e.what();
    }
  }
}
