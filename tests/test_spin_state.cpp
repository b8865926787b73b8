// The spin state of the rigid bodies in a run's summary (docs/user-guide.md "Spin state",
// docs/equations.md eqs. 17.11, 17.12): nutation against the torque-free top, the libration
// amplitude against the linear spin–orbit pendulum, circulation counted, undersampled frames
// refused, and a saved simulation that keeps it.
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

// The moon started synchronous on a circular orbit with its spin 2 % fast librates, for small
// amplitude, as the pendulum θ̈ = −ω² θ with ω = n √(3 (B − A)/C) (Murray & Dermott 1999 §5.2):
// from θ = 0 with θ̇ = 0.02 n its amplitude is 0.02 n / ω (1.129°; measured 1.132°, the
// difference the series' a/r terms and the amplitude). It stays in the orbit plane; the
// non-rotating planet circulates backwards once per orbit.
TEST(SpinState, LibrationAmplitudeOfASynchronousMoon) {
  const Scene scene = moon({"bodies.moon.orbit.e=0", "bodies.moon.angular_velocity=[0,0,1.02]", "run.t_end=300",
                            "run.output_every=0.05"});
  const RunSummary s = run(scene);
  const SpinState& m = spin_of(s, "moon");
  const double a = 0.02, b = 0.014, c = 0.01;
  const double A = b * b + c * c, B = a * a + c * c, C = a * a + b * b;
  const double omega = std::sqrt(3 * (B - A) / C);  // n = 1
  EXPECT_EQ(m.other, "planet");
  EXPECT_FALSE(m.undersampled);
  EXPECT_NEAR(m.libration_amplitude, 0.02 / omega * kDegrees, 0.02 * 0.02 / omega * kDegrees);
  EXPECT_LT(m.max_pitch, 1e-9);
  EXPECT_LT(m.max_roll, 1e-9);
  EXPECT_LT(std::abs(m.turns), 0.01);
  EXPECT_LT(m.max_nutation, 1e-9);
  const SpinState& p = spin_of(s, "planet");
  EXPECT_GT(p.libration_amplitude, 90.0);
  EXPECT_NEAR(p.turns, -(300.0 - 0.0) / s.mutual_period, 0.01);
  EXPECT_TRUE(std::isnan(p.max_nutation));  // not rotating
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
}
