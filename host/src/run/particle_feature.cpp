// The scene's massless particles as a run feature (particle_feature.hpp).
#include "run/particle_feature.hpp"

#include <noether/error.hpp>

#include "io/run_record.hpp"

#include <algorithm>
#include <sstream>

namespace noether::detail {

ParticleFeature::ParticleFeature(const Scene& scene, const Integrator& integrator, const State& bodies,
                                 std::shared_ptr<const Forcing> forcing, int threads)
    : recorded_(scene.particles.record), threads_(threads) {
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

std::vector<FeatureSeries> ParticleFeature::series() const {
  if (recorded_ == 0) return {};
  return {{"particle_positions", {recorded_, 3}}};
}

void ParticleFeature::record(const State& bodies, std::span<double> out) const {
  swarm_->recorded_positions(bodies, positions_);
  std::copy(positions_.data(), positions_.data() + positions_.size(), out.begin());
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

void ParticleFeature::keep_with(H5Writer& writer) {
  writer.checkpoint_particles([this](double t) -> std::optional<ParticleCheckpoint> {
    if (swarm_->time() != t) return std::nullopt;
    return swarm_->checkpoint();
  });
}

void ParticleFeature::refuse_save(const State& bodies) const {
  if (swarm_->time() == bodies.t) return;
  std::ostringstream why;
  why.precision(17);
  why << "save: the particles stand at t = " << swarm_->time() << ", the bodies at " << bodies.t
      << " (between the integrator's steps); save where a call to integrate() ended";
  throw Error(why.str());
}

void ParticleFeature::save_into(H5Writer& writer, std::int64_t frame) const {
  writer.write_particle_checkpoint(swarm_->checkpoint(), frame);
}

void ParticleFeature::continue_from(const io::RunRecord& run, std::size_t last, double t_last) {
  std::ostringstream why;
  why.precision(17);
  why << run.file().string() << ": continuing a run with massless particles needs them where they stood at its last frame "
      << last << " (t = " << t_last << "), ";
  if (!run.particles) {
    why << "and the file holds none (written by a noether before they were kept, or killed before its first block)";
  } else if (run.particles->frame != static_cast<std::int64_t>(last) || run.particles->t != t_last) {
    why << "and the file holds them at frame " << run.particles->frame << " (t = " << run.particles->t
        << ") — the last frame falls between an adaptive integrator's steps, or the run was killed while they were "
           "written";
  } else {
    swarm_->restore(*run.particles, t_last);
    return;
  }
  why << "; run it again whole, or give the particles a fixed-step integrator";
  throw Error(why.str());
}

void ParticleFeature::finish(H5Writer& writer, const Scene& scene) const { writer.write_particles(*swarm_, scene); }

}  // namespace noether::detail
