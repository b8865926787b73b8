// The scene's impulses as a run feature (host/src/run/impulse_feature.hpp): a run with impulses
// — and with the tangent they make jump (the STM, ∂z/∂Δv, a mass's column, the chaos
// indicators' δ) — saved and loaded, or interrupted and resumed, anywhere: before an impulse,
// between its two frames (the state before it at its time, and after), after it, ends bit for
// bit where the uninterrupted run ends, and its summary moved its references by the same jumps;
// an impulse that unbinds a bound pair is warned about with the numbers.
#include "test_support.hpp"

#include "run/impulse_feature.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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
  EXPECT_EQ(a.warnings, b.warnings) << what;
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

// DART's Δv typed in m/s instead of mm/s (issue 63: "sends Dimorphos away unbound, and the summary
// says trustworthy"): warned, with the speeds — the escape speed at the impulse against
// sqrt(2 G (m1 + m2) / r) from the state just before it — and the unit slip named; the Δv in
// mm/s is not warned about. A continuation (saved and loaded after the impulse, or resumed)
// keeps the one warning.
TEST(ImpulseFeature, AnImpulseThatUnbindsAPairIsWarnedWithTheNumbers) {
  const auto dart = [](const std::string& dv) {
    return load_scene(test::source_path("examples/didymos-dart.yaml"), {"impulses.0.delta_v.1=" + dv});
  };
  EXPECT_TRUE(run_scene(dart("-0.0027"), registry(), {}).warnings.empty());
  const Scene slip = dart("-2.7");
  Simulation sim(slip, registry());
  sim.integrate(86400.0, false);  // just before the impulse
  const State before = sim.state();
  sim.integrate(259200.0);
  const RunSummary s = sim.finish();
  ASSERT_EQ(s.warnings.size(), 1u);
  const System& sys = slip.system;
  const double r = (before.x.col(1) - before.x.col(0)).norm();
  const double escape = std::sqrt(2 * sys.G() * (sys.body(0).mass + sys.body(1).mass) / r);
  char expected[96];
  std::snprintf(expected, sizeof expected, "past the escape speed %.4g m/s at %.4g m", escape, r);
  const std::string& w = s.warnings[0];
  EXPECT_NE(w.find("impulses.0 (t = 86400 s) unbinds dimorphos from didymos: its |delta_v| of 2.7 m/s"),
            std::string::npos) << w;
  EXPECT_NE(w.find(expected), std::string::npos) << w << " / " << expected;
  EXPECT_NE(w.find("a delta_v in mm/s typed as m/s?"), std::string::npos) << w;
  EXPECT_NE(format_summary(s).find("warning                       impulses.0"), std::string::npos);
  EXPECT_NE(format_summary_json(s).find("\"warnings\": [\"impulses.0 (t = 86400 s) unbinds"), std::string::npos);
  // Saved after the impulse and loaded; interrupted there and resumed: the same one warning.
  const auto file = temporary("unbound");
  {
    Simulation first(slip, registry());
    first.integrate(90000.0);
    first.save(file);
  }
  auto loaded = Simulation::load(file, registry());
  loaded->integrate(259200.0);
  EXPECT_EQ(loaded->finish().warnings, s.warnings);
  RunOptions options;
  options.output = file;
  options.overwrite = true;
  {
    Simulation first(slip, registry(), options);
    first.integrate(90000.0);
  }
  auto resumed = Simulation::resume(file, registry());
  resumed->integrate(259200.0);
  EXPECT_EQ(resumed->finish().warnings, s.warnings);
  std::filesystem::remove(file);
}
