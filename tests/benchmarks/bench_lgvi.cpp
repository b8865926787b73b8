// Micro-benchmarks: one LGVI step on the dumbbell scene, its parts, and a point-mass step.
// Run: build/release/bin/noether_benchmarks   (results in docs/numerical-results.md)
#include "test_support.hpp"

#include <noether/discrete_attitude.hpp>

#include <benchmark/benchmark.h>

using namespace noether;

namespace {

struct Null final : Observer {
  void observe(const State&, const Forces&, bool) override {}
};

// ns per LGVI step: integrate 1000 steps per iteration (one potential evaluation each).
void BM_LgviDumbbellStep(benchmark::State& st) {
  const Scene scene = test::dumbbell_scene();
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("sphere-cluster", scene.system, Params());
  auto lgvi = registry.make_integrator("lgvi", scene.system, potential, scene.integrator.params);
  Null null;
  const double h = scene.integrator.params.at("step").as_double();
  for (auto _ : st) {
    State s = scene.initial;
    advance(*lgvi, *potential, scene.system, s, {1000 * h, 1000 * h}, null);
    benchmark::DoNotOptimize(s.x.data());
  }
  st.SetItemsProcessed(st.iterations() * 1000);
  st.counters["ns_per_step"] = benchmark::Counter(
      static_cast<double>(st.iterations()) * 1000, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["newton_per_step"] =
      static_cast<double>(lgvi->work().newton_iterations) / static_cast<double>(lgvi->work().steps);
}
BENCHMARK(BM_LgviDumbbellStep)->Unit(benchmark::kMicrosecond);

void BM_SphereClusterDumbbells(benchmark::State& st) {
  const Scene scene = test::dumbbell_scene();
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("sphere-cluster", scene.system, Params());
  noether::PotentialEvaluator evaluate(potential);  // one workspace for the loop
  Forces f;
  f.resize(scene.system);
  for (auto _ : st) {
    evaluate(scene.initial, f);
    benchmark::DoNotOptimize(f.U);
  }
}
BENCHMARK(BM_SphereClusterDumbbells);

void BM_DiscreteAttitudeSolve(benchmark::State& st) {
  const Mat3 J = Vec3(0.0004, 0.0238, 0.0238).asDiagonal();
  const Vec3 g = 2e-4 * J * Vec3(0.3, -0.2, 9.0);
  for (auto _ : st) benchmark::DoNotOptimize(solve_discrete_attitude(g, J));
}
BENCHMARK(BM_DiscreteAttitudeSolve);

}  // namespace
