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
// The dumbbell scene with its LGVI on sphere-cluster, as the step benchmarks use it.
struct DumbbellLgvi {
  Scene scene = test::dumbbell_scene();
  PluginRegistry registry = test::bundled_plugins();
  std::shared_ptr<const Potential> potential = registry.make_potential("sphere-cluster", scene.system, Params());
  std::shared_ptr<Integrator> lgvi = registry.make_integrator("lgvi", scene.system, potential, scene.integrator.params);
  double h = scene.integrator.params.at("step").as_double();
};

void BM_LgviDumbbellStep(benchmark::State& st) {
  DumbbellLgvi d;
  auto& [scene, registry, potential, lgvi, h] = d;
  Null null;
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

// The same steps carrying a tangent: the 24 × 24 state-transition matrix (Arg 24; docs/equations.md
// §21), or one deviation vector (Arg 1; run.chaos, §23). Either way one analytic force Jacobian
// and the implicit equation's derivative per step on top, and the tangent map's matrix products.
void BM_LgviDumbbellStepWithTangent(benchmark::State& st) {
  DumbbellLgvi d;
  auto& [scene, registry, potential, lgvi, h] = d;
  Null null;
  const auto N = State::tangent_rows(scene.system);
  const auto columns = static_cast<Eigen::Index>(st.range(0));
  for (auto _ : st) {
    State s = scene.initial;
    s.tangent = Eigen::MatrixXd::Identity(N, columns);
    advance(*lgvi, *potential, scene.system, s, {1000 * h, 1000 * h}, null);
    benchmark::DoNotOptimize(s.tangent.data());
  }
  st.SetLabel(columns == N ? "stm" : "deviation vector");
  st.SetItemsProcessed(st.iterations() * 1000);
  st.counters["ns_per_step"] = benchmark::Counter(
      static_cast<double>(st.iterations()) * 1000, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_LgviDumbbellStepWithTangent)->Arg(24)->Arg(1)->Unit(benchmark::kMicrosecond);

// KW4 as two ellipsoids, mutual-series order 4, with and without the STM: the series has no
// analytic Jacobian yet, so each step with the STM differences it (2 × 12 more evaluations).
void BM_LgviKw4Step(benchmark::State& st) {
  const Scene scene = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"));
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("mutual-series", scene.system, scene.potentials[0].params);
  auto lgvi = registry.make_integrator("lgvi", scene.system, potential, scene.integrator.params);
  Null null;
  const double h = scene.integrator.params.at("step").as_double();
  const auto N = State::tangent_rows(scene.system);
  const bool stm = st.range(0) != 0;
  for (auto _ : st) {
    State s = scene.initial;
    if (stm) s.tangent = Eigen::MatrixXd::Identity(N, N);
    advance(*lgvi, *potential, scene.system, s, {100 * h, 100 * h}, null);
    benchmark::DoNotOptimize(s.x.data());
  }
  st.SetLabel(stm ? "with stm" : "plain");
  st.counters["ns_per_step"] = benchmark::Counter(
      static_cast<double>(st.iterations()) * 100, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_LgviKw4Step)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// rk (rk4, h = 2e-4) and cvode (adams, rtol 1e-10) on the dumbbells over 0.2 time units, plain
// and carrying the STM (the variational equations at every stage; CVODES sensitivities): the
// cost of a step with the STM against a plain one, per integrator (docs/derivatives.md).
void BM_ContinuousDumbbellSteps(benchmark::State& st) {
  const bool cvode = st.range(0) != 0, stm = st.range(1) != 0;
  const Scene scene = test::dumbbell_scene(
      {cvode ? "integrator={plugin: cvode, method: adams, rtol: 1e-10, atol: 1e-12}" : "integrator={plugin: rk, method: rk4, step: 0.0002}"});
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("sphere-cluster", scene.system, Params());
  auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
  Null null;
  const auto N = State::tangent_rows(scene.system);
  for (auto _ : st) {
    State s = scene.initial;
    if (stm) s.tangent = Eigen::MatrixXd::Identity(N, N);
    advance(*integrator, *potential, scene.system, s, {0.2, 0.2}, null);
    benchmark::DoNotOptimize(s.x.data());
  }
  // The integrator's counters add up over the runs (start() carries them on).
  const double steps = static_cast<double>(integrator->work().steps) / static_cast<double>(st.iterations());
  st.SetLabel(std::string(cvode ? "cvode adams" : "rk4") + (stm ? ", with stm" : ", plain"));
  st.counters["steps"] = steps;
  st.counters["ns_per_step"] = benchmark::Counter(static_cast<double>(st.iterations()) * steps,
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ContinuousDumbbellSteps)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond);

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
