// Micro-benchmarks of the mutual potential of real shapes on 1999 KW4 (Hou et al. 2017
// initial conditions): one evaluation of the mutual-series plugin (integrals of Beta rotated
// into Alpha's frame, U, force, both torques, written into Forces) at each order, the set-up
// of the inertia integrals of the 9168-face primary per order, and the exact reference.
// Run: build/release/bin/noether_benchmarks --benchmark_filter=Mutual
// (results in docs/real-shapes.md)
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/exact_mutual.hpp>
#include <noether/mutual_series.hpp>
#include <noether/simulation.hpp>

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <optional>
#include <string>

using namespace noether;

namespace {

// The scene's potential evaluated once per iteration, with one workspace for the loop, each time
// at a new configuration (nothing is cached).
void evaluate_repeatedly(benchmark::State& st, const Scene& scene, noether::PotentialEvaluator& evaluate) {
  Forces f;
  f.resize(scene.system);
  State s = scene.initial;
  for (auto _ : st) {
    evaluate(s, f);
    benchmark::DoNotOptimize(f.U);
    s.x(0, 1) += 1e-9;
  }
}

void evaluate_repeatedly(benchmark::State& st, const Scene& scene) {
  auto registry = test::bundled_plugins();
  noether::PotentialEvaluator evaluate(make_scene_potential(scene, registry));
  evaluate_repeatedly(st, scene, evaluate);
}

// A scene with a potential override, its potential and its evaluator, kept for the process:
// Google Benchmark calls a benchmark several times (to size its iterations, once per
// repetition), and a set-up — the radar meshes' integrals to the order a tolerance may pick and
// the choice, or Alpha's 9168 facets integrated to degree 24 — takes seconds, the evaluation
// microseconds. `met` is false where making the potential was refused (a tolerance no order
// meets).
struct EvaluatorSetUp {
  PluginRegistry registry = test::bundled_plugins();
  Scene scene;
  std::optional<noether::PotentialEvaluator> evaluate;
  bool met = true;
};

EvaluatorSetUp& evaluator_set_up(const std::string& scene_file, const std::string& potential) {
  static std::map<std::string, std::unique_ptr<EvaluatorSetUp>> cache;
  auto& entry = cache[scene_file + " " + potential];
  if (entry) return *entry;
  entry = std::make_unique<EvaluatorSetUp>();
  entry->scene = load_scene(test::source_path(scene_file), {potential});
  try {  // a tolerance's choice, made where the scene starts
    entry->evaluate.emplace(make_scene_potential(entry->scene, entry->registry));  // one workspace for the loop
  } catch (const Error&) {
    entry->met = false;
  }
  return *entry;
}

void BM_MutualSeriesKw4(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  const Scene scene = load_scene(test::source_path("examples/kw4-polyhedra.yaml"),
                                 {"potential.order=" + std::to_string(N)});
  evaluate_repeatedly(st, scene);
}
BENCHMARK(BM_MutualSeriesKw4)->DenseRange(2, 12, 1)->Unit(benchmark::kMicrosecond);

// MutualSeries::jacobian alone on KW4's integrals (the terms and their derivatives (25.1)–(25.5),
// what a force Jacobian or an STM step costs per pair), at a turning configuration.
void BM_MutualSeriesJacobianKw4(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  const Scene scene = load_scene(test::source_path("examples/kw4-polyhedra.yaml"));
  const InertiaIntegrals TA = scene.system.body(0).solid->integrals(N), TB = scene.system.body(1).solid->integrals(N);
  MutualSeries series(N);
  MutualJacobian J;
  Vec3 R(1180.0, 620.0, -140.0);
  const Mat3 C = Eigen::AngleAxisd(0.7, Vec3(0.3, -0.4, 1).normalized()).toRotationMatrix();
  for (auto _ : st) {
    const MutualTerms t = series.jacobian(scene.system.G(), TA, TB, R, C, J);
    benchmark::DoNotOptimize(t.U);
    benchmark::DoNotOptimize(J.tauB_phi.data());
    R.x() += 1e-9;
  }
}
BENCHMARK(BM_MutualSeriesJacobianKw4)->Arg(2)->Arg(4)->Arg(8)->Arg(12)->Unit(benchmark::kMicrosecond);

void BM_MutualIntegralsKw4Primary(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  const Scene scene = load_scene(test::source_path("examples/kw4-polyhedra.yaml"));
  const Solid& alpha = *scene.system.body(0).solid;
  for (auto _ : st) benchmark::DoNotOptimize(alpha.integrals(N).T.data());
}
BENCHMARK(BM_MutualIntegralsKw4Primary)->Arg(2)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Arg(12)->Unit(benchmark::kMillisecond);

// One evaluation of mutual-exact at a scene's initial state (`method`: automatic or quadrature),
// after a first one (which builds what the pair keeps: quadrature rules, the expansion's
// moments and sphere); `first`: the first evaluation of a new potential, all of that included.
void BM_MutualExact(benchmark::State& st, const char* scene_file, const char* method, bool first) {
  const Scene scene = load_scene(test::source_path(scene_file),
                                 {std::string("potential={plugin: mutual-exact, method: ") + method + "}"});
  auto registry = test::bundled_plugins();
  Forces f;
  f.resize(scene.system);
  if (first) {
    for (auto _ : st) {
      noether::PotentialEvaluator evaluate(make_scene_potential(scene, registry));
      evaluate(scene.initial, f);
      benchmark::DoNotOptimize(f.U);
    }
    return;
  }
  auto potential = make_scene_potential(scene, registry);
  noether::PotentialEvaluator evaluate(potential);  // one workspace for the loop
  evaluate(scene.initial, f);
  for (auto _ : st) {
    evaluate(scene.initial, f);
    benchmark::DoNotOptimize(f.U);
  }
}
BENCHMARK_CAPTURE(BM_MutualExact, Octahedra, "examples/octahedra-hou.yaml", "automatic", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MutualExact, Kw4Ellipsoids, "examples/kw4-ellipsoids.yaml", "automatic", false)
    ->Unit(benchmark::kMillisecond);
// The radar meshes (Alpha 9168 faces, Beta 2292): the expansion (docs/equations.md §37), its
// first evaluation, and the quadrature it replaces there (about 9 s an evaluation: one iteration).
BENCHMARK_CAPTURE(BM_MutualExact, Kw4Polyhedra, "examples/kw4-polyhedra.yaml", "automatic", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MutualExact, Kw4PolyhedraFirst, "examples/kw4-polyhedra.yaml", "automatic", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MutualExact, Kw4PolyhedraQuadrature, "examples/kw4-polyhedra.yaml", "quadrature", false)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace

namespace {

// One evaluation of mutual-series with `tolerance: 1e-k` (k = the argument) after its choice,
// and the order it chose (docs/choosing-a-model.md).
void BM_MutualTolerance(benchmark::State& st, const char* scene_file) {
  EvaluatorSetUp& set_up = evaluator_set_up(
      scene_file, "potential={plugin: mutual-series, tolerance: 1e-" + std::to_string(st.range(0)) + ", max_order: 16}");
  if (!set_up.met) {
    st.SkipWithError("no order up to 16 meets the tolerance");
    return;
  }
  evaluate_repeatedly(st, set_up.scene, *set_up.evaluate);
  st.counters["order"] = set_up.evaluate->pair_models().at(0).order;
}
BENCHMARK_CAPTURE(BM_MutualTolerance, Kw4Polyhedra, "examples/kw4-polyhedra.yaml")->DenseRange(3, 10, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_MutualTolerance, Kw4Ellipsoids, "examples/kw4-ellipsoids.yaml")->DenseRange(3, 10, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_MutualTolerance, Didymos, "examples/didymos.yaml")->DenseRange(3, 10, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_MutualTolerance, OctahedraHou, "examples/octahedra-hou.yaml")->DenseRange(3, 10, 1)->Unit(benchmark::kMicrosecond);

}  // namespace

namespace {

// A spacecraft in KW4 Alpha's field (examples/kw4-alpha-orbiter.yaml): one evaluation of the
// spherical-harmonics potential (Cunningham's recursion, O(N²)) against the same field as the
// inertia-integral series of a point-mass pair (mutual-series), at degree/order N.
// Run: build/release/bin/noether_benchmarks --benchmark_filter=FieldOnSpacecraft
// (results in docs/gravity-fields.md)
void BM_FieldOnSpacecraft(benchmark::State& st, const char* model) {
  const int N = static_cast<int>(st.range(0));
  const std::string potential = std::string(model) == "spherical-harmonics"
                                    ? "potential={plugin: spherical-harmonics, body: alpha, degree: " + std::to_string(N) + "}"
                                    : "potential={plugin: mutual-series, order: " + std::to_string(N) + "}";
  EvaluatorSetUp& set_up = evaluator_set_up("examples/kw4-alpha-orbiter.yaml", potential);
  if (!set_up.met) {
    st.SkipWithError("the potential was refused");
    return;
  }
  evaluate_repeatedly(st, set_up.scene, *set_up.evaluate);
}
BENCHMARK_CAPTURE(BM_FieldOnSpacecraft, SphericalHarmonics, "spherical-harmonics")
    ->Arg(4)->Arg(8)->Arg(16)->Arg(24)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_FieldOnSpacecraft, MutualSeries, "mutual-series")->Arg(4)->Arg(8)->Arg(16)->Arg(24)->Unit(benchmark::kMicrosecond);

}  // namespace
