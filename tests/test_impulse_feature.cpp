// The scene's impulses as a run feature (host/src/run/impulse_feature.hpp): a run with impulses
// — and with the tangent they make jump (the STM, ∂z/∂Δv, a mass's column, the chaos
// indicators' δ) — saved and loaded, or interrupted and resumed, anywhere: before an impulse,
// between its two frames (the state before it at its time, and after), after it, ends bit for
// bit where the uninterrupted run ends, and its summary moved its references by the same jumps.
#include "test_support.hpp"

#include "run/impulse_feature.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <unistd.h>

using namespace noether;
using test::registry;

namespace {

// The Kepler orbit with two impulses on the planet — inertial at t = 1.25, in the RTN frame of its
// orbit at t = 1.5 — carrying the STM, the chaos indicators and sensitivities to the first Δv and
// to the planet's mass; frames every 0.25.
Scene kicked(const std::string& integrator) {
  return test::kepler_scene({"impulses=[{body: planet, time: 1.25, delta_v: [0.01, -0.02, 0.005]}, "
                             "{body: planet, time: 1.5, delta_v: [0, 0.01, 0.002], frame: rtn}]",
                             "integrator=" + integrator, "run.output_every=0.25", "run.stm=true", "run.chaos=true",
                             "run.sensitivities=[impulses.0.delta_v, bodies.planet.mass]"});
}

bool same_bits(const State& a, const State& b) {
  return a.t == b.t && a.x == b.x && a.p == b.p && a.tangent == b.tangent;
}

void expect_same_summary(const RunSummary& a, const RunSummary& b, const std::string& what) {
  EXPECT_EQ(a.impulses, b.impulses) << what;
  EXPECT_EQ(a.impulse_energy, b.impulse_energy) << what;
  EXPECT_EQ(a.initial.energy, b.initial.energy) << what;
  EXPECT_EQ(a.max_abs_energy_error, b.max_abs_energy_error) << what;
  EXPECT_EQ(a.max_rel_linear_momentum_error, b.max_rel_linear_momentum_error) << what;
  EXPECT_EQ(a.max_rel_angular_momentum_error, b.max_rel_angular_momentum_error) << what;
  EXPECT_EQ(a.chaos_values.megno, b.chaos_values.megno) << what;
}

std::filesystem::path temporary(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("noether-" + name + "-" + std::to_string(::getpid()) + ".h5");
}

// Where a run is cut: integrate to t (applying an impulse at t, or stopping just before it).
struct Cut {
  double t;
  bool impulse_at_t;
  const char* what;
};
const Cut kCuts[] = {{1.0, true, "before the impulses"},
                     {1.25, false, "between the first impulse's two frames"},
                     {1.25, true, "just after the first impulse"},
                     {1.5, false, "between the second (RTN) impulse's two frames"},
                     {1.75, true, "after both"}};

const char* const kIntegrators[] = {"{plugin: lgvi, step: 0.001}", "{plugin: rk, method: rk4, step: 0.001}"};

// For every integrator and cut: the run continued by `continued` (cut, then saved and loaded, or
// resumed) and taken on to t = 2 ends on the uninterrupted run's bits and summary (and frames,
// when `same_frames`: a loaded run's summary counts the frame at a cut between output times).
void expect_continuations_bitwise(const char* how, bool same_frames,
                                  const std::function<std::unique_ptr<Simulation>(const Scene&, const Cut&)>& continued) {
  for (const char* integrator : kIntegrators) {
    const Scene scene = kicked(integrator);
    Simulation whole(scene, registry());
    whole.integrate(2.0);
    const RunSummary a = whole.finish();
    ASSERT_EQ(a.impulses, 2);
    for (const Cut& cut : kCuts) {
      const std::string what = std::string(integrator) + ", " + how + " " + cut.what;
      const std::unique_ptr<Simulation> sim = continued(scene, cut);
      EXPECT_EQ(sim->time(), cut.t) << what;
      sim->integrate(2.0);
      EXPECT_TRUE(same_bits(whole.state(), sim->state())) << what;
      const RunSummary b = sim->finish();
      expect_same_summary(a, b, what);
      if (same_frames) EXPECT_EQ(a.frames, b.frames) << what;
    }
  }
}

}  // namespace

// The count of applied impulses is its one field; a new segment counts those at or before its
// time; a count that does not fit the scene is refused.
TEST(ImpulseFeature, CountsTheAppliedImpulsesInTimeOrder) {
  const Scene scene = test::kepler_scene({"impulses=[{body: planet, time: 1.5, delta_v: [0, 0.01, 0]}, "
                                          "{body: planet, time: 1.25, delta_v: [0, 0.01, 0]}]"});
  detail::ImpulseFeature feature(scene.system, scene.impulses, scene.initial.t, 0.0);
  Eigen::MatrixXd none(12, 0);
  State s = scene.initial;
  feature.start(s, none);
  ASSERT_TRUE(feature.next());
  EXPECT_EQ(*feature.next(), 1u);  // the earlier one first
  s.t = 1.3;
  feature.start(s, none);
  EXPECT_EQ(*feature.next(), 0u);
  std::vector<double> field(1);
  feature.save(none, field);
  EXPECT_EQ(field[0], 1.0);
  feature.mark_applied();
  EXPECT_FALSE(feature.next());
  feature.restore(field, none);
  EXPECT_EQ(*feature.next(), 0u);
  EXPECT_THROW(feature.restore(std::vector<double>{3.0}, none), Error);
  EXPECT_THROW(feature.restore(std::vector<double>{0.5}, none), Error);
}

// Its jumps: the next impulse's time, the momentum jump m Δv (eq. 24.1) made where the run stands,
// counted once; a fixed step that does not divide an impulse's time from t0 is refused.
TEST(ImpulseFeature, JumpsAtEachImpulseByItsMomentum) {
  const Scene scene = test::kepler_scene({"impulses=[{body: planet, time: 1.5, delta_v: [0, 0.01, 0]}, "
                                          "{body: planet, time: 1.25, delta_v: [0.02, 0, 0]}]"});
  detail::ImpulseFeature feature(scene.system, scene.impulses, scene.initial.t, 0.0);
  Eigen::MatrixXd none(12, 0);
  State s = scene.initial;
  feature.start(s, none);
  ASSERT_TRUE(feature.next_jump());
  EXPECT_EQ(*feature.next_jump(), 1.25);
  const auto planet = static_cast<std::size_t>(scene.system.index_of("planet"));
  const double mass = scene.system.body(planet).mass;
  const State before = s;
  const std::vector<std::string> no_names;
  detail::StateJump at{s, no_names, nullptr, nullptr};
  feature.jump(at);
  EXPECT_EQ(s.p.col(static_cast<Eigen::Index>(planet)), before.p.col(static_cast<Eigen::Index>(planet)) + mass * Vec3(0.02, 0, 0));
  EXPECT_EQ(*feature.next_jump(), 1.5);
  std::vector<double> field(1);
  feature.save(none, field);
  EXPECT_EQ(feature.jumps_in(field), 1u);
  feature.jump(at);
  EXPECT_FALSE(feature.next_jump());
  EXPECT_THROW(detail::ImpulseFeature(scene.system, scene.impulses, scene.initial.t, 0.1 * std::sqrt(2.0)), SceneError);
  EXPECT_NO_THROW(detail::ImpulseFeature(scene.system, scene.impulses, scene.initial.t, 0.25));
}

// Saved anywhere and loaded: the uninterrupted run's bits, tangent and summary.
TEST(ImpulseFeature, SavedAndLoadedAnywhereContinuesBitwise) {
  const auto file = temporary("impulse-save");
  expect_continuations_bitwise("saved", false, [&file](const Scene& scene, const Cut& cut) {
    {
      Simulation first(scene, registry());
      first.integrate(cut.t, cut.impulse_at_t);
      first.save(file);
    }
    return Simulation::load(file, registry());
  });
  std::filesystem::remove(file);
}

// Interrupted anywhere (its file ends at the cut's frame, as a killed run's ends at its last
// complete one) and resumed: the uninterrupted run's bits and summary — its frames too — the
// impulses' jumps read back from the frames.
TEST(ImpulseFeature, ResumedAnywhereContinuesBitwise) {
  const auto file = temporary("impulse-resumed");
  expect_continuations_bitwise("resumed", true, [&file](const Scene& scene, const Cut& cut) {
    RunOptions options;
    options.output = file;
    options.overwrite = true;
    {
      Simulation first(scene, registry(), options);
      first.integrate(cut.t, cut.impulse_at_t);
    }
    return Simulation::resume(file, registry());
  });
  std::filesystem::remove(file);
}

// A run's output file (not a saved simulation) loaded anywhere: its frames replayed into the
// summary — the impulses' jumps found in them also when all of them lie before the file's last
// frame — and the run continued: the uninterrupted run's bits and summary.
TEST(ImpulseFeature, LoadedFromItsOutputFileAnywhereContinuesBitwise) {
  const auto file = temporary("impulse-loaded-file");
  expect_continuations_bitwise("loaded from its file", false, [&file](const Scene& scene, const Cut& cut) {
    RunOptions options;
    options.output = file;
    options.overwrite = true;
    {
      Simulation first(scene, registry(), options);
      first.integrate(cut.t, cut.impulse_at_t);
    }
    return Simulation::load(file, registry());
  });
  std::filesystem::remove(file);
}
