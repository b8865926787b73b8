// The driver's step against the kernel's (issue: the stepping loop at the kernel's speed): the
// dumbbell scene through Simulation::integrate, as `noether run` steps it — the run statistics
// and the verdict's running values at every output frame, progress every 16 steps — against
// BM_LgviDumbbellStep and BM_ContinuousDumbbellSteps (rk4, plain), which step the same scene
// through advance() with an observer that does nothing.
// Run: build/release/bin/noether_benchmarks --benchmark_filter='Dumbbell'
// (results in docs/numerical-results.md, "The driver's step").
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>

using namespace noether;

namespace {

// Arg 0: 0 the lgvi, 1 rk4 (both h = 2e-4, 100 000 steps). Arg 1: what the run does besides
// stepping — 0 nothing but the loop (one frame, at the end); 1 the loop watching two events at
// every step (a close approach and an escape, neither reached); 2 the scene's frames, every 50
// steps, to the run statistics (2 000 frames); 3 those frames written to an HDF5 file as well.
void BM_DriverDumbbellSteps(benchmark::State& st) {
  const bool rk4 = st.range(0) != 0;
  const int mode = static_cast<int>(st.range(1));
  std::vector<std::string> overrides;
  if (rk4) overrides.emplace_back("integrator={plugin: rk, method: rk4, step: 0.0002}");
  if (mode <= 1) overrides.emplace_back("run.output_every=20");
  if (mode == 1) overrides.insert(overrides.end(), {"run.close_approach=0.05", "run.escape={body: alpha, about: beta, distance: 100}"});
  const Scene scene = test::dumbbell_scene(overrides);
  auto registry = test::bundled_plugins();
  const auto file = std::filesystem::temp_directory_path() / "noether-bench-driver.h5";
  RunOptions options;
  options.progress = [](double, double, double) {};  // the driver's progress line, silenced
  if (mode == 3) {
    options.output = file;
    options.overwrite = true;
  }
  std::int64_t steps = 0;
  for (auto _ : st) {
    st.PauseTiming();
    auto run = std::make_unique<Simulation>(scene, registry, options);
    st.ResumeTiming();
    run->integrate(scene.run.t_end);
    st.PauseTiming();
    steps += run->summary().work.steps;
    run.reset();  // closing the file is not a step's cost
    st.ResumeTiming();
  }
  std::filesystem::remove(file);
  const char* what[] = {"the loop", "the loop and two events", "frames to the statistics", "frames to a file"};
  st.SetLabel(std::string(rk4 ? "rk4, " : "lgvi, ") + what[mode]);
  st.counters["ns_per_step"] = benchmark::Counter(static_cast<double>(steps),
                                                  benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_DriverDumbbellSteps)->ArgsProduct({{0, 1}, {0, 1, 2, 3}})->Unit(benchmark::kMillisecond);

}  // namespace
