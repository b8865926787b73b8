// Massless particles (host/include/noether/particles.hpp): the cost of one particle's Verlet step
// in the fields of the Didymos binary (examples/didymos.yaml: the Didymos_A polyhedron, 1996
// faces, and Dimorphos as an ellipsoid), for 1000 particles on circular orbits of random
// inclination, far from Didymos (where its series is used) or near it (its exact field), on 1
// and 2 threads (docs/numerical-results.md, "Particles").
// Run: build/release/bin/noether_benchmarks --benchmark_filter=ParticleSteps
#include "test_support.hpp"

#include <noether/particles.hpp>

#include <benchmark/benchmark.h>

#include <random>

using namespace noether;

namespace {

// Args: near (0: a in [1500, 3000] m, 1: a in [500, 1100] m), threads.
void BM_ParticleSteps(benchmark::State& st) {
  const bool near = st.range(0) != 0;
  const int threads = static_cast<int>(st.range(1));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> a(near ? 500.0 : 1500.0, near ? 1100.0 : 3000.0), angle(0.0, 360.0);
  std::string orbits;
  for (int k = 0; k < 1000; ++k)
    orbits += (k ? ", {a: " : "{a: ") + std::to_string(a(rng)) + ", i: " + std::to_string(angle(rng) / 2) +
              ", Omega: " + std::to_string(angle(rng)) + ", M: " + std::to_string(angle(rng)) + "}";
  const Scene scene = load_scene(test::source_path("examples/didymos.yaml"),
                                 {"particles={around: didymos, orbits: [" + orbits + "]}"});
  ParticleSwarm swarm(scene.system, scene.particles, scene.initial);
  State from = scene.initial, to = scene.initial;  // the bodies held still: the particles' cost alone
  for (auto _ : st) {
    to.t = from.t + 30.0;
    swarm.advance(from, to, threads);
    from.t = to.t;
  }
  st.counters["particle_steps"] = static_cast<double>(swarm.particle_steps());
  st.counters["ns_per_particle_step"] = benchmark::Counter(static_cast<double>(swarm.particle_steps()),
                                                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  std::size_t flying = 0;
  for (const auto& o : swarm.outcomes()) flying += o.fate == ParticleFate::in_flight;
  st.counters["in_flight"] = static_cast<double>(flying);
}
BENCHMARK(BM_ParticleSteps)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
