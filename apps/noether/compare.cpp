// noether compare: work against precision on a user's scene (docs/user-guide.md).
#include "commands.hpp"

#include <noether/compare.hpp>
#include <noether/error.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <unistd.h>

namespace noether::app {

int compare(const std::string& scene_file, const std::vector<std::string>& overrides,
            const std::vector<std::string>& runs, const std::vector<std::string>& models,
            const std::string& reference_model, const std::string& spec_file, int repeats,
            std::string csv, std::string h5, std::string png, bool plot, double max_wall_time) {
  const noether::Scene scene = noether::load_scene(scene_file, overrides);
  noether::PluginRegistry registry;
  noether::CompareSpec spec = spec_file.empty() ? noether::default_compare_spec(scene)
                                                : noether::load_compare_spec(spec_file, scene);
  if (!runs.empty() || !models.empty()) {
    spec.runs.clear();
    for (std::size_t k = 0; k < runs.size(); ++k)
      for (auto& r : noether::expand_runs(noether::parse_params(runs[k], "--run " + std::to_string(k + 1))))
        spec.runs.push_back(std::move(r));
    for (std::size_t k = 0; k < models.size(); ++k)
      for (auto& r : noether::expand_model_runs(noether::parse_params(models[k], "--model " + std::to_string(k + 1))))
        spec.runs.push_back(std::move(r));
  }
  if (models.empty() && !reference_model.empty())
    throw noether::SceneError("--reference-model goes with --model: it is the potential the models are "
                              "measured against (integrator runs are measured against the scene's potential)");
  if (!models.empty()) {
    // Models are measured against a reference model under the scene's own integrator, so that
    // the integration error cancels and the difference is the models'.
    spec.reference = noether::Params();
    spec.reference_check = noether::Params();
    spec.reference_potential =
        noether::parse_params(reference_model.empty() ? "{plugin: mutual-exact}" : reference_model, "--reference-model");
  }
  if (repeats > 0) spec.repeats = repeats;
  if (max_wall_time > 0) spec.max_wall_seconds = max_wall_time;
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

}  // namespace noether::app
