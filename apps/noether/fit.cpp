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
  std::string scene, observations, output, plot;
  std::vector<std::string> overrides, free;
  FitOptions options;
  bool force = false;
};

int run_fit(const FitCommand& c) {
  // The JSON: -o's, or the plot's data beside it (FIT.png → FIT.json).
  std::string json = c.output;
  if (json.empty() && !c.plot.empty()) json = std::filesystem::path(c.plot).replace_extension(".json").string();
  for (const std::string& file : {json, c.plot})
    if (!file.empty() && !c.force && std::filesystem::exists(file))
      throw OutputError(file + " exists; noether does not overwrite output unless asked: pass --force");
  FitOptions options = c.options;
  for (const auto& list : c.free) {  // --free a,b and --free a --free b alike
    std::stringstream in(list);
    for (std::string key; std::getline(in, key, ',');)
      if (!key.empty()) options.free.push_back(key);
  }
  PluginRegistry registry;
  const FitResult result = fit(c.scene, c.overrides, c.observations, options, registry);
  std::cout << format_fit(result);
  if (!json.empty()) {
    std::ofstream out(json);
    out << fit_json(result);
    out.close();
    if (!out) throw OutputError(json + ": cannot write");
    std::cout << "output                " << json << "\n";
  }
  if (!c.plot.empty()) draw_plot("plot_fit.py", {json, c.plot}, c.plot, json);
  if (!result.verdict.trustworthy) {
    std::cout.flush();
    std::cerr << "noether: UNTRUSTWORTHY FIT: the run at the estimate is not to be trusted:";
    for (const auto& r : result.verdict.reasons) std::cerr << " " << r << ";";
    std::cerr << " so neither are the estimate and its sigmas (a smaller step or tolerance? thresholds: run.trust in "
                 "the scene)\n";
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
  cmd->add_option("--plot", c->plot, "FIT.png: the residuals over their sigma against time (its data: the JSON)");
  cmd->add_flag("--force", c->force, "replace existing output files");
  cmd->callback([c, &chosen] { chosen = [c] { return run_fit(*c); }; });
}

}  // namespace noether::app
