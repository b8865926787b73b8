// SensitivityFeature (run/sensitivity_feature.cpp): the tangent's last columns start at
// ∂z(t0)/∂p as scene_sensitivity gives them, the parameters of the dynamics among the keys are
// handed to the integrator (or refused by one that cannot carry them), a state set from outside is
// refused, and a recorded frame's /derivatives/sensitivity is read back.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "io/frame_schema.hpp"
#include "run/sensitivity_feature.hpp"

#include <gtest/gtest.h>

using namespace noether;
using test::registry;

namespace {

Scene scene_with(const std::string& integrator) {
  return test::dumbbell_scene(
      {"integrator=" + integrator, "run.t_end=0.4", "run.sensitivities=[bodies.beta.velocity, bodies.alpha.mass]"});
}

}  // namespace

TEST(SensitivityFeature, StartsAtTheScenesDerivativeAndHandsTheIntegratorItsParameters) {
  const Scene scene = scene_with("{plugin: lgvi, step: 0.002}");
  const auto potential = make_scene_potential(scene, registry());
  auto integrator = registry().make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
  detail::SensitivityFeature feature(scene, *potential, registry(), false, *integrator);
  const SceneSensitivity expected = scene_sensitivity(
      scene, scene.run.sensitivities, *potential, [](const Scene& s) { return make_scene_potential(s, registry()); },
      [](const Scene& s) { return make_scene_forcing(s, registry()); });
  EXPECT_EQ(feature.names(), expected.names);
  ASSERT_EQ(feature.names().size(), 4u);  // three velocity components, one mass
  EXPECT_EQ(feature.names().back(), "bodies.alpha.mass");
  ASSERT_TRUE(feature.parameters());
  EXPECT_EQ(feature.parameters()->size(), 1u);
  const Eigen::Index N = State::tangent_rows(scene.system);
  Eigen::MatrixXd V(N, feature.tangent_columns());
  feature.start(scene.initial, V);
  EXPECT_EQ(V, expected.columns);
  EXPECT_THROW(feature.refuse_state(scene.initial), Error);
  io::RecordedFrame frame;
  frame.sensitivity = Eigen::MatrixXd::Random(N, 4);
  feature.read_frame(frame, V);
  EXPECT_EQ(V, frame.sensitivity);
  frame.sensitivity = Eigen::MatrixXd::Random(N, 3);  // another run's keys
  EXPECT_THROW(feature.read_frame(frame, V), Error);
  // A model given in code cannot be made again at p ± d for a parameter of the dynamics.
  auto again = registry().make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
  EXPECT_THROW(detail::SensitivityFeature(scene, *potential, registry(), true, *again), SceneError);
}

// In a run: the tangent's last columns are the feature's, after the STM's; set_state is refused
// and leaves the run where it stood.
TEST(SensitivityFeature, AreTheTangentsLastColumnsAndRefuseASetState) {
  Scene scene = scene_with("{plugin: lgvi, step: 0.002}");
  scene.run.stm = true;
  Simulation sim(scene, registry());
  const Eigen::Index N = State::tangent_rows(scene.system);
  ASSERT_EQ(sim.state().tangent.cols(), N + 4);
  EXPECT_TRUE(sim.state().tangent.leftCols(N).isIdentity(0.0));
  EXPECT_EQ(sim.sensitivity_names().size(), 4u);
  sim.integrate(0.2);
  const State before = sim.state();
  EXPECT_THROW(sim.set_state(before), Error);
  EXPECT_EQ(sim.state().tangent, before.tangent);
  sim.integrate(0.4);
  EXPECT_TRUE(sim.state().tangent.allFinite());
}
