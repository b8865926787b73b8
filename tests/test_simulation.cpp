// Simulation: a run held open. Integrating in several calls is integrating in one; a state set
// between calls is checked; save() and load() continue bit for bit (docs/python.md), as
// --resume does (tests/cli/resume.py).
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <unistd.h>

using namespace noether;

namespace {

bool same_bits(const State& a, const State& b) {
  if (a.x != b.x || a.p != b.p || a.Pi != b.Pi || a.R.size() != b.R.size()) return false;
  for (std::size_t k = 0; k < a.R.size(); ++k)
    if (a.R[k] != b.R[k]) return false;
  return true;
}

// The scene run whole to t_end, and run to t_save, saved, loaded (a fresh simulation: its own
// potential, integrator and workspaces) and continued to t_end.
struct SavedAndContinued {
  std::unique_ptr<Simulation> whole, continued;
};
SavedAndContinued run_whole_and_continued(const Scene& scene, PluginRegistry& registry, double t_save, double t_end,
                                          const std::filesystem::path& file) {
  SavedAndContinued r;
  r.whole = std::make_unique<Simulation>(scene, registry);
  r.whole->integrate(t_end);
  {
    Simulation first(scene, registry);
    first.integrate(t_save);
    first.save(file);
  }
  r.continued = Simulation::load(file, registry);
  EXPECT_EQ(r.continued->time(), t_save);
  r.continued->integrate(t_end);
  return r;
}

const char* const kIntegrators[] = {"{plugin: lgvi, step: 0.0002}", "{plugin: lgvi, step: 0.0002, order: 4}",
                                    "{plugin: lgvi, step: 0.0002, frame: relative}",
                                    "{plugin: lgvi, step: 0.0002, form: lagrangian}",
                                    "{plugin: rk, method: rk4, step: 0.0002}"};

}  // namespace

// Every fixed-step form: stopping at any step and going on is the uninterrupted run, bit for bit.
TEST(Simulation, CallsInPiecesAreOneCall) {
  PluginRegistry registry;
  for (const char* integrator : kIntegrators) {
    const Scene scene = test::dumbbell_scene({std::string("integrator=") + integrator, "run.t_end=1"});
    Simulation whole(scene, registry);
    whole.integrate(1.0);
    Simulation pieces(scene, registry);
    for (double t : {0.0102, 0.5, 0.7776, 1.0}) pieces.integrate(t);
    EXPECT_TRUE(same_bits(whole.state(), pieces.state())) << integrator;
    EXPECT_EQ(whole.summary().max_abs_energy_error, pieces.summary().max_abs_energy_error) << integrator;
    EXPECT_EQ(whole.summary().work.steps, pieces.summary().work.steps) << integrator;
  }
}

TEST(Simulation, SaveAndLoadContinueBitwise) {
  PluginRegistry registry;
  const auto file = std::filesystem::temp_directory_path() / ("noether-save-" + std::to_string(::getpid()) + ".h5");
  // Every fixed-step form: the inertial Hamiltonian LGVI and rk4 continue from the state, the
  // relative-frame and Lagrangian forms from their own variables (Integrator::checkpoint).
  for (const char* integrator : kIntegrators) {
    const Scene scene = test::dumbbell_scene({std::string("integrator=") + integrator, "run.t_end=1"});
    const auto [whole, second] = run_whole_and_continued(scene, registry, 0.4002, 1.0, file);
    EXPECT_TRUE(same_bits(whole->state(), second->state())) << integrator;
    const RunSummary a = whole->summary(), b = second->summary();
    EXPECT_EQ(a.max_abs_energy_error, b.max_abs_energy_error);
    EXPECT_EQ(a.max_rel_angular_momentum_error, b.max_rel_angular_momentum_error);
    EXPECT_EQ(a.min_distance, b.min_distance);
    EXPECT_EQ(a.work.steps, b.work.steps);
    EXPECT_EQ(a.frames + 1, b.frames);  // 0.4002 is not an output time
  }
  std::filesystem::remove(file);
}

// The exact model evaluates from the configuration alone (docs/equations.md §14, §37): a run
// saved and loaded — a fresh potential, none of the first one's quadrature levels or degrees —
// continues bit for bit, by the quadrature and by the expansion (KW4's ellipsoids: the
// expansion asked for, as their field is an ellipsoid's).
TEST(Simulation, TheExactModelContinuesBitwise) {
  PluginRegistry registry;
  const auto file = std::filesystem::temp_directory_path() / ("noether-exact-" + std::to_string(::getpid()) + ".h5");
  for (const char* method : {"quadrature", "expansion"}) {
    const Scene scene = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"),
                                   {std::string("potential={plugin: mutual-exact, method: ") + method + "}",
                                    "run.t_end=1200", "run.output_every=600"});
    const auto [whole, second] = run_whole_and_continued(scene, registry, 420.0, 1200.0, file);
    EXPECT_TRUE(same_bits(whole->state(), second->state())) << method;
    EXPECT_EQ(whole->summary().max_abs_energy_error, second->summary().max_abs_energy_error) << method;
  }
  std::filesystem::remove(file);
}

// Forces beyond the potential (docs/forces.md): the tidal spin-down saved mid-run and loaded —
// the LGVI of orders 2 and 4, its Lagrangian form (from x_k − x_{k−1} in its checkpoint) and rk4 —
// continues bit for bit — the state, the forces' balance (each force's work and momenta) and the
// verdict's errors, whose momentum scales include the largest momenta the forces exchanged (kept
// in the checkpoint). Loaded with a new output file, the balance starts again there.
TEST(Simulation, AForcedRunSavedAndLoadedContinuesBitwise) {
  PluginRegistry registry;
  const auto file = std::filesystem::temp_directory_path() / ("noether-forced-" + std::to_string(::getpid()) + ".h5");
  // The relative forms need the moon rigid: a small sphere's inertia.
  const char* rigid_moon = "bodies.moon.inertia=[1e-3, 1e-3, 1e-3]";
  for (const std::string integrator : {"integrator.order=2", "integrator.order=4", "integrator.form=lagrangian",
                                       "integrator={plugin: rk, method: rk4, step: 0.01}",
                                       "integrator={plugin: lgvi, step: 0.01, frame: relative}",
                                       "integrator={plugin: lgvi, step: 0.01, frame: relative, form: lagrangian}"}) {
    const bool relative = integrator.find("relative") != std::string::npos;
    const Scene scene = load_scene(test::source_path("examples/tidal-spin-down.yaml"),
                                   {integrator, "run.t_end=6", "run.output_every=1", relative ? rigid_moon : "G=1"});
    const auto [whole, second] = run_whole_and_continued(scene, registry, 2.37, 6.0, file);
    EXPECT_TRUE(same_bits(whole->state(), second->state())) << integrator;
    EXPECT_EQ(whole->state().force_balance, second->state().force_balance) << integrator;
    const RunSummary a = whole->summary(), b = second->summary();
    ASSERT_EQ(b.forces.size(), 1u);
    EXPECT_NE(a.forces[0].work, 0.0);
    EXPECT_EQ(a.forces[0].work, b.forces[0].work) << integrator;
    EXPECT_EQ(a.forces[0].angular_momentum, b.forces[0].angular_momentum) << integrator;
    EXPECT_EQ(a.max_abs_energy_error, b.max_abs_energy_error) << integrator;
    EXPECT_EQ(a.max_rel_linear_momentum_error, b.max_rel_linear_momentum_error) << integrator;
    EXPECT_EQ(a.max_rel_angular_momentum_error, b.max_rel_angular_momentum_error) << integrator;
  }
  // A new output file: its summary and the forces' balance start at the loaded state; E − W is
  // conserved from there to the integrator's error (the whole run's is ~1e-8 here).
  const auto out = std::filesystem::temp_directory_path() / ("noether-forced-out-" + std::to_string(::getpid()) + ".h5");
  RunOptions options;
  options.output = out;
  options.overwrite = true;
  auto again = Simulation::load(file, registry, options);
  EXPECT_TRUE(again->state().force_balance.isZero(0.0));
  again->integrate(6.0);
  EXPECT_NE(again->summary().forces[0].work, 0.0);
  EXPECT_LT(again->summary().max_abs_energy_error, 1e-6 * std::abs(again->summary().initial.energy));
  again.reset();
  std::filesystem::remove(out);
  std::filesystem::remove(file);
}

TEST(Simulation, SetStateIsChecked) {
  PluginRegistry registry;
  Simulation sim(test::dumbbell_scene({"run.t_end=1"}), registry);
  State s = sim.state();
  s.R[1] = 2.0 * Mat3::Identity();
  EXPECT_THROW(sim.set_state(s), Error);
  s = sim.state();
  s.R[0] = -Mat3::Identity();  // orthogonal, but a reflection
  EXPECT_THROW(sim.set_state(s), Error);
  s = sim.state();
  s.x(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(sim.set_state(s), Error);
  s = sim.state();
  s.x.resize(3, 3);
  EXPECT_THROW(sim.set_state(s), Error);
  EXPECT_THROW(sim.integrate(0.0), Error);  // not after the current time
  EXPECT_THROW(sim.integrate(0.00013), SceneError);  // off the step grid
}
