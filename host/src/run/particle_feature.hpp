#pragma once
// The scene's massless particles (and ejecta) as a run feature (docs/user-guide.md, "Particles";
// docs/equations.md §38): the swarm carried over every step the bodies take, moved with the
// bodies when a state is set from outside, and its outcome in the summary. The swarm's own
// checkpoint (every particle, written with the output's blocks: H5Writer::checkpoint_particles)
// is what a continued or loaded run restores it from.
#include <noether/forces.hpp>
#include <noether/integrator.hpp>
#include <noether/particles.hpp>
#include <noether/scene.hpp>

#include "run/run_feature.hpp"

#include <memory>

namespace noether::detail {

class ParticleFeature final : public RunFeature {
 public:
  // The scene's particles at the bodies' state `bodies` (t0), carried by the run's `threads`.
  // SceneError, located at the scene's particles block, when the integrator chooses its own
  // steps and particles.step is not given, or the swarm cannot be made.
  ParticleFeature(const Scene& scene, const Integrator& integrator, const State& bodies,
                  std::shared_ptr<const Forcing> forcing, int threads);
  std::string_view name() const override { return "particles"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  void accept_state(const State& state) override;
  void before_steps(const State& from) override { bodies_ = from; }
  void after_step(const State& reached, Eigen::Ref<const Eigen::MatrixXd>) override;
  void summarize(RunSummary& summary) const override;

  ParticleSwarm& swarm() { return *swarm_; }

 private:
  std::unique_ptr<ParticleSwarm> swarm_;
  State bodies_;  // the bodies' state the particles were last carried to
  int threads_;
};

}  // namespace noether::detail
