// noether run, noether plugins.
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <cstdio>
#include <iostream>

namespace noether::app {

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

}  // namespace noether::app
