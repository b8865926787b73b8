#pragma once
// Massless particles in a run (the scene's `particles:`; docs/user-guide.md, "Particles";
// docs/equations.md §38): test particles — ejecta, boulders, spacecraft — that feel every body's
// field (BodyField) and the point masses of the scene's forces that pull them (a prescribed
// planet or Sun, ForceModel::pull_particles), and exert nothing. For each step the bodies' integrator takes, every particle
// in flight takes steps of velocity Verlet (38.3), no longer than `step`, in the field of the bodies
// at the substeps' ends (the step's own states at its ends, the cubic Hermite interpolant (16.2) between
// them). The bodies' integration is untouched (the LGVI stays symplectic for them); each particle's
// map is symplectic in the field of the bodies at those times, of order 2. A particle that ends a
// substep inside a body's surface (its real shape, eq. 16.5) has landed: the time is found on the
// substep's cubic Hermite path by regula falsi (38.4), with where and how fast it hit, in the body
// frame. A point mass that pulls them with a radius (a prescribed planet's) is a sphere they land
// on the same way. A particle farther than `escape` from the centre has escaped.
#include <noether/body_field.hpp>
#include <noether/force_model.hpp>
#include <noether/particle_check.hpp>
#include <noether/scene.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace noether {

enum class ParticleFate : int { in_flight = 0, impact = 1, escape = 2 };

struct ParticleOutcome {
  ParticleFate fate = ParticleFate::in_flight;
  double t = std::numeric_limits<double>::quiet_NaN();  // of the impact or escape
  int body = -1;                  // what it landed on: its index in ParticleSwarm::surfaces()
  // impact: where, in the body frame (centre of mass, principal axes); on a point mass's sphere,
  // from its centre in inertial axes
  Vec3 point = Vec3::Zero();
  // impact: the particle's velocity relative to the spinning surface there, body frame (on a
  // point mass's sphere: relative to its centre, inertial)
  Vec3 velocity = Vec3::Zero();
};

// A swarm where it stands, every number that carries it on bit for bit (Simulation::save and
// load): a row of kColumns numbers per particle, then per particle of the check at half the step
// — x, v, a (the acceleration at x), fate, t, body, point, velocity (ParticleOutcome) —, and the
// swarm's time and counters.
struct ParticleCheckpoint {
  static constexpr std::size_t kColumns = 18;
  double t = 0.0;
  double particle_steps = 0.0, check_steps = 0.0, seconds = 0.0;  // (whole numbers up to 2^53)
  std::int64_t frame = 0;  // the output frame it was written with (read back from a file)
  std::vector<double> rows;  // row-major
};

class ParticleSwarm {
 public:
  // The particles of `settings` at their initial states, the bodies at `bodies` (the run's t0),
  // in the field of the bodies and of the forces in `forcing` that pull particles (none: null);
  // or, when `settings.restored`, where that checkpoint has them (Error when it does not fit:
  // another number of particles, another time than the bodies').
  ParticleSwarm(const System& system, const ParticleSettings& settings, const State& bodies,
                std::shared_ptr<const Forcing> forcing = nullptr);
  ~ParticleSwarm();

  // Carries every particle in flight from the bodies' state `from` to `to` (the ends of one step
  // of their integrator, or of a shortened step at an event), on `threads` threads: each particle
  // is independent, so the result is the same bit for bit for any number.
  void advance(const State& from, const State& to, int threads);

  std::size_t size() const { return outcomes_.size(); }
  double time() const { return t_; }
  const Eigen::Matrix3Xd& positions() const { return x_; }   // inertial; a landed particle's where it landed
  const Eigen::Matrix3Xd& velocities() const { return v_; }
  const std::vector<Vec3>& initial_positions() const { return settings_.position; }
  const std::vector<Vec3>& initial_velocities() const { return settings_.velocity; }
  const std::vector<ParticleOutcome>& outcomes() const { return outcomes_; }
  // The positions of the first `settings.record` particles when the bodies are at `bodies`, at a
  // time in [the last step's start, time()]: at time() where they stand; before it (an output
  // frame between an adaptive method's steps) on the cubic Hermite path through their positions
  // and velocities at the step's ends. A particle that has landed rides on its body, at the point
  // where it landed.
  void recorded_positions(const State& bodies, Eigen::Matrix3Xd& out) const;
  // Particle i's energy per unit mass in the bodies' field at `bodies`: ½ v² + Σ Φ_b (38.1), and
  // −μ/r of each point mass that pulls it.
  double energy(std::size_t i, const State& bodies);
  // What each body's field is (BodyField::describe), in the scene's order of bodies, then what
  // each of the scene's forces is to the particles.
  std::vector<std::string> fields() const;
  // What a particle can land on, as ParticleOutcome::body indexes it: the scene's bodies, then the
  // point masses of the forces that pull the particles (a prescribed body: landed on when it has a
  // radius), by the force's name.
  const std::vector<std::string>& surfaces() const { return surfaces_; }
  std::int64_t particle_steps() const { return particle_steps_; }  // Verlet steps taken, all particles
  // The check's comparison where the run stands, the bodies at `bodies` (at time()).
  ParticleCheck check(const State& bodies) const;
  double seconds() const { return seconds_; }                      // wall time spent in advance()
  // The bodies were set to `bodies` where the particles stand (Simulation::set_state): each
  // particle in flight feels their field there from now on (its acceleration made again). Error
  // when `bodies` is at another time, or a particle in flight would be inside a body (named).
  void set_bodies(const State& bodies);
  // Every number that carries the swarm on where it stands (Simulation::save).
  ParticleCheckpoint checkpoint() const;
  // Carries on from `from`, the bodies standing at `t_bodies` (Error when it does not fit:
  // another number of particles, another time).
  void restore(const ParticleCheckpoint& from, double t_bodies);

  struct Placement;  // the bodies' positions and attitudes at one time

 private:
  // One particle in flight, (x, v, a) at time(), through the substeps `ends` (38.3), landing
  // when it crosses a surface (38.4).
  struct Flight {
    Vec3 x, v, a;
    ParticleOutcome outcome;
  };
  std::string inside(const Vec3& x, const Placement& at) const;  // what x is inside of ("": nothing)
  Placement place(const State& bodies) const;  // the bodies and the forces' point masses at `bodies`
  void place(const State& bodies, Placement& at) const;  // the same into `at`, reusing its memory
  Vec3 acceleration(const Vec3& x, const Placement& at, std::vector<BodyField>& fields) const;
  void carry(Flight& p, const std::vector<Placement>& ends, const State& from, const State& to,
             std::vector<BodyField>& fields, State& probe) const;
  Vec3 centre(const State& bodies) const;  // what `escape` is measured from
  // Every particle of (x, outcomes) in flight farther than `escape` from the centre has escaped at `bodies`.
  void mark_escapes(const State& bodies, const Eigen::Matrix3Xd& x, std::vector<ParticleOutcome>& outcomes) const;
  // Throws IntegrationError when a particle in flight is no longer finite after the step to `t`.
  void check_finite(double t) const;
  ParticleOutcome landing(std::size_t surface, double ta, double tb, const Vec3& xa, const Vec3& va, const Vec3& xb,
                          const Vec3& vb, const State& from, const State& to, State& probe) const;

  const System& system_;
  ParticleSettings settings_;
  std::vector<std::vector<BodyField>> fields_;  // one copy per thread (the series holds scratch)
  std::vector<std::shared_ptr<const ForceModel>> pulling_;  // the forces whose point masses pull the particles
  std::vector<std::string> force_fields_;       // what each of the scene's forces is to the particles
  std::vector<std::string> surfaces_;           // the bodies' names, then the pulling point masses'
  std::vector<double> pull_radius_;             // each pulling point mass's radius (0: none)
  Eigen::Matrix3Xd x_, v_, a_;                  // a: the acceleration at x, at time t_
  Eigen::Matrix3Xd x_before_, v_before_;        // the recorded particles at the last step's start
  double t_before_ = 0.0;
  std::vector<ParticleOutcome> outcomes_;
  // The check's particles (their indices) at half the step: their own states and outcomes.
  std::vector<std::size_t> checked_;
  Eigen::Matrix3Xd x_half_, v_half_, a_half_;
  std::vector<ParticleOutcome> outcomes_half_;
  std::int64_t check_steps_ = 0;
  double t_ = 0.0;
  std::int64_t particle_steps_ = 0;
  double seconds_ = 0.0;
  struct Scratch;  // advance()'s buffers, kept from step to step
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace noether
