// The scene's massless particles as a run feature (particle_feature.hpp).
#include "run/particle_feature.hpp"

#include <noether/error.hpp>

namespace noether::detail {

ParticleFeature::ParticleFeature(const Scene& scene, const Integrator& integrator, const State& bodies,
                                 std::shared_ptr<const Forcing> forcing, int threads)
    : threads_(threads) {
  if (!(integrator.fixed_step() > 0.0) && !(scene.particles.step > 0.0))
    throw SceneError(scene.root.at("particles").here() + "particles: integrator '" + scene.integrator.plugin +
                     "' chooses its own steps, which may be long for the particles: give particles.step (their "
                     "longest Verlet step)");
  try {
    swarm_ = std::make_unique<ParticleSwarm>(scene.system, scene.particles, bodies, std::move(forcing));
  } catch (const SceneError& e) {  // where in the scene: the particles' block
    throw SceneError(scene.root.at("particles").here() + e.what());
  }
}

void ParticleFeature::accept_state(const State& state) {
  try {  // where they stand, in the new bodies' field (or refused before anything changes)
    swarm_->set_bodies(state);
  } catch (const Error& e) {
    throw Error(std::string("set_state: ") + e.what());
  }
}

void ParticleFeature::after_step(const State& reached, Eigen::Ref<const Eigen::MatrixXd>) {
  swarm_->advance(bodies_, reached, threads_);  // carried over the step the bodies took (particles.hpp)
  bodies_ = reached;
}

void ParticleFeature::summarize(RunSummary& summary) const {
  ParticleSummary s;
  s.count = swarm_->size();
  s.bodies = swarm_->surfaces();
  s.impacts.assign(s.bodies.size(), 0);
  for (const ParticleOutcome& o : swarm_->outcomes()) {
    if (o.fate == ParticleFate::impact) ++s.impacts[static_cast<std::size_t>(o.body)];
    if (o.fate == ParticleFate::escape) ++s.escaped;
    if (o.fate == ParticleFate::in_flight) ++s.in_flight;
  }
  s.steps = swarm_->particle_steps();
  s.seconds = swarm_->seconds();
  s.fields = swarm_->fields();
  s.check = swarm_->check(summary.final_state);
  summary.particles = std::move(s);
}

}  // namespace noether::detail
