// noether check-potential: a potential's forces and moments against finite differences of U.
#include "commands.hpp"

#include <noether/potential_check.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <iostream>

namespace noether::app {

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

}  // namespace noether::app
