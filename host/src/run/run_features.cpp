// The one list of run features (run_features.hpp). A new feature: its file, one line here, its
// test (docs/architecture.md, "Run features").
#include "run/run_features.hpp"

#include "run/attracting_pairs.hpp"
#include "run/chaos_feature.hpp"
#include "run/closest_approach_feature.hpp"
#include "run/event_feature.hpp"
#include "run/force_balance_feature.hpp"
#include "run/binary_pair.hpp"
#include "run/impulse_feature.hpp"
#include "run/mutual_orbit_feature.hpp"
#include "run/orbit_periods_feature.hpp"
#include "run/particle_feature.hpp"
#include "run/sensitivity_feature.hpp"
#include "run/spin_state_feature.hpp"
#include "run/stm_feature.hpp"

namespace noether::detail {

std::vector<std::unique_ptr<RunFeature>> make_run_features(const FeatureContext& c) {
  const Scene& sc = c.scene;
  std::vector<std::unique_ptr<RunFeature>> features;
  // The tangent: [STM | the other features' columns | sensitivities] (docs/derivatives.md).
  if (sc.run.stm) features.push_back(std::make_unique<StmFeature>(State::tangent_rows(sc.system)));
  if (sc.run.chaos) features.push_back(std::make_unique<ChaosFeature>(sc.system));
  if (!sc.impulses.empty())
    features.push_back(std::make_unique<ImpulseFeature>(sc.system, sc.impulses, sc.initial.t, c.integrator.fixed_step(), sc.units));
  if (!sc.particles.empty())
    features.push_back(std::make_unique<ParticleFeature>(sc, c.integrator, c.initial, c.forcing, c.threads));
  if (auto events = std::make_unique<EventFeature>(sc.system, sc.run); events->watches_any())
    features.push_back(std::move(events));
  const auto pair = binary_pair(sc.system);
  if (pair) features.push_back(std::make_unique<MutualOrbitFeature>(sc.system, pair->primary, pair->secondary));
  if (sc.system.size() >= 3 && sc.system.size() <= kAttractingPairsMostBodies)  // (two: the binary's alone)
    features.push_back(std::make_unique<OrbitPeriodsFeature>(
        sc.system, pair ? std::optional(std::pair(pair->primary, pair->secondary)) : std::nullopt));
  if (sc.system.rigid_count() > 0) features.push_back(std::make_unique<SpinStateFeature>(sc.system));
  if (sc.system.size() >= 2 && sc.system.size() <= kClosestApproachMostBodies)
    features.push_back(std::make_unique<ClosestApproachFeature>(sc.system));
  if (!sc.forces.empty()) features.push_back(std::make_unique<ForceBalanceFeature>(sc.forces.size()));
  if (!sc.run.sensitivities.empty())  // the tangent's last columns
    features.push_back(
        std::make_unique<SensitivityFeature>(sc, c.potential, c.registry, c.custom_potential, c.integrator));
  return features;
}

}  // namespace noether::detail
