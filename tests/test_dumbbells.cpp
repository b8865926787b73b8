// The reference scene of Lee, Leok & McClamroch 2007 §5 (docs/equations.md §6) run end to end through the plugins.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

using namespace noether;

namespace {
RunSummary run(const std::vector<std::string>& overrides = {}) {
  auto registry = test::bundled_plugins();
  return run_scene(test::dumbbell_scene(overrides), registry, {});
}
}  // namespace

// Published: E0 ≈ 0.44068740, max |ΔE| = 2.6966e-7, max ‖I − RᵀR‖ = 2.8657e-13, closest
// approach ≈ 0.330 near t ≈ 9.
TEST(Dumbbells, ReproducesThePublishedLgviResults) {
  const RunSummary s = run();
  EXPECT_NEAR(s.initial.energy, 0.44068740, 5e-9);
  EXPECT_NEAR(s.max_abs_energy_error, 2.6966e-7, 0.01 * 2.6966e-7);
  EXPECT_LE(s.max_orthogonality_error, 1e-12);
  // Total linear and angular momentum are conserved to round-off (measured: 1.2e-15 and
  // 3.2e-14 relative to the sum of the magnitudes of their parts).
  EXPECT_LE(s.max_rel_linear_momentum_error, 1e-14);
  EXPECT_LE(s.max_rel_angular_momentum_error, 1e-13);
  EXPECT_NEAR(s.min_distance, 0.330, 0.001);
  EXPECT_NEAR(s.t_of_min_distance, 9.0, 0.1);
  EXPECT_EQ(s.work.steps, 100000);
  EXPECT_EQ(s.work.potential_evaluations, 100001);  // one per step, plus t0
  EXPECT_EQ(s.frames, 2001u);
}

// Second order: halving h divides max |ΔE| by 4.
TEST(Dumbbells, EnergyErrorFallsAsHSquared) {
  const double coarse = run({"integrator.step=0.0004"}).max_abs_energy_error;
  const double fine = run({"integrator.step=0.0002"}).max_abs_energy_error;
  EXPECT_NEAR(coarse / fine, 4.0, 0.4) << coarse << " / " << fine;
}

// A step too large for the spin: a clear error naming the body and the step, and the state
// left at the last valid step, still on SO(3).
TEST(Dumbbells, StepTooLargeForTheSpinIsAClearError) {
  const Scene scene = test::dumbbell_scene({"integrator.step=0.02", "run.output_every=0.02",
                                            "bodies.alpha.angular_velocity=[0, 0, 400]"});
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("sphere-cluster", scene.system, Params());
  auto lgvi = registry.make_integrator("lgvi", scene.system, potential, scene.integrator.params);
  struct Count final : Observer {
    int frames = 0;
    void observe(const State&, const Forces&, bool) override { ++frames; }
  } count;
  State s = scene.initial;
  try {
    advance(*lgvi, *potential, scene.system, s, {scene.run.t_end, scene.run.output_every}, count);
    FAIL() << "expected an IntegrationError";
  } catch (const IntegrationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("step too large for the spin of body 'alpha'"), std::string::npos) << what;
    EXPECT_NE(what.find("step h = 0.02"), std::string::npos) << what;
    EXPECT_EQ(e.t_reached(), s.t);
    EXPECT_EQ(s.t, scene.initial.t);  // |Ω| h = 8 rad: the first step already fails
    EXPECT_EQ(s.x, scene.initial.x);
    for (const auto& R : s.R) EXPECT_LE(orthogonality_error(R), 1e-15);
  }
  EXPECT_EQ(count.frames, 1);
}

// Fixed steps cannot land on t_end or output times that are not whole multiples of h.
TEST(Dumbbells, OutputTimesMustBeWholeSteps) {
  EXPECT_THROW(run({"integrator.step=0.0003"}), SceneError);
  EXPECT_THROW(run({"run.output_every=0.00025"}), SceneError);
}
