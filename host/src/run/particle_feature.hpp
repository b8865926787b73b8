#pragma once
// The scene's massless particles (and ejecta) as a run feature (docs/user-guide.md, "Particles";
// docs/equations.md §38): the swarm carried over every step the bodies take, moved with the
// bodies when a state is set from outside, their recorded positions in every frame, and its
// outcome in the summary and the file's /test_particles. The swarm's own checkpoint (every
// particle, written with the output's blocks: H5Writer::checkpoint_particles) is what a
// continued or loaded run restores it from.
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
  // The first particles.record particles' positions at each frame
  // (/particles/test_particles/position).
  std::vector<FeatureSeries> series() const override;
  void record(const State& bodies, std::span<double> out) const override;

  // The swarm's own checkpoint (/checkpoint/particles, eq. 38.3's state of every particle):
  // written with each block of frames whose last frame is a step's end; a continued run starts
  // from it only where it stands at the run's last frame.
  void keep_with(H5Writer& writer) override;
  void refuse_save(const State& bodies) const override;
  void save_into(H5Writer& writer, std::int64_t frame) const override;
  void continue_from(const io::RunRecord& run, std::size_t last, double t_last) override;
  void finish(H5Writer& writer, const Scene& scene) const override;

  ParticleSwarm& swarm() { return *swarm_; }

 private:
  std::unique_ptr<ParticleSwarm> swarm_;
  std::size_t recorded_ = 0;  // particles.record
  mutable Eigen::Matrix3Xd positions_;  // their positions at the frame being recorded
  State bodies_;  // the bodies' state the particles were last carried to
  int threads_;
};

}  // namespace noether::detail
