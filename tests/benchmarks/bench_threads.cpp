// Threads inside one evaluation (noether/evaluation_threads.hpp): mutual-series on K ellipsoids
// (K(K−1)/2 pairs, tests/test_support.hpp's lattice), at orders 2 and 4, on 1 and 2 threads —
// the cost of an evaluation, per pair, and the speed-up (docs/numerical-results.md, "Threads").
// Run: build/release/bin/noether_benchmarks --benchmark_filter=MutualSeriesPairs
#include "test_support.hpp"

#include <noether/evaluation_threads.hpp>

#include <benchmark/benchmark.h>

using namespace noether;

namespace {

// Args: K, order, threads.
void BM_MutualSeriesPairs(benchmark::State& st) {
  const int K = static_cast<int>(st.range(0)), order = static_cast<int>(st.range(1)), threads = static_cast<int>(st.range(2));
  const Scene scene = test::ellipsoid_lattice_scene(K, "{plugin: mutual-series, order: " + std::to_string(order) + "}");
  auto registry = test::bundled_plugins();
  const auto potential = registry.make_potential("mutual-series", scene.system, scene.potentials[0].params);
  auto workspace = potential->make_workspace();
  Forces f;
  f.resize(scene.system);
  const EvaluationThreads in_scope(threads);
  for (auto _ : st) {
    potential->evaluate(scene.initial, f, *workspace);
    benchmark::DoNotOptimize(f.U);
  }
  const double pairs = K * (K - 1) / 2.0;
  st.counters["pairs"] = pairs;
  st.counters["ns_per_pair"] = benchmark::Counter(static_cast<double>(st.iterations()) * pairs,
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_MutualSeriesPairs)
    ->ArgsProduct({{2, 8, 32, 128}, {2, 4}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace
