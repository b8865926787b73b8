#pragma once
// Ensembles (docs/ensembles.md): one scene run many times with some of its keys drawn from
// distributions, on every core, into one HDF5 file. Each sample's values depend on (seed, index)
// only, and results are stored by index, so the file is the same bit for bit whatever the number
// of threads and the order in which samples finish; a killed ensemble resumes without redoing
// the samples it finished.
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/state.hpp>

#include <cmath>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace noether {

// A distribution of one scene key: normal(μ, σ), uniform(a, b), log-uniform(a, b) (a, b > 0),
// list(v1, v2, ...) (one of the values, each equally likely), grid(a, b, n) (n values from a to
// b; several grids form their product, the first varying slowest).
// A fit's estimate (noether fit -o FIT.json) varies its keys jointly: a multivariate normal of the
// fit's covariance C = L Lᵀ, each key one Variation of kind Fitted, consecutive and in order.
struct Variation {
  enum class Kind { Normal, Uniform, LogUniform, List, Grid, Fitted };
  std::string key;    // as for --set: bodies.dimorphos.velocity.1
  std::string text;   // the specification as given
  Kind kind = Kind::Normal;
  std::vector<double> args;  // the parameters, or the list's values; Fitted: μ_j, L_j0 … L_jj
};

// "KEY=normal(0.1, 0.01)" → a Variation; SceneError naming the problem otherwise.
Variation parse_variation(const std::string& text);

// The variations of a fit's estimate, read from its JSON (`noether fit -o`): one Fitted per
// parameter, x = μ + L z with L the Cholesky factor of the fit's covariance and z standard
// normal (docs/ensembles.md, "From a fit"). SceneError naming the file when it is not a fit's,
// or its covariance is not positive definite.
std::vector<Variation> variations_from_fit(const std::filesystem::path& fit_json);

// The values of sample `index` (in the order of `vary`): a function of (seed, index) only.
// `samples` sizes the grids' product.
std::vector<double> sample_values(const std::vector<Variation>& vary, std::uint64_t seed, std::size_t index);
// The number of samples the grids give (1 without grids).
std::size_t grid_size(const std::vector<Variation>& vary);

struct EnsembleOptions {
  std::vector<Variation> vary;
  std::size_t samples = 0;     // 0: the grids' product (an error without grids)
  std::uint64_t seed = 1;
  unsigned threads = 0;        // 0: one per core
  std::string pair;            // "a,b": the bodies whose mutual orbit is recorded (default: the first two)
  std::size_t trajectories = 0;  // full output files for the first k samples, next to the ensemble file
  bool resume = false;         // continue an ensemble file: run only the samples it lacks
  bool overwrite = false;
};

// The run of sample i that --trajectories writes next to the ensemble's file: ENS-sample-I.h5.
std::filesystem::path sample_run_path(const std::filesystem::path& ensemble, std::size_t i);

struct EnsembleReport {
  std::size_t samples = 0, run = 0, skipped = 0;  // skipped: finished in an earlier (resumed) run
  std::size_t ranks = 1;                          // processes (MPI), this one included
  std::size_t completed = 0, stopped = 0, failed = 0;
  std::size_t untrustworthy = 0;  // finished, but their verdict (run.trust) says not to trust them
  double wall_seconds = 0.0;          // the whole ensemble
  double sample_seconds = 0.0;        // summed over the samples run (integration and set-up)
  double setup_seconds = 0.0;         // summed scene parsing and plugin set-up
  unsigned threads = 0;
};

// What one sample left (written at its index by the process that holds the file).
struct SampleResult {
  std::int8_t outcome = -1;  // 0 completed, 1 stopped by an event, 2 failed
  std::string message;
  std::vector<double> summary;  // final_time, max |ΔE|, max rel. |ΔE|, max rel. ΔL, min distance, steps, evaluations
  State final_state;
  double a = NAN, e = NAN, period = NAN;  // the pair's osculating mutual orbit at the end
  double wall = 0.0, setup = 0.0;
  std::int8_t trustworthy = -1;  // the verdict: 1, 0 (why: in message), −1 when it failed
  // The run's indicators (/indicators/<name>, named by ensemble_indicator_names): the chaos
  // indicators when the scene asks for them (run.chaos); NaN when it failed.
  std::vector<double> indicators;
  // As numbers (all but the message), for sending between processes.
  std::vector<double> pack() const;
  static SampleResult unpack(const std::vector<double>& numbers, std::string message);
};

// An ensemble checked and ready: the scene, the overrides and the samples. Every process of an
// MPI ensemble builds the same plan from the same command line.
struct EnsemblePlan {
  EnsemblePlan(const std::filesystem::path& scene_file, std::vector<std::string> overrides, EnsembleOptions options);
  std::vector<std::string> sample_overrides(std::size_t index) const;  // the scene's and the sample's
  // Runs sample `index` (with a registry of the calling thread's); failures are in the result.
  SampleResult run(std::size_t index, PluginRegistry& registry, const std::filesystem::path& output) const;
  Scene base;
  std::vector<std::string> overrides;
  EnsembleOptions options;
  std::size_t samples = 0, pair_a = 0, pair_b = 1;
};

// Workers in other processes (MPI ranks), served by the process that writes the file.
class RemoteWorkers {
 public:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  virtual ~RemoteWorkers() = default;
  virtual std::size_t count() const = 0;
  // Without blocking: the results that arrived, and the workers waiting for a sample.
  virtual void poll(std::vector<std::pair<std::size_t, SampleResult>>& results, std::vector<int>& idle) = 0;
  // Gives a worker a sample, or kNone: no more, stop.
  virtual void assign(int worker, std::size_t index) = 0;
};

// Runs the ensemble of `scene_file` (with `overrides` applied to every sample) into `output`.
// Every variation key and distribution is checked (and one sample's scene built) before any
// sample runs. `progress` is called from the main thread with (samples finished, total).
// `remote`: more workers in other processes (MPI), fed from the same queue of samples.
EnsembleReport run_ensemble(const std::filesystem::path& scene_file, const std::vector<std::string>& overrides,
                            const EnsembleOptions& options, const std::filesystem::path& output,
                            const std::function<void(std::size_t, std::size_t)>& progress = {},
                            RemoteWorkers* remote = nullptr);

}  // namespace noether
