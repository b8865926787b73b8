// Reading a scene of N point masses (YAML → System + State, every check included): the cost
// should grow as N log N at most (the coincident-body check sorts; nothing compares all pairs).
#include <noether/scene.hpp>

#include <benchmark/benchmark.h>

#include <string>

namespace {

std::string lattice_scene(int n) {
  std::string text = "G: 1.0e-9\nbodies:\n";
  for (int i = 0; i < n; ++i)
    text += "  - {name: b" + std::to_string(i) + ", mass: 1.0, position: [" + std::to_string(i % 22) + ", " +
            std::to_string((i / 22) % 22) + ", " + std::to_string(i / 484) + "], velocity: [0, 0, 0]}\n";
  return text + "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 0.01}\n"
                "run: {t_end: 0.01, output_every: 0.01}\n";
}

void BM_ParseScene(benchmark::State& st) {
  const std::string text = lattice_scene(static_cast<int>(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(noether::parse_scene(text, "lattice.yaml"));
  st.SetComplexityN(st.range(0));
}
BENCHMARK(BM_ParseScene)->RangeMultiplier(10)->Range(100, 10000)->Unit(benchmark::kMillisecond)->Complexity();

}  // namespace
