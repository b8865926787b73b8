// noether check-potential: a potential's forces and moments against finite differences of U, its
// force Jacobian against differences of the forces.
#include "commands.hpp"

#include <noether/potential_check.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <CLI/CLI.hpp>

#include <memory>
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

void add_check_potential_command(CLI::App& app, Command& chosen) {
  struct Options {
    std::string scene;
    std::vector<std::string> overrides;
    PotentialCheckOptions check;
    bool no_third_law = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("check-potential",
                                 "check a scene's potential: forces and moments against finite differences of U, the force "
                                 "Jacobian against differences of the forces, and Newton's third law, at the scene's "
                                 "state and at perturbed states");
  cmd->add_option("scene", o->scene, "scene file (YAML)")->required();
  cmd->add_option("--set", o->overrides, "override a scene key")->take_all();
  cmd->add_option("--tolerance", o->check.tolerance, "finite-difference agreement, relative to the largest force or moment")
      ->capture_default_str();
  cmd->add_option("--states", o->check.perturbed_states, "perturbed states to check")->capture_default_str();
  cmd->add_flag("--no-third-law", o->no_third_law, "skip the net force and torque rows (for external-field models)");
  cmd->callback([o, &chosen] {
    chosen = [o] {
      o->check.third_law = !o->no_third_law;
      return check_potential(o->scene, o->overrides, o->check);
    };
  });
}

}  // namespace noether::app
