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
  const noether::CompareSpec spec =
      noether::make_compare_spec(scene, runs, models, reference_model, spec_file, repeats, max_wall_time);
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
