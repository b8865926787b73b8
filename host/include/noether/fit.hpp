#pragma once
// Fitting a scene to observations (docs/fitting.md, "noether fit"; docs/equations.md §28):
// weighted least squares over keys `--set` takes, by Levenberg–Marquardt on the run's own
// sensitivities (docs/derivatives.md), with the covariance of the estimate from the whitened
// Jacobian at the solution.
#include <noether/observations.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace noether {

struct FitOptions {
  // The free keys, as `--sensitivity` takes them (a vector key frees its three components).
  std::vector<std::string> free;
  int max_iterations = 30;
  // Converged when a step moves every parameter by less than `tolerance` of its 1σ.
  double tolerance = 1e-3;
};

// One observation against the model at the estimate.
struct FitResidual {
  Observation observation;
  double computed = 0.0;
  double residual = 0.0;    // observed − computed
  double normalized = 0.0;  // residual / sigma
};

struct FitResult {
  std::string scene_file, observations_file;
  std::vector<std::string> bodies;  // the scene's, naming the observations' targets and centers
  std::vector<std::string> names;  // the free parameters, one per component, as `--set` keys
  Eigen::VectorXd initial, estimate, sigma;
  Eigen::MatrixXd covariance, correlation;
  double chi2_initial = 0.0, chi2 = 0.0;
  std::size_t observations = 0;
  std::ptrdiff_t degrees_of_freedom = 0;  // observations − parameters
  int iterations = 0, runs = 0;           // accepted steps; runs of the scene (each with its sensitivities)
  bool converged = false;
  std::string stop;  // why it stopped, in words
  std::vector<FitResidual> residuals;
  // The overrides that make the scene at the estimate (the scene's own, then one per parameter).
  std::vector<std::string> overrides;
  // The verdict on the run at the estimate (docs/user-guide.md, "Verdict"), as `noether run`
  // would give it: a fit to an untrustworthy run is not to be trusted either.
  Verdict verdict;
};

// The model at the scene (with `overrides`): each observation's computed value and its
// derivatives with respect to the free keys' components (names). The scene runs from its t0 to
// the last observation with sensitivities to `free`, sampled at its output times, at every
// observation it can stop at (an adaptive method: all; a fixed-step one: those on its grid) and
// on both sides of each impulse; between samples, eq. 16.2 and its derivative (eqs. 28.1–28.2).
struct Prediction {
  std::vector<std::string> names;
  Eigen::VectorXd values;    // one per observation
  Eigen::MatrixXd jacobian;  // observations × names
  Verdict verdict;           // the run's (Simulation::finish)
};
Prediction predict(const std::string& scene_file, const std::vector<std::string>& overrides,
                   const std::vector<Observation>& observations, const std::vector<std::string>& free,
                   PluginRegistry& registry, const std::string& observations_file = {});

// The fit. SceneError (exit 2 in the driver) for a bad observation file, an observation outside
// the run's time span, a key that cannot be varied, or parameters the observations do not
// determine (named); the result says whether it converged and why it stopped.
FitResult fit(const std::string& scene_file, const std::vector<std::string>& overrides,
              const std::string& observations_file, const FitOptions& options, PluginRegistry& registry);

// As the driver prints it: the parameters with their 1σ, the correlations, χ².
std::string format_fit(const FitResult& result);
// As `noether fit -o FILE.json` writes it (docs/fitting.md lists its fields).
std::string fit_json(const FitResult& result);

}  // namespace noether
