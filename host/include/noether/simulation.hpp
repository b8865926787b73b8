#pragma once
// Simulation: one run of a scene — plugins made by name, the integrator driven to t_end,
// diagnostics at every output frame, the HDF5 file written as it goes, and a summary.
#include <noether/chaos_values.hpp>
#include <noether/closest_approach.hpp>
#include <noether/orbit_period.hpp>
#include <noether/derived_error.hpp>
#include <noether/spin_state.hpp>
#include <noether/diagnostics.hpp>
#include <noether/integrator.hpp>
#include <noether/particle_check.hpp>
#include <noether/stepping.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include <csignal>
#include <filesystem>
#include <functional>
#include <memory>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace noether {

class ParticleSwarm;

struct RunOptions {
  std::optional<std::filesystem::path> output;  // HDF5 file, none if empty
  bool overwrite = false;                       // replace an existing output file (--force)
  // Called every 16 steps with t, the time the integrate() call began at and its end (the
  // driver's progress line, apps/noether/progress.hpp); none when empty.
  std::function<void(double t, double t_begin, double t_end)> progress;
  // Set asynchronously (a signal handler) to stop the run after the current step: the run
  // then ends like an event, with the output complete and stop_reason "interrupted".
  const volatile std::sig_atomic_t* interrupt = nullptr;
  // A wall-time budget in seconds (0: none): the run stops after the step that exhausts it,
  // like an event ("wall-time budget"), with the output complete up to there.
  double max_wall_seconds = 0.0;
  // Threads inside each evaluation of the potential (noether/evaluation_threads.hpp;
  // docs/user-guide.md, "Threads"): 0 takes NOETHER_THREADS from the environment, else 1.
  // The result is the same bit for bit for any number.
  int threads = 0;
};

// Whether a finished run can be trusted (docs/user-guide.md, "Verdict"): each check that
// failed, in words; none when the run is trustworthy.
struct Verdict {
  bool trustworthy = true;
  std::vector<std::string> reasons;
};

// An orbit the verdict judges on its own scale (docs/user-guide.md, "Verdict"): a body and the
// body that attracts it most at t0, one per pair, with the magnitude of the pair's two-body
// energy then, |½ μ v² − G m_a m_b / r| (or ½ μ v² + G m_a m_b / r for a near-parabolic
// pair). The run's energy error is judged against it as well as against E0, so that a small
// body's motion is not lost in the energy of large ones.
struct OrbitScale {
  std::string body, about;
  double energy_scale = 0.0;
  double relative_energy_error = 0.0;  // max |E − E0| / energy_scale (filled by judge)
  double relative_roundoff = 0.0;      // RunSummary::energy_roundoff / energy_scale (filled by judge)
  // The smallest orbit, when the energy certifies the run but not this orbit — its error, or the
  // round-off floor below which the energy sees nothing, is too large a part of the orbit's
  // energy (filled by judge): the resolution check decides.
  bool uncertified = false;
};

// The resolution check of an orbit the energy cannot certify (run when a run finishes): the
// scene integrated again — a fixed-step method's over one period of that orbit at h and at h/2,
// or whole at h/2; an adaptive method's whole at a tenfold tighter tolerance (a tenfold looser
// one, an upper bound, where tighter would ask for less than 1e-14) — and how far the orbit's
// relative position moved, as a fraction of the pair's separation.
struct ResolutionCheck {
  bool done = false;
  std::string body, about;
  // How the run was repeated ("at half the step", "at a tenfold tighter tolerance", …), the change made
  // ("halving the step", …), and what lowers the difference ("a smaller step", …).
  std::string how = "at half the step", change = "halving the step", remedy = "a smaller step";
  // A run that took at most run.rerun_seconds is repeated whole at h/2 (whole_run); a longer one
  // over one period of the orbit at h and h/2, extrapolated linearly.
  bool whole_run = false;
  double window = 0.0;          // the time integrated twice (the run, or one period in whole steps)
  double per_window = 0.0;      // |Δ(x_body − x_about)| / |x_body − x_about| at its end
  double over_run = 0.0;        // over the run: measured (whole_run) or extrapolated (≥ per_window)
  // Set when the run at h/2 ends otherwise (an event the run did not have, or not the run's):
  // the outcome itself is not resolved.
  std::string ends_differently;
};
// The wall time of a run up to which its step-halving check repeats it whole, unless the scene's
// run.rerun_seconds says otherwise (RunSettings::rerun_seconds).
inline constexpr double kWholeRunSeconds = RunSettings::kRerunSecondsDefault;


// The mutual period before and after a jump of the run (an impulse; docs/user-guide.md
// "Impulses"), each timed as RunSummary::mutual_period is over the stretch between jumps — the
// run's start or the jump before to this one, this one to the next or the end —, and their
// difference ΔP, each with its error (the run repeated at half the step; ΔP's own change, in
// which the errors the two periods share cancel).
struct PeriodChange {
  double t = 0.0;  // the jump
  double before = std::numeric_limits<double>::quiet_NaN(), after = std::numeric_limits<double>::quiet_NaN();
  int revolutions_before = 0, revolutions_after = 0;
  DerivedError before_error, after_error, change_error;
  bool measured() const { return revolutions_before > 0 && revolutions_after > 0; }
  double change() const { return after - before; }  // ΔP (NaN unless measured)
};

// What a force beyond the potential put into the run (docs/forces.md), from t0 to the end: the
// columns of State::force_balance (docs/equations.md eq. 33.3).
struct ForceSummary {
  std::string name;
  double work = 0.0;
  Vec3 linear_momentum = Vec3::Zero(), angular_momentum = Vec3::Zero();
};

// What became of the scene's massless particles (`particles:`; docs/user-guide.md, "Particles").
struct ParticleSummary {
  std::size_t count = 0;
  std::vector<std::string> bodies;   // what they can land on: the scene's bodies, then the prescribed bodies
  std::vector<std::size_t> impacts;  // landed on each body, in the scene's order
  std::size_t escaped = 0, in_flight = 0;
  std::int64_t steps = 0;  // Verlet steps, all particles
  double seconds = 0.0;    // wall time spent carrying them (the check's particles too)
  std::vector<std::string> fields;  // each body's field as the particles feel it (BodyField::describe), then each force's
  ParticleCheck check;              // the step-halving check (particles.check)
};

struct RunSummary {
  std::string potential;            // plugin names, "+"-joined
  std::string integrator;
  std::string units;                // the scene's units (Units::describe), when declared
  Diagnostics initial;
  Diagnostics final;
  double max_abs_energy_error = 0.0;            // max |E − E0| over output frames
  double max_rel_linear_momentum_error = 0.0;   // max ‖P − P0‖ / Σ‖γ_i(0)‖
  double max_rel_angular_momentum_error = 0.0;  // max ‖L − L0‖ / Σ(‖x_i×γ_i‖ + ‖Π_k‖) at t0
  double max_orthogonality_error = 0.0;         // max ‖I − RᵀR‖_F over frames and bodies
  // max |E − E0| / energy_scale: |E0|, or the initial kinetic energy T0 when |E0| < 10⁻³ T0
  double max_rel_energy_error = 0.0;
  std::string energy_scale = "|E0|";
  // What round-off allows |E − E0| to reach (filled by judge): ε (T0 + |U0|) (1 + √steps), the
  // double's ε times the sum of the energy's terms, its rounding at each step adding up as a
  // random walk. An error at this floor is not the integrator's: no step or tolerance lowers it.
  double energy_roundoff = 0.0;
  // What the scene conserves, read off the forces at t0: Σ f_i = 0 (no external force) and
  // Σ x_i × f_i + Σ R_k M_k = 0 (no external torque about the origin).
  bool conserves_linear_momentum = true, conserves_angular_momentum = true;
  // The smallest gap between two bodies seen (pairs with radii): between their surfaces when one
  // has a solid shape (docs/equations.md eq. 16.5), else ‖x_a − x_b‖ − (r_a + r_b).
  double min_gap = std::numeric_limits<double>::infinity();
  double min_gap_reach = 0.0;  // r_a + r_b of that pair
  std::string min_gap_pair;
  Verdict verdict;
  std::vector<OrbitScale> orbits;  // set at frame 0; the smallest scale first
  ResolutionCheck resolution;      // set when a run finishes (Simulation::finish)
  // Two-body-like scenes (two bodies hold 99 % of the mass): the period of their mutual orbit
  // measured from the trajectory — the time of the last whole revolution of their relative
  // position (in the plane of its t0 angular momentum, crossings interpolated between output
  // frames by a cubic Hermite in the angle and its rate) divided by the revolutions. NaN before
  // one revolution.
  std::string mutual_pair;  // "a–b" (empty: not two-body-like)
  double mutual_period = std::numeric_limits<double>::quiet_NaN();
  int mutual_revolutions = 0;
  // The frames were too far apart to follow the orbit (more than a third of a turn): the period
  // and the period changes are not measured (NaN, none) rather than aliased.
  bool mutual_undersampled = false;
  DerivedError mutual_period_error;  // set when a run finishes (Simulation::finish)
  std::vector<PeriodChange> period_changes;  // one per jump of the mutual orbit (its errors: at finish)
  // The scene's impulses applied so far (in this segment) and the energy they added: each moves
  // the references E0, P0, L0 by its jump, so the errors above are the integrator's alone.
  int impulses = 0;
  double impulse_energy = 0.0;
  // The scene's forces beyond the potential: what each put in. The errors above are measured from
  // E0 + W, P0 + ΔP and L0 + ΔL, which the forced flow conserves (docs/equations.md eq. 33.3).
  std::vector<ForceSummary> forces;
  // Each rigid body's libration about its binary's line of centres and its nutation, from the
  // output frames (docs/user-guide.md "Spin state").
  std::vector<SpinState> spin_states;
  // The chaos indicators at the run's last step (run.chaos; NaN without): docs/derivatives.md.
  bool chaos = false;
  ChaosValues chaos_values;
  std::string time_unit;    // the scene's unit of time, for the summary
  // The scene's units of energy and length when it declares units (empty otherwise): the
  // summary prints its numbers with them.
  std::string energy_unit, length_unit, angular_momentum_unit;
  // The closest approach of two body centres: at the output frames (scenes of 13 to 64 bodies),
  // or the least of closest_approaches (2 to 12 bodies).
  double min_distance = 0.0;
  double t_of_min_distance = 0.0;
  std::string min_distance_pair;                // "a–b"
  // Each pair's closest approach, located between the integrator's steps (scenes of 2 to 12
  // bodies), the closest first; its errors set when a run finishes.
  std::vector<ClosestApproach> closest_approaches;
  // Each body's orbit about the body it is bound to closest at the start but the binary's (timed as
  // mutual_period), its period measured from the trajectory (scenes of 3 to 64 bodies); its
  // errors set when a run finishes.
  std::vector<OrbitPeriod> orbit_periods;
  std::size_t frames = 0;
  std::int64_t interpolated_frames = 0;  // frames interpolated between the method's steps
  std::string stop_reason;  // empty when the run reached t_end; else the event that stopped it
  // An event's time (a collision's, an escape's: final_state.t) with its error by the run repeated
  // at half the step, when it stopped the run at the same event (set when a run finishes).
  DerivedError stop_time_error;
  State final_state;        // the state at the end of the run
  std::vector<PairModel> pair_models;  // what a tolerance-driven potential chose, per pair
  WorkCounters work;
  double wall_seconds = 0.0;
  int threads = 1;  // threads inside each evaluation of the potential (RunOptions::threads)
  ParticleSummary particles;  // count 0: the scene has none
  // What in the scene's input looks mistaken, with the numbers (an impulse that unbinds a bound
  // pair): said, not judged — the run is what was asked for.
  std::vector<std::string> warnings;
};

// The scene's forces beyond the potential (`forces:`), made by name: each named by its plugin and
// its `body` ("tides alpha").
std::shared_ptr<const Forcing> make_scene_forcing(const Scene& scene, PluginRegistry& registry);

// The scene's potential: its plugins made by name, summed when more than one.
std::shared_ptr<const Potential> make_scene_potential(const Scene& scene, PluginRegistry& registry);

// A run held open: integrate to a time, read or change the state, integrate on. `noether run`
// is one call of integrate(t_end); the Python module's Simulation is this class.
class Simulation {
 public:
  // Makes the plugins by name (or uses `potential` instead of the scene's: one written in
  // Python), creates the output file, and observes the initial state (frame 0).
  Simulation(Scene scene, PluginRegistry& registry, RunOptions options = {},
             std::shared_ptr<const Potential> potential = nullptr);
  // Continues the run recorded in `file` (killed, interrupted, out of its wall-time budget, or
  // finished when t_end extends it) from its last complete frame, appending to the same file
  // (`noether run --resume`, docs/user-guide.md "Continuing a run"). For fixed-step integrators
  // the continuation is bit for bit the uninterrupted run; adaptive ones start afresh from the
  // last frame's state. NaN t_end: the scene's.
  static std::unique_ptr<Simulation> resume(const std::filesystem::path& file, PluginRegistry& registry,
                                            RunOptions options = {},
                                            double t_end = std::numeric_limits<double>::quiet_NaN());
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Integrates to t > time(): frames at the scene's output times (counted from the run's t0)
  // and at t itself. Stops early at an event, an interrupt or the wall-time budget (the stop
  // reason says which; empty when t was reached). On an IntegrationError the state is the last
  // valid one, the output is finalized with the error, and the error propagates.
  // An impulse at t itself is applied before returning, unless `impulse_at_t` is false: then the
  // state is the one just before it, and the impulse comes first in the next call — which may
  // be integrate(t) again, to apply it and return (a fit samples both sides of an impulse).
  StopInfo integrate(double t, bool impulse_at_t = true);
  double time() const;
  // The integrator's fixed step (0 for adaptive methods): integrate(t) needs t − t0 to be a
  // whole number of them, except at the scene's t_end.
  double fixed_step() const;
  const State& state() const;
  // Replaces the state between calls, after checking it (shapes, finite values, attitudes in
  // SO(3) to 1e-10). The integrator starts again from it, which begins a new segment: the
  // summary's references (E0, momenta) are taken from this state.
  void set_state(const State& state);
  const Scene& scene() const;
  // The keys of the tangent's sensitivity columns (run.sensitivities, one per component), in
  // order; they follow the state-transition matrix's columns when run.stm is on too.
  const std::vector<std::string>& sensitivity_names() const;
  // ∂m_i/∂key for the sensitivity columns, bodies × columns: nonzero for keys that move a
  // body's mass (its mass, its density); with the momenta's columns, ∂v/∂key = (∂γ/∂key −
  // v ∂m/∂key) / m.
  Eigen::MatrixXd mass_sensitivities() const;
  const Potential& potential() const;
  // The scene's massless particles where the run stands (null: the scene has none).
  const ParticleSwarm* particles() const;
  // The summary so far, judged against run.trust.
  RunSummary summary() const;
  // Saves the simulation where it stands (the scene, the exact state, t0 and the step count,
  // work, and the summary's running values) to an HDF5 checkpoint; load() continues from it as
  // this simulation would — bit for bit for fixed-step integrators. A simulation with an
  // output file keeps writing there; the checkpoint does not copy its frames.
  void save(const std::filesystem::path& file) const;
  // A saved simulation. With options.output, the loaded one writes a new output file whose
  // frame 0 is the saved state (and whose summary starts there).
  // A simulation saved with a potential given in code (not the scene's plugins) needs that
  // potential again: `potential`; without it, loading such a checkpoint is refused.
  static std::unique_ptr<Simulation> load(const std::filesystem::path& file, PluginRegistry& registry,
                                          RunOptions options = {},
                                          std::shared_ptr<const Potential> potential = nullptr);
  // Writes the outcome to the output file and closes it (the destructor does it too); returns
  // the summary. Calling integrate() afterwards is an error.
  RunSummary finish();

  struct Impl;  // what a run held open consists of (internal: host/src/run/simulation_impl.hpp)

 private:
  std::unique_ptr<Impl> impl_;
};

// Runs the scene to its t_end: Simulation(scene).integrate(t_end), then finish(). On an
// IntegrationError the output written so far is finalized (readable, with the error recorded)
// and the error is rethrown.
RunSummary run_scene(const Scene& scene, PluginRegistry& registry, const RunOptions& options);

// The verdict on a finished run against the scene's run.trust thresholds (also fills
// max_rel_energy_error and energy_scale).
void judge(RunSummary& summary, const Scene& scene);

// One line per pair model (and one more where the run left the range it was chosen for).
std::string format_pair_models(const std::vector<PairModel>& models);

// The summary as printed by `noether run`.
std::string format_summary(const RunSummary& summary);
// The same as one JSON object (`noether run --summary json`): quantities a scene does not
// conserve or have are null.
std::string format_summary_json(const RunSummary& summary);

}  // namespace noether
