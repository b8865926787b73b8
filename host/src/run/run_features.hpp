#pragma once
// The one list of run features (run_feature.hpp): those a scene's run carries, made from it.
#include <noether/forces.hpp>
#include <noether/integrator.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include "run/run_feature.hpp"

#include <memory>
#include <vector>

namespace noether::detail {

// What the features are made from: the scene, its integrator (which a feature may hand what it
// carries: the sensitivities' parameters), the run's initial state (t0), its model (made from
// the scene by `registry`, or given in code: `custom_potential`), the scene's forces (none:
// null) and the run's threads.
struct FeatureContext {
  const Scene& scene;
  Integrator& integrator;
  const State& initial;
  const Potential& potential;
  PluginRegistry& registry;
  bool custom_potential = false;
  std::shared_ptr<const Forcing> forcing;
  int threads = 1;
};

// The features the scene's run carries, in the order of their tangent columns and of their hooks'
// calls. SceneError (located) when the scene asks for one the run cannot carry.
std::vector<std::unique_ptr<RunFeature>> make_run_features(const FeatureContext& context);

}  // namespace noether::detail
