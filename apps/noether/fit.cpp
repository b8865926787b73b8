// noether fit: a scene's free keys estimated from observations by weighted least squares on the
// run's sensitivities (docs/fitting.md, "noether fit").
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/fit.hpp>
#include <noether/registry.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace noether::app {

namespace {

struct FitCommand {
  std::string scene, observations, output;
  std::vector<std::string> overrides, free;
  FitOptions options;
  bool force = false;
};

int run_fit(const FitCommand& c) {
  if (!c.output.empty() && !c.force && std::filesystem::exists(c.output))
    throw OutputError(c.output + " exists; noether does not overwrite output unless asked: pass --force");
  FitOptions options = c.options;
  for (const auto& list : c.free) {  // --free a,b and --free a --free b alike
    std::stringstream in(list);
    for (std::string key; std::getline(in, key, ',');)
      if (!key.empty()) options.free.push_back(key);
  }
  PluginRegistry registry;
  const FitResult result = fit(c.scene, c.overrides, c.observations, options, registry);
  std::cout << format_fit(result);
  if (!c.output.empty()) {
    std::ofstream out(c.output);
    out << fit_json(result);
    out.close();
    if (!out) throw OutputError(c.output + ": cannot write");
    std::cout << "output                " << c.output << "\n";
  }
  return result.converged ? 0 : 1;
}

}  // namespace

void add_fit_command(CLI::App& app, Command& chosen) {
  auto c = std::make_shared<FitCommand>();
  auto* cmd = app.add_subcommand("fit",
                                 "estimate a scene's keys from observations: weighted least squares (Levenberg–Marquardt) "
                                 "on the run's sensitivities, with 1σ, correlations and χ² (docs/fitting.md)");
  cmd->add_option("scene", c->scene, "scene file (YAML)")->required();
  cmd->add_option("--observations", c->observations, "observation file (CSV; docs/fitting.md)")->required();
  cmd->add_option("--free", c->free, "keys to fit, as --sensitivity takes them (comma-separated or repeated)")
      ->required()
      ->take_all();
  cmd->add_option("--set", c->overrides, "override a scene key")->take_all();
  cmd->add_option("--max-iterations", c->options.max_iterations, "Levenberg–Marquardt steps at most")->capture_default_str();
  cmd->add_option("--tolerance", c->options.tolerance, "converged when every step is below this fraction of its 1σ")
      ->capture_default_str();
  cmd->add_option("-o,--output", c->output, "the fit as JSON: estimates, 1σ, covariance, correlation, χ², residuals");
  cmd->add_flag("--force", c->force, "replace an existing output file");
  cmd->callback([c, &chosen] { chosen = [c] { return run_fit(*c); }; });
}

}  // namespace noether::app
