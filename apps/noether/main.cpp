// noether: the driver. `noether run | plugins | compare | orbit | check-potential`, `--version`.
// Each command lives in its own file (commands.hpp).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/version.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"noether: bodies under mutual gravity — the full body problem and point masses"};
  app.set_version_flag("--version", std::string("noether ") + NOETHER_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // --log-level also after the subcommand
  app.name("noether");
  std::string level = "warn";
  app.add_option("--log-level", level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));

  auto* run_cmd = app.add_subcommand("run", "integrate a scene and print a summary");
  std::string scene, output;
  std::vector<std::string> overrides;
  bool no_progress = false;
  run_cmd->add_option("scene", scene, "scene file (YAML)");
  run_cmd->add_option("-o,--output", output, "HDF5 output file");
  std::string resume;
  double resume_t_end = std::numeric_limits<double>::quiet_NaN();
  run_cmd->add_option("--resume", resume,
                      "continue the run recorded in this output file from its last complete frame, appending to it "
                      "(instead of a scene)");
  run_cmd->add_option("--t-end", resume_t_end, "with --resume: a later end time, to extend a run");
  run_cmd->add_option("--set", overrides, "override a scene key: --set integrator.step=1e-3")
      ->take_all();
  run_cmd->add_flag("--no-progress", no_progress, "no progress line on stderr");
  bool force = false;
  run_cmd->add_flag("--force", force, "overwrite an existing output file (never a link or the scene)");
  std::string summary_format = "text";
  run_cmd->add_option("--summary", summary_format, "the summary on stdout: text, or json (one object)")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();

  double max_wall_time = 0.0;
  run_cmd->add_option("--max-wall-time", max_wall_time,
                      "stop after this many seconds of wall time, like an event (output complete up to there)")
      ->check(CLI::NonNegativeNumber);

  auto* plugins_cmd = app.add_subcommand("plugins", "list every plugin found");

  auto* compare_cmd = app.add_subcommand(
      "compare", "run a scene under several integrators against a reference: work against precision");
  std::vector<std::string> runs;
  std::string spec_file, csv, h5, png;
  int repeats = 0;
  bool no_plot = false;
  compare_cmd->add_option("scene", scene, "scene file (YAML)")->required();
  compare_cmd->add_option("--set", overrides, "override a scene key")->take_all();
  compare_cmd->add_option("--run", runs,
                          "an integrator setting as YAML, lists expand: "
                          "'{plugin: lgvi, step: [1e-3, 5e-4]}' (repeatable; default: a standard sweep)");
  std::vector<std::string> models;
  std::string reference_model;
  compare_cmd->add_option("--model", models,
                          "a potential as YAML, lists expand: '{plugin: mutual-series, tolerance: [1e-3, 1e-6]}' "
                          "(repeatable; runs the scene's integrator with each model)");
  compare_cmd->add_option("--reference-model", reference_model,
                          "the potential of the reference run for --model (default {plugin: mutual-exact})");
  compare_cmd->add_option("--spec", spec_file, "compare file: {repeats, reference, runs: [...]}");
  compare_cmd->add_option("--repeats", repeats, "repeats per run for the median wall time (default 3)");
  compare_cmd->add_option("-o,--csv", csv, "CSV table (default SCENE-compare.csv)");
  compare_cmd->add_option("--h5", h5, "HDF5 table (default SCENE-compare.h5)");
  compare_cmd->add_option("--plot", png, "work–precision plot (default SCENE-compare.png)");
  compare_cmd->add_flag("--no-plot", no_plot, "do not draw the plot");
  compare_cmd->add_option("--max-wall-time", max_wall_time,
                          "wall-time budget of each compared run in seconds (not the reference); a run that exhausts it is listed as stopped")
      ->check(CLI::NonNegativeNumber);

  auto* ensemble_cmd = app.add_subcommand(
      "ensemble", "run a scene many times with keys drawn from distributions, on every core, into one HDF5 file");
  std::vector<std::string> vary;
  noether::app::EnsembleCommand ensemble;
  ensemble_cmd->add_option("scene", scene, "scene file (YAML)")->required();
  ensemble_cmd->add_option("--vary", vary,
                           "KEY=DIST: normal(mean, sd), uniform(a, b), log-uniform(a, b), list(v1, ...), grid(a, b, n) "
                           "(repeatable; KEY as for --set)")
      ->required();
  ensemble_cmd->add_option("--samples", ensemble.samples, "number of samples (default: the grids' points)");
  ensemble_cmd->add_option("--seed", ensemble.seed, "random seed: sample i draws from (seed, i)")->capture_default_str();
  ensemble_cmd->add_option("--threads", ensemble.threads, "worker threads (default: one per core)");
  ensemble_cmd->add_option("--pair", ensemble.pair, "a,b: the bodies whose mutual orbit is recorded (default: the first two)");
  ensemble_cmd->add_option("--trajectories", ensemble.trajectories,
                           "write full output files for the first K samples (ENS-sample-I.h5)");
  ensemble_cmd->add_option("-o,--output", ensemble.output, "the ensemble's HDF5 file")->required();
  ensemble_cmd->add_option("--set", overrides, "override a scene key for every sample")->take_all();
  ensemble_cmd->add_flag("--resume", ensemble.resume, "continue the ensemble in the output file: run only missing samples");
  ensemble_cmd->add_flag("--force", ensemble.force, "replace an existing output file");

  const CLI::Validator positive(
      [](std::string& v) -> std::string {
        try {
          if (std::stod(v) > 0) return {};
        } catch (const std::exception&) {
        }
        return "must be a positive number, not " + v;
      },
      "> 0");
  auto* orbit_cmd = app.add_subcommand("orbit", "periodic orbits: find (least action), verify, stability, refine; relative equilibria of rigid bodies");
  orbit_cmd->require_subcommand(1);
  noether::app::OrbitOptions orbit;
  auto* find_cmd = orbit_cmd->add_subcommand("find", "minimize a Fourier-discretized action from random starts");
  auto* bodies_opt = find_cmd->add_option("--bodies", orbit.bodies, "number of bodies (equal masses, G = 1, point-mass)")
                         ->capture_default_str();
  find_cmd->add_option("--masses", orbit.masses, "masses (overrides --bodies)")->delimiter(',');
  find_cmd->add_option("--scene", orbit.scene,
                       "take the bodies, G and potential from this scene instead (point masses, planar)");
  find_cmd->add_option("--set", orbit.overrides, "override a key of --scene")->take_all();
  find_cmd->add_option("--period", orbit.period, "period T of the orbits sought (default 2 pi)")->check(positive);
  find_cmd->add_option("--modes", orbit.modes, "Fourier modes per coordinate")->capture_default_str();
  find_cmd->add_option("--points", orbit.points, "quadrature points (default: 100, or more than 2 × modes)");
  find_cmd->add_flag("--choreography", orbit.choreography, "all bodies on one curve, z_j(t) = z(t + 2 pi j/n)");
  find_cmd->add_option("--seed", orbit.seed, "random seed")->capture_default_str();
  find_cmd->add_option("--starts", orbit.starts, "random starts")->capture_default_str();
  find_cmd->add_option("--out-dir", orbit.out_dir, "folder for orbit-K.yaml, .csv and .png")->capture_default_str();
  bool no_refine = false;
  find_cmd->add_flag("--no-refine", no_refine, "skip the Newton (shooting) refinement");
  find_cmd->add_option("--max-residual", orbit.max_residual,
                       "largest equation-of-motion residual along the Fourier curve to try to refine")
      ->capture_default_str();
  std::vector<CLI::App*> orbit_scene_cmds;
  for (auto [name, help] : {std::pair{"verify", "integrate one period and report the closure error"},
                            std::pair{"stability", "monodromy multipliers with the first integrals projected out"},
                            std::pair{"refine", "Newton (shooting) on the initial state and period"}}) {
    auto* c = orbit_cmd->add_subcommand(name, help);
    c->add_option("scene", orbit.scene, "scene of the orbit (YAML)")->required();
    c->add_option("--period", orbit.period, "period (default: the scene's run.t_end)")->check(positive);
    c->add_option("--set", orbit.overrides, "override a scene key")->take_all();
    c->add_option("--rtol", orbit.rtol, "relative tolerance of the rkf78 integration")->capture_default_str();
    orbit_scene_cmds.push_back(c);
  }
  orbit_scene_cmds[0]->add_option("--tolerance", orbit.tolerance, "closure accepted (relative)")->capture_default_str();
  orbit_scene_cmds[1]->add_option("--tolerance", orbit.tolerance, "|lambda| <= 1 + tolerance is stable")->capture_default_str();
  orbit_scene_cmds[1]->add_option("--first-order", orbit.first_order, "also Vanderbei's first-order product with N steps");
  orbit_scene_cmds[1]->add_option("--plot", orbit.plot, "PNG: the multipliers and the unit circle; data in the .csv beside it");
  orbit_scene_cmds[1]->add_option("--turns", orbit.angle_turns,
                                  "rigid bodies: whole turns to add to the measured angle alpha")->capture_default_str();
  orbit_scene_cmds[2]->add_option("-o,--output", orbit.output, "refined scene (default: overwrite the input)");

  auto* equilibrium_cmd = orbit_cmd->add_subcommand(
      "equilibrium", "relative equilibrium of rigid bodies (locked, turning about the angular momentum) and its stability");
  bool no_align = false;
  equilibrium_cmd->add_option("scene", orbit.scene, "scene whose state is the first guess (YAML)")->required();
  equilibrium_cmd->add_option("--set", orbit.overrides, "override a scene key")->take_all();
  equilibrium_cmd->add_option("--fix", orbit.fix, "the member of the family: separation, angular-momentum or rate")
      ->check(CLI::IsMember({"separation", "angular-momentum", "rate"}))->capture_default_str();
  equilibrium_cmd->add_option("--value", orbit.value, "its value (default: the scene's)");
  equilibrium_cmd->add_option("--pair", orbit.pair, "a,b: the bodies whose separation is fixed (default: the first two)")
      ->delimiter(',')->expected(2);
  equilibrium_cmd->add_option("--sweep", orbit.sweep, "from,to,count: a table along the family, each solution the next guess")
      ->delimiter(',')->expected(3);
  equilibrium_cmd->add_option("--sweep-key", orbit.sweep_key,
                              "KEY: --sweep varies this scene key (a mass, a semi-axis) with the --fix quantity held");
  equilibrium_cmd->add_option("--tolerance", orbit.tolerance, "|Re lambda| <= tolerance x max(omega, |lambda|) is stable")
      ->capture_default_str();
  equilibrium_cmd->add_flag("--no-align", no_align, "keep the guess's attitudes (default: principal axes turned onto the angular momentum)");
  equilibrium_cmd->add_option("-o,--output", orbit.output, "write the equilibrium as a scene (one period)");
  equilibrium_cmd->add_option("--libration", orbit.libration,
                              "NAME,DEG: with -o, that body turned by DEG about the axis, librating (four libration periods)")
      ->delimiter(',')->expected(2);
  equilibrium_cmd->add_option("--lyapunov", orbit.lyapunov,
                              "NAME,DEG: the periodic orbit of that body's libration at that amplitude, on the scene's "
                              "integrator; with -o, written as a scene of one period")
      ->delimiter(',')->expected(2);
  equilibrium_cmd->add_option("--plot", orbit.plot,
                              "PNG: the eigenvalues (or, with --sweep, the modes along the family); data in the .csv beside it");

  auto* check_cmd = app.add_subcommand(
      "check-potential",
      "check a scene's potential: forces and moments against finite differences of U, and "
      "Newton's third law, at the scene's state and at perturbed states");
  noether::PotentialCheckOptions check_options;
  bool no_third_law = false;
  check_cmd->add_option("scene", scene, "scene file (YAML)")->required();
  check_cmd->add_option("--set", overrides, "override a scene key")->take_all();
  check_cmd->add_option("--tolerance", check_options.tolerance,
                        "finite-difference agreement, relative to the largest force or moment")
      ->capture_default_str();
  check_cmd->add_option("--states", check_options.perturbed_states, "perturbed states to check")
      ->capture_default_str();
  check_cmd->add_flag("--no-third-law", no_third_law,
                      "skip the net force and torque rows (for external-field models)");

  if (argc == 1) {  // bare `noether`: the help
    std::cout << app.help();
    return 0;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, the version, or the usage error
    return code == 0 ? 0 : 2;      // usage errors exit 2, as documented
  }
  orbit.bodies_given = bodies_opt->count() > 0;
  orbit.refine = !no_refine;
  orbit.align = !no_align;
  spdlog::set_level(spdlog::level::from_str(level));
  try {
    if (*run_cmd) {
      if (resume.empty() == scene.empty()) {
        std::cerr << "noether run: give a scene, or --resume FILE.h5 (not both)\n";
        return 2;
      }
      if (!resume.empty() && (!output.empty() || !overrides.empty() || force)) {
        std::cerr << "noether run: --resume appends to the file it continues, with the scene recorded there: "
                     "-o, --set and --force do not apply (extend a run with --t-end)\n";
        return 2;
      }
      if (resume.empty() && !std::isnan(resume_t_end)) {
        std::cerr << "noether run: --t-end goes with --resume; for a new run use --set run.t_end=T\n";
        return 2;
      }
      return noether::app::run(scene, output, overrides, !no_progress, force, summary_format == "json",
                               max_wall_time, resume, resume_t_end);
    }
    if (*plugins_cmd) return noether::app::list_plugins();
    if (*ensemble_cmd) return noether::app::ensemble(scene, overrides, vary, ensemble);
    if (*find_cmd) return noether::app::orbit_find(orbit);
    if (*orbit_scene_cmds[0]) return noether::app::orbit_verify(orbit);
    if (*orbit_scene_cmds[1]) return noether::app::orbit_stability(orbit);
    if (*orbit_scene_cmds[2]) return noether::app::orbit_refine(orbit);
    if (*equilibrium_cmd) return noether::app::orbit_equilibrium(orbit);
    if (*compare_cmd) return noether::app::compare(scene, overrides, runs, models, reference_model, spec_file, repeats, csv, h5, png,
                                     !no_plot, max_wall_time);
    if (*check_cmd) {
      check_options.third_law = !no_third_law;
      return noether::app::check_potential(scene, overrides, check_options);
    }
  } catch (const noether::Error& e) {
    std::cerr << "noether: " << e.what() << "\n";
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {  // e.g. a read-only --out-dir
    std::cerr << "noether: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "noether: unexpected error: " << e.what() << "\n";
    return 4;
  }
  return 0;
}
