// noether compare: work against precision on a user's scene (docs/user-guide.md).
#include "commands.hpp"

#include <noether/compare.hpp>
#include <noether/error.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include <CLI/CLI.hpp>

#include <memory>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <unistd.h>

namespace noether::app {

int compare(const std::string& scene_file, const std::vector<std::string>& overrides,
            const std::vector<std::string>& runs, const std::vector<std::string>& models,
            const std::string& reference_model, const std::string& spec_file, int repeats,
            std::string csv, std::string h5, std::string png, bool plot, double max_wall_time, bool force) {
  const noether::Scene scene = noether::load_scene(scene_file, overrides);
  noether::PluginRegistry registry;
  const noether::CompareSpec spec =
      noether::make_compare_spec(scene, runs, models, reference_model, spec_file, repeats, max_wall_time);
  // The tables and plot share a name: -o's (out/table.csv → out/table.h5, out/table.png), else
  // SCENE-compare in the working folder.
  const std::string stem = csv.empty() ? std::filesystem::path(scene_file).stem().string() + "-compare"
                                       : std::filesystem::path(csv).replace_extension().string();
  if (csv.empty()) csv = stem + ".csv";
  if (h5.empty()) h5 = stem + ".h5";
  if (png.empty()) png = stem + ".png";
  // Like `noether run`: existing results are replaced only when asked, and refused before the
  // (possibly long) comparison runs.
  if (!force)
    for (const std::string& file : plot ? std::vector<std::string>{csv, h5, png} : std::vector<std::string>{csv, h5})
      if (std::filesystem::exists(file))
        throw noether::OutputError(file + " exists; noether does not overwrite output unless asked: pass --force, "
                                   "or choose other names (-o, --h5, --plot)");
  const auto result = noether::compare(scene, registry, spec, [](const std::string& m) {
    std::cerr << "compare: " << m << "\n";
  });
  std::cout << "scene " << scene_file << "\n" << noether::format_compare(result);
  noether::write_compare_csv(result, csv);
  noether::write_compare_h5(result, scene, h5);
  std::cout << "table: " << csv << ", " << h5 << "\n";
  if (plot) {
    std::string command;
    if (!run_plot_script("plot_compare.py", {csv, png, "--title", std::filesystem::path(scene_file).filename().string()},
                         command))
      std::cerr << "noether: could not draw the plot (needs python3-matplotlib; command: "
                << command << "); the table is written\n";
    else
      std::cout << "plot: " << png << "\n";
  }
  for (const auto& row : result.rows)
    if (!row.ok) return 3;
  return 0;
}

void add_compare_command(CLI::App& app, Command& chosen) {
  struct Options {
    std::string scene, spec_file, csv, h5, png, reference_model;
    std::vector<std::string> overrides, runs, models;
    int repeats = 0;
    bool no_plot = false, force = false;
    double max_wall_time = 0.0;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "compare", "run a scene under several integrators against a reference: work against precision");
  cmd->add_option("scene", o->scene, "scene file (YAML)")->required();
  cmd->add_option("--set", o->overrides, "override a scene key")->take_all();
  cmd->add_option("--run", o->runs,
                  "an integrator setting as YAML, lists expand: "
                  "'{plugin: lgvi, step: [1e-3, 5e-4]}' (repeatable; default: a standard sweep)");
  cmd->add_option("--model", o->models,
                  "a potential as YAML, lists expand: '{plugin: mutual-series, tolerance: [1e-3, 1e-6]}' "
                  "(repeatable; runs the scene's integrator with each model)");
  cmd->add_option("--reference-model", o->reference_model,
                  "the potential of the reference run for --model (default {plugin: mutual-exact})");
  cmd->add_option("--spec", o->spec_file, "compare file: {repeats, reference, runs: [...]}");
  cmd->add_option("--repeats", o->repeats, "repeats per run for the median wall time (default 3)");
  cmd->add_option("-o,--csv", o->csv, "CSV table (default SCENE-compare.csv)");
  cmd->add_option("--h5", o->h5, "HDF5 table (default: -o's name with .h5, else SCENE-compare.h5)");
  cmd->add_option("--plot", o->png, "work–precision plot (default: -o's name with .png, else SCENE-compare.png)");
  cmd->add_flag("--no-plot", o->no_plot, "do not draw the plot");
  cmd->add_flag("--force", o->force, "replace existing tables and plot");
  cmd->add_option("--max-wall-time", o->max_wall_time,
                  "wall-time budget of each compared run in seconds (not the reference); a run that exhausts it is "
                  "listed as stopped")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([o, &chosen] {
    chosen = [o] {
      return compare(o->scene, o->overrides, o->runs, o->models, o->reference_model, o->spec_file, o->repeats, o->csv,
                     o->h5, o->png, !o->no_plot, o->max_wall_time, o->force);
    };
  });
}

}  // namespace noether::app
