// Threads inside one evaluation (noether/evaluation_threads.hpp): mutual-series on K ellipsoids
// (K(K−1)/2 pairs, tests/test_support.hpp's lattice), at orders 2 and 4, on 1 and 2 threads —
// the cost of an evaluation and of a force Jacobian, per pair, and the speed-up; and a swarm of
// satellites whose pairs are mostly far, at a tolerance against the fixed order it needs
// (docs/numerical-results.md, "Threads"); sphere-cluster's pairs; and radiation on a radar shape,
// facet blocks on threads.
// Run: build/release/bin/noether_benchmarks --benchmark_filter='MutualSeries(Pairs|Swarm)|SphereClusterPairs|Radiation'
#include <noether/force_jacobian.hpp>
#include "test_support.hpp"

#include <noether/evaluation_threads.hpp>
#include <noether/lie.hpp>
#include <noether/scene.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>

using namespace noether;

namespace {

// The counters every benchmark here reports: the pairs of K bodies, and the time per pair.
void count_pairs(benchmark::State& st, int K) {
  const double pairs = K * (K - 1) / 2.0;
  st.counters["pairs"] = pairs;
  st.counters["ns_per_pair"] = benchmark::Counter(static_cast<double>(st.iterations()) * pairs,
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// One evaluation of a lattice scene's potential (its plugin), on `threads` threads, per iteration.
void evaluate_lattice(benchmark::State& st, const Scene& scene, const std::string& plugin, int threads) {
  auto registry = test::bundled_plugins();
  const auto potential = registry.make_potential(plugin, scene.system, scene.potentials[0].params);
  auto workspace = potential->make_workspace();
  Forces f;
  f.resize(scene.system);
  const EvaluationThreads in_scope(threads);
  for (auto _ : st) {
    potential->evaluate(scene.initial, f, *workspace);
    benchmark::DoNotOptimize(f.U);
  }
  count_pairs(st, static_cast<int>(scene.system.size()));
}

// Args: K, order, threads.
void BM_MutualSeriesPairs(benchmark::State& st) {
  const int K = static_cast<int>(st.range(0)), order = static_cast<int>(st.range(1)), threads = static_cast<int>(st.range(2));
  evaluate_lattice(st, test::ellipsoid_lattice_scene(K, "{plugin: mutual-series, order: " + std::to_string(order) + "}"),
                   "mutual-series", threads);
}
BENCHMARK(BM_MutualSeriesPairs)
    ->ArgsProduct({{2, 8, 32, 128}, {2, 4}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// The force Jacobian K (docs/equations.md §25) of the same lattices. Args: K, order, threads.
void BM_MutualSeriesPairsJacobian(benchmark::State& st) {
  const int K = static_cast<int>(st.range(0)), order = static_cast<int>(st.range(1)), threads = static_cast<int>(st.range(2));
  const Scene scene = test::ellipsoid_lattice_scene(K, "{plugin: mutual-series, order: " + std::to_string(order) + "}");
  auto registry = test::bundled_plugins();
  const auto potential = registry.make_potential("mutual-series", scene.system, scene.potentials[0].params);
  auto workspace = potential->make_workspace();
  const EvaluationThreads in_scope(threads);
  for (auto _ : st) {
    const ForceJacobian J = force_jacobian(*potential, scene.initial, *workspace);
    benchmark::DoNotOptimize(J.K.data());
  }
  count_pairs(st, K);
}
BENCHMARK(BM_MutualSeriesPairsJacobian)
    ->ArgsProduct({{8, 32, 128}, {2, 4}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// A primary and K − 1 satellites (test::satellite_swarm_scene): each pair's order chosen from
// `tolerance: 1e-8` (mode 0), or every pair at the highest order that choice gave (mode 1: what a
// fixed order must be to meet the tolerance everywhere). Args: K, mode, threads. Counters: the
// pairs' mean and largest order.
void BM_MutualSeriesSwarm(benchmark::State& st) {
  const int K = static_cast<int>(st.range(0)), mode = static_cast<int>(st.range(1)), threads = static_cast<int>(st.range(2));
  auto registry = test::bundled_plugins();
  const Scene chosen = test::satellite_swarm_scene(K, "{plugin: mutual-series, tolerance: 1e-8}");
  const auto tolerant = registry.make_potential("mutual-series", chosen.system, chosen.potentials[0].params);
  auto tolerant_workspace = tolerant->make_workspace();
  Forces f;
  f.resize(chosen.system);
  tolerant->evaluate(chosen.initial, f, *tolerant_workspace);  // chooses the orders
  double sum = 0.0;
  int largest = 0;
  const auto models = tolerant->pair_models(*tolerant_workspace);
  for (const PairModel& m : models) sum += m.order, largest = std::max(largest, m.order);
  const Scene fixed = test::satellite_swarm_scene(K, "{plugin: mutual-series, order: " + std::to_string(largest) + "}");
  const auto fixed_potential = registry.make_potential("mutual-series", fixed.system, fixed.potentials[0].params);
  const Potential& potential = mode == 0 ? *tolerant : *fixed_potential;
  auto workspace = mode == 0 ? std::move(tolerant_workspace) : fixed_potential->make_workspace();
  const EvaluationThreads in_scope(threads);
  for (auto _ : st) {
    potential.evaluate(chosen.initial, f, *workspace);
    benchmark::DoNotOptimize(f.U);
  }
  count_pairs(st, K);
  st.counters["mean_order"] = mode == 0 ? sum / static_cast<double>(models.size()) : largest;
  st.counters["max_order"] = largest;
}
BENCHMARK(BM_MutualSeriesSwarm)
    ->ArgsProduct({{8, 32, 128}, {0, 1}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// sphere-cluster on K dumbbells on the same lattice (4 point pairs a body pair). Args: K, threads.
void BM_SphereClusterPairs(benchmark::State& st) {
  const int K = static_cast<int>(st.range(0)), threads = static_cast<int>(st.range(1));
  evaluate_lattice(st, test::ellipsoid_lattice_scene(K, "{plugin: sphere-cluster}", 4.0, test::kLatticeDumbbell),
                   "sphere-cluster", threads);
}
BENCHMARK(BM_SphereClusterPairs)->ArgsProduct({{8, 32, 128}, {1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();

// Radiation on KW4 Alpha's radar shape (9168 facets; examples/kw4-yorp.yaml): one evaluation of
// the force and torque, on 1 and 2 threads (blocks of 64 facets), without and with its shadows on
// itself (a ray from each lit facet through the hierarchy of its facets). Args: threads, shadows.
void BM_RadiationKw4Alpha(benchmark::State& st) {
  const int threads = static_cast<int>(st.range(0));
  const Scene scene = load_scene(test::source_path("examples/kw4-yorp.yaml"),
                                 {st.range(1) ? "forces.0.self_shadowing=true" : "forces.0.self_shadowing=false"});
  auto registry = test::bundled_plugins();
  const auto force = registry.make_force("radiation", scene.system, scene.forces[0].params);
  auto workspace = force->make_workspace();
  Forces f;
  f.resize(scene.system);
  State s = scene.initial;
  const EvaluationThreads in_scope(threads);
  std::int64_t k = 0;
  for (auto _ : st) {
    s.R[0] = exp_so3(Vec3(0.0, 0.0, 1e-3 * static_cast<double>(k++)));  // the Sun seen from another side
    force->evaluate(s, f, *workspace);
    benchmark::DoNotOptimize(f.M.data());
  }
  st.counters["ns_per_facet"] = benchmark::Counter(static_cast<double>(st.iterations()) * 9168.0,
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RadiationKw4Alpha)->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
