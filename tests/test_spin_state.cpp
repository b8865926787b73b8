// The spin state of the rigid bodies in a run's summary (docs/user-guide.md "Spin state",
// docs/equations.md eqs. 17.11–17.14): nutation and the rotation period against the torque-free
// top, the libration amplitude and period against the linear spin–orbit pendulum, circulation
// counted, a run too short to tell said so, undersampled frames refused, and a saved simulation
// that keeps it.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

using namespace noether;
using test::registry;

namespace {

RunSummary run(const Scene& scene) {
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  return sim.finish();
}

const SpinState& spin_of(const RunSummary& s, const std::string& body) {
  for (const auto& spin : s.spin_states)
    if (spin.body == body) return spin;
  throw std::runtime_error("no spin state for " + body);
}

Scene moon(std::vector<std::string> overrides) {
  return load_scene(test::source_path("examples/tumbling-moon.yaml"), overrides);
}

constexpr double kDegrees = 180.0 / std::numbers::pi;

}  // namespace

// A torque-free axisymmetric top (J = diag(1, 1, 2), alone): Π turns about the
// symmetry axis in the body frame at a fixed angle atan(Π⊥/Π_z), the nutation of eq. 17.11.
TEST(SpinState, NutationOfATorqueFreeTopIsItsConeAngle) {
  const Scene scene = parse_scene(R"(G: 1
bodies:
  - {name: top, mass: 1, inertia: [1, 1, 2], position: [0, 0, 0], angular_velocity: [0.3, 0.1, 1]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 50, output_every: 0.1}
)",
                                 "top");
  const RunSummary summary = run(scene);
  const SpinState& top = spin_of(summary, "top");
  const double expected = std::atan2(std::hypot(0.3, 0.1), 2.0) * kDegrees;  // Π = J Ω = (0.3, 0.1, 2)
  EXPECT_NEAR(top.nutation, expected, 1e-9);
  EXPECT_NEAR(top.max_nutation, expected, 1e-9);
  EXPECT_TRUE(top.other.empty());  // not a binary's: no libration
  EXPECT_TRUE(std::isnan(top.libration_amplitude));
}

// Eq. 17.14 on the torque-free top: with Euler angles about L (precession φ, cone θ, spin ψ) a
// body axis across the symmetry axis turns about L at the mean rate φ̇ + ψ̇, with φ̇ = |Π| / J₁
// and ψ̇ = Ω₃ (J₁ − J₃) / J₁ (Goldstein §5.6): 2.0248 − 1 rad per unit time. About a principal
// axis (Ω = (0, 0, 1)) the period is 2π / |Ω|; the LGVI's phase error at h = 0.05 and 0.025
// shrinks fourfold (order 2) and the run repeated at half the step estimates it within a factor 2.
TEST(SpinState, RotationPeriodOfATorqueFreeTop) {
  auto top = [](const std::string& omega, double step) {
    const Scene scene = parse_scene(R"(G: 1
bodies:
  - {name: top, mass: 1, inertia: [1, 1, 2], position: [0, 0, 0], angular_velocity: )" + omega + R"(}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: )" + std::to_string(step) + R"(}
run: {t_end: 60, output_every: 0.1}
)",
                                    "top");
    return spin_of(run_scene(scene, registry(), {}), "top");
  };
  const SpinState tumbling = top("[0.3, 0.1, 1]", 0.01);
  const double rate = std::hypot(0.3, 0.1, 2.0) / 1.0 + 1.0 * (1.0 - 2.0) / 1.0;
  EXPECT_FALSE(tumbling.spin_undersampled);
  EXPECT_NEAR(tumbling.spin_period, 2 * std::numbers::pi / rate, 2e-3 * (2 * std::numbers::pi / rate));
  EXPECT_NEAR(tumbling.spin_turns, 60.0 * rate / (2 * std::numbers::pi), 0.02);
  const double exact = 2 * std::numbers::pi;
  const SpinState coarse = top("[0, 0, 1]", 0.05), fine = top("[0, 0, 1]", 0.025);
  const double error = std::abs(coarse.spin_period - exact), finer = std::abs(fine.spin_period - exact);
  EXPECT_NEAR(error / finer, 4.0, 0.2);
  ASSERT_TRUE(coarse.spin_period_error.estimated()) << coarse.spin_period_error.why_not;
  EXPECT_GT(coarse.spin_period_error.error, error / 2);
  EXPECT_LT(coarse.spin_period_error.error, error * 2);
}

// The moon started synchronous on a circular orbit with its spin 2 % fast librates, for small
// amplitude, as the pendulum θ̈ = −ω² θ with ω = n √(3 (B − A)/C) (Murray & Dermott 1999 §5.2):
// from θ = 0 with θ̇ = 0.02 n its amplitude is 0.02 n / ω (1.1309°; measured 1.1321°) and its
// period 2π/ω (eq. 17.13: 6.2007; measured 6.1987). The moon is the example's shrunk tenfold
// (the same ratios, the same ω): at full size its own quadrupole bends the orbit the scene starts
// as a Kepler circle into one of e ~ (size / a)², and so near resonance (ω/n = 1.013) the forced
// libration adds 10 % to the amplitude (1.24° at small steps; 1.132 ± 0.11° at the example's
// 0.01, its step error estimated). It stays in the orbit plane; the non-rotating planet
// circulates backwards once per orbit.
TEST(SpinState, LibrationAmplitudeOfASynchronousMoon) {
  const Scene scene = moon({"bodies.moon.orbit.e=0", "bodies.moon.angular_velocity=[0,0,1.02]", "run.t_end=300",
                            "run.output_every=0.05", "bodies.moon.shape.ellipsoid.semi_axes=[0.002,0.0014,0.001]"});
  const RunSummary s = run(scene);
  const SpinState& m = spin_of(s, "moon");
  const double a = 0.002, b = 0.0014, c = 0.001;
  const double A = b * b + c * c, B = a * a + c * c, C = a * a + b * b;
  const double omega = std::sqrt(3 * (B - A) / C);  // n = 1
  EXPECT_EQ(m.other, "planet");
  EXPECT_FALSE(m.undersampled);
  EXPECT_NEAR(m.libration_amplitude, 0.02 / omega * kDegrees, 0.005 * 0.02 / omega * kDegrees);
  EXPECT_LT(m.max_pitch, 1e-9);
  EXPECT_LT(m.max_roll, 1e-9);
  EXPECT_LT(std::abs(m.turns), 0.01);
  EXPECT_LT(m.max_nutation, 1e-9);
  // Eq. 17.13: the pendulum's period 2π/ω (6.2007); the turning points' interpolation between
  // frames 0.05 apart is far below that.
  EXPECT_NEAR(m.libration_period, 2 * std::numbers::pi / omega, 1e-3 * 2 * std::numbers::pi / omega);
  EXPECT_GT(m.turning_points, 90);
  EXPECT_LT(m.libration_period_frames_error, 1e-4);
  const SpinState& p = spin_of(s, "planet");
  EXPECT_GT(p.libration_amplitude, 90.0);
  EXPECT_NEAR(p.turns, -(300.0 - 0.0) / s.mutual_period, 0.01);
  EXPECT_TRUE(std::isnan(p.max_nutation));  // not rotating
}

// A run shorter than a swing each way cannot tell a libration from a circulation: the moon (2 %
// fast, period 6.2) over 2 time units has turned back once at most, and is not said to librate.
TEST(SpinState, ARunTooShortToTellIsSaidSo) {
  const RunSummary s = run(moon({"bodies.moon.orbit.e=0", "bodies.moon.angular_velocity=[0,0,1.02]", "run.t_end=2",
                                 "run.output_every=0.05"}));
  const SpinState& m = spin_of(s, "moon");
  EXPECT_LT(m.turning_points, 2);
  EXPECT_TRUE(std::isnan(m.libration_period));
  EXPECT_FALSE(m.libration_error.estimated());
  const std::string text = format_summary(s);
  EXPECT_EQ(text.find("librates"), std::string::npos) << text;
  EXPECT_NE(text.find("too short a run to tell libration from circulation"), std::string::npos) << text;
  EXPECT_NE(text.find("rotation period not measured: 0.32"), std::string::npos) << text;
}

// Frames farther apart than a sixth of a turn of the body relative to the line of centres
// cannot follow the yaw: the libration is not reported rather than aliased; the nutation is.
TEST(SpinState, UndersampledFramesAreSaidSo) {
  const RunSummary s = run(moon({"run.t_end=100", "run.output_every=2"}));
  for (const char* body : {"planet", "moon"}) {
    const SpinState& spin = spin_of(s, body);
    EXPECT_TRUE(spin.undersampled) << body;
    EXPECT_TRUE(std::isnan(spin.libration_amplitude)) << body;
  }
  EXPECT_GT(spin_of(s, "moon").max_nutation, 10.0);  // the tumbling moon leaves its principal axis
}

// A saved and loaded simulation reports the spin state of the whole run, as one that went on.
TEST(SpinState, ASavedSimulationKeepsIt) {
  const Scene scene = moon({"run.t_end=20", "run.output_every=0.05"});
  Simulation whole(scene, registry());
  whole.integrate(20.0);
  const SpinState expected = spin_of(whole.finish(), "moon");

  const auto file = std::filesystem::temp_directory_path() / "noether-spin-state-save.h5";
  {
    Simulation first(scene, registry());
    first.integrate(10.0);
    first.save(file);
  }
  auto loaded = Simulation::load(file, registry());
  loaded->integrate(20.0);
  const SpinState got = spin_of(loaded->finish(), "moon");
  std::filesystem::remove(file);
  EXPECT_DOUBLE_EQ(got.libration_amplitude, expected.libration_amplitude);
  EXPECT_DOUBLE_EQ(got.turns, expected.turns);
  EXPECT_DOUBLE_EQ(got.max_nutation, expected.max_nutation);
  EXPECT_DOUBLE_EQ(got.max_roll, expected.max_roll);
  EXPECT_EQ(got.turning_points, expected.turning_points);
  EXPECT_DOUBLE_EQ(got.spin_turns, expected.spin_turns);
}
