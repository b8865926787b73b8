#pragma once
// Scene: reads a YAML scene (docs/user-guide.md), applies --set overrides, validates
// it, and builds the System and the initial State. Every error names file, line and field.
#include <noether/params.hpp>
#include <noether/state.hpp>
#include <noether/stepping.hpp>
#include <noether/system.hpp>
#include <noether/units.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace noether {

struct PluginConfig {
  std::string plugin;  // plugin name
  Params params;       // the whole mapping, including "plugin"
};

// When a finished run is called untrustworthy (docs/user-guide.md, "Verdict"): scene key
// run.trust.
struct TrustThresholds {
  double energy = 1e-2;         // max |E − E0| / energy scale
  double momentum = 1e-6;       // relative linear and angular momentum errors, where conserved
  double orthogonality = 1e-6;  // max ‖I − RᵀR‖_F
  // An orbit the energy cannot certify (a small body's): its relative position error over the
  // run, estimated by halving the step over one orbit (docs/user-guide.md, "Verdict"); and the
  // checked particles' positions and landing points at half their step (particles.check).
  double position = 1e-2;
  // The fraction of the checked particles whose fate changes at half their step.
  double particle_fates = 0.05;
  // A mutual orbit period's estimated error over the period (RunSummary::mutual_period_error):
  // 1e-3, 43 s of Didymos' 11.9 h, well inside the ±1 min to which DART's ΔP of −33 min was
  // measured (docs/user-guide.md, "Verdict"); and a rotation period's (SpinState::spin_period_error).
  double period = 1e-3;
  // An impulse's period change ΔP: its estimated error over |ΔP| (PeriodChange::change_error):
  // 1e-3, half the 2.2e-3 to which DART's was measured (Scheirich et al. 2024: −33.240 ± 0.072
  // min).
  double period_change = 1e-3;
  // A libration amplitude's estimated error over the amplitude (SpinState::libration_error),
  // and a libration period's over the period (libration_period_error):
  // 0.1, twice the frames' own sampling of the extremes at ten frames a libration period
  // (docs/user-guide.md, "Spin state").
  double libration = 0.1;
  // A closest approach between frames (an encounter): its distance's estimated error — the run
  // at half the step, and the frames' interpolation — over the distance (ClosestApproach):
  // 1e-3, a kilometre at a thousand.
  double closest_approach = 1e-3;
  // The time of the event that stopped the run (a collision, an escape): its estimated error over
  // the time run until it.
  double event_time = 1e-3;
};

struct RunSettings {
  // The longest run, in wall seconds, repeated whole when it finishes — at half the step, or an
  // adaptive method at a tenfold tighter tolerance — for the errors of the numbers it derives and
  // a small orbit's resolution (docs/user-guide.md "Verdict"); 0: never. run.rerun_seconds.
  static constexpr double kRerunSecondsDefault = 30.0;
  double rerun_seconds = kRerunSecondsDefault;
  double t_end = 0.0;
  double output_every = 0.0;
  double close_approach = 0.0;  // stop when two centres come closer (0: off)
  bool collisions = true;       // stop when two bodies touch (their shapes, else their radii)
  std::optional<Escape> escape;  // run.escape: stop when a body leaves another
  // Carry the state-transition matrix ∂z(t)/∂z(t0) of the integrator's own map through the run
  // (`noether run --stm`; docs/derivatives.md): /derivatives/stm at every output frame.
  bool stm = false;
  // Keys of the bodies' initial states (run.sensitivities, `noether run --sensitivity KEY`;
  // docs/derivatives.md): ∂z(t)/∂key at every output frame, /derivatives/sensitivity.
  std::vector<std::string> sensitivities;
  // Chaos indicators (run.chaos, `noether run --chaos`; docs/derivatives.md): MEGNO and the fast
  // Lyapunov indicator from a deviation vector the tangent map carries, /derivatives/megno and
  // /derivatives/fli at every output frame and their last values in the summary.
  bool chaos = false;
  TrustThresholds trust;
  // Whether the run carries a tangent at all (run.stm, run.sensitivities, run.chaos).
  bool carries_tangent() const { return stm || !sensitivities.empty() || chaos; }
};

// An instantaneous change of a body's velocity during the run (the scene's `impulses:`; a kinetic
// impactor such as DART): at `time` its linear momentum jumps by m Δv (docs/user-guide.md,
// "Impulses"; docs/equations.md §24).
struct Impulse {
  // The axes delta_v is given in: the scene's inertial ones, or the RTN frame of the body's orbit
  // about `around` at `time` (radial, along-track, normal; docs/equations.md eq. 24.4).
  enum class Frame { inertial, rtn };
  std::size_t body = 0;
  double time = 0.0;
  Vec3 delta_v = Vec3::Zero();  // in `frame`, the scene's unit of velocity
  Frame frame = Frame::inertial;
  std::size_t around = 0;  // for rtn: the body orbited (default: the heaviest other body)
};

// Massless particles (the scene's `particles:`; docs/user-guide.md, "Particles"): their initial
// states and how they are carried (particles.hpp).
struct ParticleCheckpoint;  // particles.hpp

struct ParticleSettings {
  std::vector<Vec3> position, velocity;  // initial, inertial, in the scene's units
  // `around`: the body the states are given relative to (`states`, `file`) or about (`orbits`),
  // and that `escape` is measured from (else the bodies' barycentre).
  std::optional<std::size_t> around;
  // The particles' longest Verlet step (38.3): each step of the bodies is cut into equal
  // substeps no longer than this. 0: one Verlet step per step of the bodies (fixed-step
  // integrators only: one that chooses its steps needs a particle step).
  double step = 0.0;
  int degree = 16;           // of the bodies' series fields (BodyFieldOptions)
  double tolerance = 1e-10;  // of the series against a polyhedron's exact field (38.2)
  double escape = 0.0;       // a particle farther than this has escaped (0: never)
  std::size_t record = 100;  // the first this many particles' positions at every output frame
  // How many particles, spread evenly through the list, are carried a second time at half the
  // step for the verdict (docs/user-guide.md, "Particles"; 0: none).
  std::size_t check = 32;
  // Where a loaded simulation's particles stand (Simulation::load): the swarm starts from it,
  // not from `position` and `velocity` (which stay the t0 states); none for a new run.
  std::shared_ptr<const ParticleCheckpoint> restored;
  bool empty() const { return position.empty(); }
};

struct Scene {
  std::string file;                      // as given, for messages
  std::string text;                      // the scene text as read (before overrides)
  std::vector<std::string> overrides;    // "key=value" as given
  Params root;                           // the resolved tree (after overrides)
  Units units;                           // as declared (`units:`), or the scene's own
  System system;
  State initial;
  // Where the models make their choices (a tolerance's orders, Potential::choose_models): the
  // initial state, unless the scene continues a run from another state (a loaded simulation,
  // whose initial state is where the file stood) — then the run's own initial state, so that it
  // goes on with the models the run had. models_state() says which.
  std::optional<State> models_chosen_at;
  const State& models_state() const { return models_chosen_at ? *models_chosen_at : initial; }
  std::vector<PluginConfig> potentials;  // summed when more than one
  std::vector<PluginConfig> forces;      // forces beyond the potential (`forces:`), none by default
  PluginConfig integrator;
  RunSettings run;
  std::vector<Impulse> impulses;  // in the scene's order (keys impulses.K.…), times after t0
  ParticleSettings particles;     // none unless the scene has `particles:`
  // Values allowed but that look like slips (scene/input_warnings.hpp: a spin beyond breakup, a
  // step longer than the shortest period, a density no body has), each with the numbers and its
  // key's file:line. The run's summary carries them; `noether run` prints them as it starts.
  std::vector<std::string> warnings;
};

// The scene as run (its resolved tree, after the overrides) as YAML text: load_scene on it
// gives the same scene.
std::string scene_as_run(const Scene& scene);

// YAML text or file → Params (for compare specs and other YAML inputs), with file:line.
Params parse_params(const std::string& text, const std::string& file);
Params load_params_file(const std::filesystem::path& file);

// Overrides are "dotted.key=value" (value parsed as YAML); sequence items by index, bodies
// also by name: "bodies.alpha.mass=2".
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::string>& overrides = {});

}  // namespace noether
