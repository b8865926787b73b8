// noether ensemble: one scene, many samples, every core (docs/ensembles.md).
#include "commands.hpp"

#include <noether/ensemble.hpp>
#include <noether/error.hpp>

#ifdef NOETHER_WITH_MPI
#include "ensemble_mpi.hpp"
#endif

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <unistd.h>

namespace noether::app {

namespace {

int print_report(const noether::EnsembleReport& report, const std::string& scene_file, const std::string& output,
                 bool tty) {
  if (tty) std::fprintf(stderr, "\n");
  std::printf("scene                         %s\n", scene_file.c_str());
  std::printf("samples                       %zu (%zu run here, %zu finished before)\n", report.samples, report.run,
              report.skipped);
  std::printf("outcomes                      %zu completed, %zu stopped by an event, %zu failed; %zu untrustworthy\n",
              report.completed, report.stopped, report.failed, report.untrustworthy);
  std::printf("threads                       %u%s\n", report.threads,
              report.ranks > 1 ? (" on rank 0, and " + std::to_string(report.ranks - 1) + " more ranks").c_str() : "");
  std::printf("wall time                     %.3f s (%.1f samples/s; per sample %.4f s, of which set-up %.4f s)\n",
              report.wall_seconds, report.wall_seconds > 0 ? static_cast<double>(report.run) / report.wall_seconds : 0.0,
              report.run ? report.sample_seconds / static_cast<double>(report.run) : 0.0,
              report.run ? report.setup_seconds / static_cast<double>(report.run) : 0.0);
  std::printf("output                        %s\n", output.c_str());
  if (report.untrustworthy > 0) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "noether: %zu UNTRUSTWORTHY samples: they finished, but their verdict (run.trust) says not to trust "
                 "them; /trustworthy is 0 and /message says why\n",
                 report.untrustworthy);
  }
  return report.failed > 0 ? 3 : 0;
}

}  // namespace

int ensemble(const std::string& scene_file, const std::vector<std::string>& overrides,
             const std::vector<std::string>& vary, const EnsembleCommand& command) {
  noether::EnsembleOptions options;
  for (const auto& v : vary) options.vary.push_back(noether::parse_variation(v));
  if (!command.from_fit.empty())
    for (auto& v : noether::variations_from_fit(command.from_fit)) {
      for (const auto& other : options.vary)
        if (other.key == v.key)
          throw noether::SceneError("--vary " + other.key + ": the fit " + command.from_fit + " varies it already");
      options.vary.push_back(std::move(v));
    }
  options.samples = command.samples;
  options.seed = command.seed;
  options.threads = command.threads;
  options.pair = command.pair;
  options.trajectories = command.trajectories;
  options.resume = command.resume;
  options.overwrite = command.force;
  const bool tty = isatty(STDERR_FILENO) != 0;
  auto lead = [&](noether::RemoteWorkers* remote) {
    const auto report = noether::run_ensemble(scene_file, overrides, options, command.output,
                                              [tty](std::size_t done, std::size_t total) {
                                                if (tty) std::fprintf(stderr, "\rensemble: %zu / %zu samples", done, total);
                                              },
                                              remote);
    return print_report(report, scene_file, command.output, tty);
  };
#ifdef NOETHER_WITH_MPI
  if (launched_by_mpi()) {
    if (command.threads == 0) options.threads = 1;  // one sample at a time per rank, rank 0 included
    return mpi_ensemble(lead, scene_file, overrides, options, command.output);
  }
#else
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* n = std::getenv(v); n && std::atoi(n) > 1)
      throw noether::Error("this noether was built without MPI (no libopenmpi-dev when it was configured): "
                           "run the ensemble without mpirun, on one machine's threads");
#endif
  return lead(nullptr);
}

void add_ensemble_command(CLI::App& app, Command& chosen) {
  struct Options {
    std::string scene;
    std::vector<std::string> overrides, vary;
    EnsembleCommand ensemble;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "ensemble", "run a scene many times with keys drawn from distributions, on every core, into one HDF5 file");
  cmd->add_option("scene", o->scene, "scene file (YAML)")->required();
  cmd->add_option("--vary", o->vary,
                  "KEY=DIST: normal(mean, sd), uniform(a, b), log-uniform(a, b), list(v1, ...), grid(a, b, n) "
                  "(repeatable; KEY as for --set)");
  EnsembleCommand& e = o->ensemble;
  cmd->add_option("--from-fit", e.from_fit,
                  "FIT.json (noether fit -o): its keys drawn jointly from the estimate and its covariance");
  cmd->add_option("--samples", e.samples, "number of samples (default: the grids' points)");
  cmd->add_option("--seed", e.seed, "random seed: sample i draws from (seed, i)")->capture_default_str();
  cmd->add_option("--threads", e.threads, "worker threads (default: one per core)");
  cmd->add_option("--pair", e.pair, "a,b: the bodies whose mutual orbit is recorded (default: the first two)");
  cmd->add_option("--trajectories", e.trajectories, "write full output files for the first K samples (ENS-sample-I.h5)");
  cmd->add_option("-o,--output", e.output, "the ensemble's HDF5 file")->required();
  cmd->add_option("--set", o->overrides, "override a scene key for every sample")->take_all();
  cmd->add_flag("--resume", e.resume, "continue the ensemble in the output file: run only missing samples");
  cmd->add_flag("--force", e.force, "replace an existing output file");
  cmd->callback([o, &chosen] {
    if (o->vary.empty() && o->ensemble.from_fit.empty())
      throw CLI::ValidationError("ensemble", "give --vary KEY=DIST (repeatable) or --from-fit FIT.json");
    chosen = [o] { return ensemble(o->scene, o->overrides, o->vary, o->ensemble); };
  });
}

}  // namespace noether::app
