#pragma once
// Compare: one scene under several integrator settings, each measured against a reference
// solution — the speed–accuracy trade of noether's integrators on a user's own scene.
#include <noether/params.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace noether {

struct CompareRun {
  std::string family;  // e.g. "lgvi", "cvode adams", "rk dopri5": one line in the plot
  std::string label;   // e.g. "step=0.001", "rtol=1e-08"
  Params integrator;   // the scene's `integrator` mapping for this run (null: the scene's)
  Params potential;    // a `potential` mapping replacing the scene's (null: the scene's)
};

struct CompareSpec {
  std::vector<CompareRun> runs;
  Params reference;        // integrator mapping of the reference solution (null: the scene's)
  Params reference_potential;  // its potential (null: the scene's), e.g. {plugin: mutual-exact}
  Params reference_check;  // a looser reference, to estimate the reference's own error
  int repeats = 3;         // wall time is the median of this many runs
  double max_wall_seconds = 0.0;  // each compared run's wall-time budget (0: none; not the reference); key max_wall_time
};

// Expands `{plugin: cvode, method: adams, rtol: [1e-6, 1e-8]}`: every key whose value is a
// list gives one run per item (several list keys are zipped, and must have equal lengths).
std::vector<CompareRun> expand_runs(const Params& mapping);

// Model runs: `{plugin: mutual-series, tolerance: [1e-3, 1e-6]}` expands like an integrator
// run into runs that replace the scene's potential and keep its integrator.
std::vector<CompareRun> expand_model_runs(const Params& mapping);

// The default sweep: lgvi and rk4 at output_every/{10, 20, 50}; cvode adams and bdf, rk dopri5
// and rkf78 at rtol 1e-6, 1e-8, 1e-10 (atol = rtol/100); reference rk rkf78 rtol 1e-13.
CompareSpec default_compare_spec(const Scene& scene);

// A compare file: {repeats: N, reference: {...}, runs: [{plugin: ..., ...}, ...]}.
CompareSpec load_compare_spec(const std::filesystem::path& file, const Scene& scene);

// The spec of `noether compare` (and noether.compare in Python) from its options: `runs` and
// `models` as YAML mappings (lists expand), replacing the default sweep or the spec file's runs
// when given; `reference_model` (YAML, with models only; default {plugin: mutual-exact});
// repeats and the wall-time budget when > 0. Names each option in its errors.
CompareSpec make_compare_spec(const Scene& scene, const std::vector<std::string>& runs,
                              const std::vector<std::string>& models, const std::string& reference_model,
                              const std::string& spec_file, int repeats, double max_wall_seconds);

struct CompareRow {
  std::string family, label;
  bool ok = false;
  std::string error;               // why the run failed, when !ok
  double wall_seconds = 0.0;       // median over repeats
  double final_position_error = 0.0;  // max_i ‖x_i(T) − x_i^ref(T)‖
  double final_attitude_error = 0.0;  // max_k ‖R_k(T) − R_k^ref(T)‖_F
  // The run summary's compare columns (docs/user-guide.md, "Summary reference": the work
  // counters, the energy, momentum and orthogonality errors), by key, in the schema's order.
  std::vector<std::pair<std::string, double>> summary;
  // Any column of compare_columns() by its name; throws Error for a name that is none.
  double value(std::string_view column) const;
};

// The numeric columns of a comparison, as the CSV, the HDF5 file and Python's table have them:
// wall_seconds, final_position_error, final_attitude_error, then the summary's compare columns.
std::vector<std::string> compare_columns();

struct CompareResult {
  std::string reference;         // description of the reference run
  double reference_error = 0.0;  // estimate: its final-state difference to the looser check
  std::string reference_error_note;  // why there is no estimate (reference_error = 0)
  double reference_seconds = 0.0;
  std::vector<CompareRow> rows;
};

using CompareProgress = std::function<void(const std::string& message)>;

CompareResult compare(const Scene& scene, PluginRegistry& registry, const CompareSpec& spec,
                      const CompareProgress& progress = {});

std::string format_compare(const CompareResult& result);
void write_compare_csv(const CompareResult& result, const std::filesystem::path& file);
void write_compare_h5(const CompareResult& result, const Scene& scene,
                      const std::filesystem::path& file);

}  // namespace noether
