// noether: the driver. `noether run SCENE`, `noether plugins`, `noether --version`.
#include <noether/compare.hpp>
#include <noether/error.hpp>
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
