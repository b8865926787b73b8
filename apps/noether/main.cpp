// noether: the driver. `noether run SCENE`, `noether plugins`, `noether --version`.
#include <noether/compare.hpp>
#include <noether/error.hpp>
#include <noether/least_action.hpp>
#include <noether/periodic_orbit.hpp>
#include <noether/potential_check.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>
#include <noether/version.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <iostream>
#include <unistd.h>

namespace {

int run(const std::string& scene_file, const std::string& output,
        const std::vector<std::string>& overrides, bool progress) {
  const noether::Scene scene = noether::load_scene(scene_file, overrides);
  noether::PluginRegistry registry;
  noether::RunOptions options;
  if (!output.empty()) options.output = output;
  options.progress = progress;
  try {
    const auto summary = noether::run_scene(scene, registry, options);
    std::cout << "scene                         " << scene_file << "\n"
              << noether::format_summary(summary);
    if (!output.empty()) std::cout << "output                        " << output << "\n";
  } catch (const noether::IntegrationError& e) {
    std::cerr << "noether: integration stopped at t = " << e.t_reached() << ": " << e.what()
              << "\n";
    if (!output.empty())
      std::cerr << "noether: the output up to that time is in " << output << "\n";
    return 3;
  }
  return 0;
}

int list_plugins() {
  noether::PluginRegistry registry;
  std::vector<std::string> failures;
  const auto plugins = registry.load_all(failures);
  if (plugins.empty() && failures.empty()) {
    std::cerr << "noether: no plugins found; searched:";
    for (const auto& d : registry.search_path()) std::cerr << ' ' << d.string();
    std::cerr << "\n";
    return 1;
  }
  for (const auto& p : plugins) {
    std::printf("%-11s %-16s %s\n", noether::to_string(p.kind), p.name.c_str(),
                p.description.c_str());
    for (const auto& d : p.params)
      std::printf("%30s%-22s %s (%s%s%s)\n", "", d.name, d.description, d.type,
                  d.default_value ? ", default " : ", required",
                  d.default_value ? d.default_value : "");
    std::printf("%30sfrom %s\n", "", p.file.string().c_str());
  }
  for (const auto& f : failures) std::fprintf(stderr, "noether: %s\n", f.c_str());
  return failures.empty() ? 0 : 1;
}

// The work–precision plot is drawn by tools/plot_compare.py (Debian's python3-matplotlib):
// installed in <prefix>/share/noether, or found in the source tree of a build.
std::string plot_script() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path& candidate :
       {exe.parent_path() / ".." / "share" / "noether" / "plot_compare.py",
        fs::path(NOETHER_SOURCE_DIR) / "tools" / "plot_compare.py"})
    if (fs::exists(candidate, ec)) return candidate.string();
  return {};
}

int compare(const std::string& scene_file, const std::vector<std::string>& overrides,
            const std::vector<std::string>& runs, const std::string& spec_file, int repeats,
            std::string csv, std::string h5, std::string png, bool plot) {
  const noether::Scene scene = noether::load_scene(scene_file, overrides);
  noether::PluginRegistry registry;
  noether::CompareSpec spec = spec_file.empty() ? noether::default_compare_spec(scene)
                                                : noether::load_compare_spec(spec_file, scene);
  if (!runs.empty()) {
    spec.runs.clear();
    for (std::size_t k = 0; k < runs.size(); ++k)
      for (auto& r : noether::expand_runs(noether::parse_params(runs[k], "--run " + std::to_string(k + 1))))
        spec.runs.push_back(std::move(r));
  }
  if (repeats > 0) spec.repeats = repeats;
  const std::string stem = std::filesystem::path(scene_file).stem().string() + "-compare";
  if (csv.empty()) csv = stem + ".csv";
  if (h5.empty()) h5 = stem + ".h5";
  if (png.empty()) png = stem + ".png";
  const auto result = noether::compare(scene, registry, spec, [](const std::string& m) {
    std::cerr << "compare: " << m << "\n";
  });
  std::cout << "scene " << scene_file << "\n" << noether::format_compare(result);
  noether::write_compare_csv(result, csv);
  noether::write_compare_h5(result, scene, h5);
  std::cout << "table: " << csv << ", " << h5 << "\n";
  if (plot) {
    const std::string script = plot_script();
    const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
    const std::string command = python + " '" + script + "' '" + csv + "' '" + png + "' --title '" +
                                scene_file + "'";
    if (script.empty() || std::system(command.c_str()) != 0)
      std::cerr << "noether: could not draw the plot (needs python3-matplotlib; command: "
                << command << "); the table is written\n";
    else
      std::cout << "plot: " << png << "\n";
  }
  for (const auto& row : result.rows)
    if (!row.ok) return 3;
  return 0;
}

// noether orbit …: periodic orbits of planar point masses (docs/periodic-orbits.md).
struct OrbitOptions {
  std::string scene;
  std::vector<std::string> overrides;
  double period = 0;  // 0: the scene's run.t_end
  double rtol = 1e-13, tolerance = 1e-6;
  int first_order = 0;
  std::string output;
  // find
  std::vector<double> masses;
  int bodies = 3, modes = 15, points = 0, starts = 20;
  unsigned seed = 1;
  bool choreography = false, refine = true;
  double max_residual = 1e-2;
  std::string out_dir = ".";
};

noether::PlanarSystem orbit_system(const OrbitOptions& o, Eigen::VectorXd& xi, double& T) {
  const noether::Scene scene = noether::load_scene(o.scene, o.overrides);
  auto sys = noether::PlanarSystem::from(scene.system, scene.initial, xi);
  T = o.period > 0 ? o.period : scene.run.t_end;
  return sys;
}

noether::FlowOptions flow_options(const OrbitOptions& o) {
  noether::FlowOptions f;
  f.rtol = o.rtol;
  f.atol = o.rtol * 1e-2;
  return f;
}

int orbit_verify(const OrbitOptions& o) {
  Eigen::VectorXd xi;
  double T;
  const auto sys = orbit_system(o, xi, T);
  const auto f = noether::integrate_flow(sys, xi, T, false, flow_options(o));
  const double closure = (f.end - xi).norm();
  std::printf("period %.15g, rkf78 rtol %.1e, %zu steps\nclosure ||xi(T) - xi(0)|| = %.3e (relative %.3e)\n", T,
              o.rtol, f.steps, closure, closure / xi.norm());
  std::printf("energy %.15g\n", sys.energy(xi));
  if (closure <= o.tolerance * std::max(1.0, xi.norm())) return 0;
  std::fprintf(stderr, "noether: the orbit does not close: relative closure %.3e > tolerance %.1e (wrong period, "
               "or not a periodic orbit; try noether orbit refine)\n", closure / std::max(1.0, xi.norm()), o.tolerance);
  return 1;
}

int orbit_stability(const OrbitOptions& o) {
  Eigen::VectorXd xi;
  double T;
  const auto sys = orbit_system(o, xi, T);
  const auto f = noether::integrate_flow(sys, xi, T, true, flow_options(o));
  const auto s = noether::stability(sys, xi, f.monodromy, o.tolerance);
  std::printf("period %.15g, closure %.3e, variational equations by rkf78 rtol %.1e (%zu steps)\n", T,
              (f.end - xi).norm(), o.rtol, f.steps);
  std::printf("multipliers of P Phi(T) P (first integrals projected out), by modulus:\n");
  for (auto l : s.multipliers)
    if (std::abs(l) > 1e-9) std::printf("  %+.10f %+.10fi   |lambda| = %.12f\n", l.real(), l.imag(), std::abs(l));
  std::printf("max |lambda(Phi)| = %.10f, max |lambda(P Phi P)| = %.10f\n", s.max_unprojected, s.max_projected);
  if (o.first_order > 0) {
    const auto M = noether::first_order_monodromy(sys, xi, T, static_cast<std::size_t>(o.first_order), flow_options(o));
    const auto s1 = noether::stability(sys, xi, M, o.tolerance);
    std::printf("the seed's first-order product with %d steps: max |lambda| = %.4f, projected %.4f\n", o.first_order,
                s1.max_unprojected, s1.max_projected);
  }
  std::printf("verdict: %s (tolerance %.1e)\n", s.verdict.c_str(), o.tolerance);
  return 0;
}

int orbit_refine(const OrbitOptions& o) {
  Eigen::VectorXd xi;
  double T;
  const auto sys = orbit_system(o, xi, T);
  const double before = (noether::integrate_flow(sys, xi, T, false, flow_options(o)).end - xi).norm();
  const auto r = noether::refine_periodic_orbit(sys, xi, T, 1e-12, 12, flow_options(o));
  std::printf("closure %.3e -> %.3e in %d Newton steps; period %.15g -> %.15g\n", before, r.closure, r.iterations, T, r.period);
  const std::string out = o.output.empty() ? o.scene : o.output;
  std::ofstream(out) << noether::orbit_scene(sys, r.xi0, r.period, "refined by noether orbit refine from " + o.scene);
  std::printf("written: %s\n", out.c_str());
  return r.closure <= 1e-10 ? 0 : 1;
}

int orbit_find(OrbitOptions o) {
  noether::LeastActionProblem p;
  p.masses = o.masses.empty() ? std::vector<double>(static_cast<std::size_t>(o.bodies), 1.0) : o.masses;
  p.modes = o.modes;
  p.choreography = o.choreography;
  p.points = o.points > 0 ? o.points : [&] {  // the seed's 100, adjusted: > 2F, multiple of n
    int m = std::max(100, 2 * o.modes + 2);
    while (p.choreography && m % static_cast<int>(p.masses.size()) != 0) ++m;
    return m;
  }();
  p.validate();
  std::filesystem::create_directories(o.out_dir);
  std::vector<double> found_actions;
  int k = 0, failures = 0;
  for (int s = 0; s < o.starts; ++s) {
    const auto orbit = noether::minimize_action(p, noether::random_start(p, o.seed + static_cast<unsigned>(s)));
    std::printf("start %3d: action %.10f, EOM residual %.2e, min distance %.3f", s, orbit.action, orbit.residual,
                orbit.min_distance);
    bool seen = false;
    for (double a : found_actions) seen |= std::abs(a - orbit.action) < 1e-6 * std::abs(a);
    if (orbit.residual > o.max_residual || orbit.min_distance < 1e-3) {
      std::printf("  (rejected: EOM residual above %.0e, not a solution at this truncation)\n", o.max_residual);
      ++failures;
      continue;
    }
    if (seen) {
      std::printf("  (found before)\n");
      continue;
    }
    noether::PlanarSystem sys;
    sys.masses = p.masses;
    Eigen::VectorXd xi = orbit.initial_state(p);
    double T = 2 * std::numbers::pi;
    double closure = (noether::integrate_flow(sys, xi, T, false).end - xi).norm();
    if (o.refine) {
      const auto r = noether::refine_periodic_orbit(sys, xi, T);
      if (r.closure < closure) xi = r.xi0, T = r.period, closure = r.closure;
    }
    if (closure > 1e-8 * std::max(1.0, xi.norm())) {  // verified by integration, or not an orbit
      std::printf("  (rejected: closure %.1e after one period)\n", closure);
      ++failures;
      continue;
    }
    std::printf("\n");
    found_actions.push_back(orbit.action);
    ++k;
    const std::string stem = (std::filesystem::path(o.out_dir) / ("orbit-" + std::to_string(k))).string();
    char desc[256];
    std::snprintf(desc, sizeof desc, "least-action orbit %d: action %.10f, EOM residual %.2e, closure %.2e", k,
                  orbit.action, orbit.residual, closure);
    std::ofstream(stem + ".yaml") << noether::orbit_scene(sys, xi, T, desc);
    std::ofstream curve(stem + ".csv");
    curve << "t";
    for (std::size_t j = 0; j < p.n(); ++j) curve << ",x" << j + 1 << ",y" << j + 1;
    curve << "\n";
    for (int i = 0; i <= 400; ++i) {
      const double t = 2 * std::numbers::pi * i / 400;
      curve << t;
      for (std::size_t j = 0; j < p.n(); ++j) {
        const auto z = noether::fourier_position(p, orbit.coefficients, j, t);
        curve << ',' << z.x() << ',' << z.y();
      }
      curve << "\n";
    }
    curve.close();  // complete on disk before the plotting script reads it
    std::printf("  -> %s.yaml (period %.12f, closure %.2e after refinement)\n", stem.c_str(), T, closure);
    const std::string script = std::filesystem::path(plot_script()).parent_path() / "plot_orbit.py";
    const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
    const std::string cmd = python + " '" + script + "' '" + stem + ".csv' '" + stem + ".png' --title '" + desc + "'";
    if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "noether: could not draw %s.png\n", stem.c_str());
  }
  std::printf("%d distinct orbits from %d starts (%d starts rejected)\n", k, o.starts, failures);
  return k > 0 ? 0 : 1;
}

int check_potential(const std::string& scene_file, const std::vector<std::string>& overrides,
                    const noether::PotentialCheckOptions& options) {
  const noether::Scene scene = noether::load_scene(scene_file, overrides);
  noether::PluginRegistry registry;
  const auto potential = noether::make_scene_potential(scene, registry);
  const auto report = noether::check_potential(scene.system, *potential, scene.initial, options);
  std::string names;
  for (const auto& p : scene.potentials) names += (names.empty() ? "" : "+") + p.plugin;
  std::cout << "potential " << names << " of " << scene_file << "\n" << report.format();
  return report.passed() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"noether: bodies under mutual gravity — the full body problem and point masses"};
  app.set_version_flag("--version", std::string("noether ") + NOETHER_VERSION);
  app.require_subcommand(1);
  std::string level = "warn";
  app.add_option("--log-level", level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));

  auto* run_cmd = app.add_subcommand("run", "integrate a scene and print a summary");
  std::string scene, output;
  std::vector<std::string> overrides;
  bool no_progress = false;
  run_cmd->add_option("scene", scene, "scene file (YAML)")->required();
  run_cmd->add_option("-o,--output", output, "HDF5 output file");
  run_cmd->add_option("--set", overrides, "override a scene key: --set integrator.step=1e-3")
      ->take_all();
  run_cmd->add_flag("--no-progress", no_progress, "no progress line on stderr");

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
  compare_cmd->add_option("--spec", spec_file, "compare file: {repeats, reference, runs: [...]}");
  compare_cmd->add_option("--repeats", repeats, "repeats per run for the median wall time (default 3)");
  compare_cmd->add_option("-o,--csv", csv, "CSV table (default SCENE-compare.csv)");
  compare_cmd->add_option("--h5", h5, "HDF5 table (default SCENE-compare.h5)");
  compare_cmd->add_option("--plot", png, "work–precision plot (default SCENE-compare.png)");
  compare_cmd->add_flag("--no-plot", no_plot, "do not draw the plot");

  auto* orbit_cmd = app.add_subcommand("orbit", "periodic orbits: find (least action), verify, stability, refine");
  orbit_cmd->require_subcommand(1);
  OrbitOptions orbit;
  auto* find_cmd = orbit_cmd->add_subcommand("find", "minimize a Fourier-discretized action from random starts");
  find_cmd->add_option("--bodies", orbit.bodies, "number of bodies (equal masses)")->capture_default_str();
  find_cmd->add_option("--masses", orbit.masses, "masses (overrides --bodies)")->delimiter(',');
  find_cmd->add_option("--modes", orbit.modes, "Fourier modes per coordinate")->capture_default_str();
  find_cmd->add_option("--points", orbit.points, "quadrature points (default: 100, or more than 2 × modes)");
  find_cmd->add_flag("--choreography", orbit.choreography, "all bodies on one curve, z_j(t) = z(t + 2 pi j/n)");
  find_cmd->add_option("--seed", orbit.seed, "random seed")->capture_default_str();
  find_cmd->add_option("--starts", orbit.starts, "random starts")->capture_default_str();
  find_cmd->add_option("--out-dir", orbit.out_dir, "folder for orbit-K.yaml, .csv and .png")->capture_default_str();
  find_cmd->add_flag("!--no-refine", orbit.refine, "skip the Newton (shooting) refinement");
  find_cmd->add_option("--max-residual", orbit.max_residual,
                       "largest equation-of-motion residual along the Fourier curve to try to refine")
      ->capture_default_str();
  std::vector<CLI::App*> orbit_scene_cmds;
  for (auto [name, help] : {std::pair{"verify", "integrate one period and report the closure error"},
                            std::pair{"stability", "monodromy multipliers with the first integrals projected out"},
                            std::pair{"refine", "Newton (shooting) on the initial state and period"}}) {
    auto* c = orbit_cmd->add_subcommand(name, help);
    c->add_option("scene", orbit.scene, "scene of the orbit (YAML)")->required();
    c->add_option("--period", orbit.period, "period (default: the scene's run.t_end)");
    c->add_option("--set", orbit.overrides, "override a scene key")->take_all();
    c->add_option("--rtol", orbit.rtol, "relative tolerance of the rkf78 integration")->capture_default_str();
    orbit_scene_cmds.push_back(c);
  }
  orbit_scene_cmds[0]->add_option("--tolerance", orbit.tolerance, "closure accepted (relative)")->capture_default_str();
  orbit_scene_cmds[1]->add_option("--tolerance", orbit.tolerance, "|lambda| <= 1 + tolerance is stable")->capture_default_str();
  orbit_scene_cmds[1]->add_option("--first-order", orbit.first_order, "also the seed's first-order product with N steps");
  orbit_scene_cmds[2]->add_option("-o,--output", orbit.output, "refined scene (default: overwrite the input)");

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

  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(level));
  try {
    if (*run_cmd) return run(scene, output, overrides, !no_progress);
    if (*plugins_cmd) return list_plugins();
    if (*find_cmd) return orbit_find(orbit);
    if (*orbit_scene_cmds[0]) return orbit_verify(orbit);
    if (*orbit_scene_cmds[1]) return orbit_stability(orbit);
    if (*orbit_scene_cmds[2]) return orbit_refine(orbit);
    if (*compare_cmd) return compare(scene, overrides, runs, spec_file, repeats, csv, h5, png, !no_plot);
    if (*check_cmd) {
      check_options.third_law = !no_third_law;
      return check_potential(scene, overrides, check_options);
    }
  } catch (const noether::Error& e) {
    std::cerr << "noether: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "noether: unexpected error: " << e.what() << "\n";
    return 4;
  }
  return 0;
}
