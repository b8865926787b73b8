// noether ensemble: one scene, many samples, every core (docs/ensembles.md).
#include "commands.hpp"

#include <noether/ensemble.hpp>

#include <cstdio>
#include <iostream>
#include <unistd.h>

namespace noether::app {

int ensemble(const std::string& scene_file, const std::vector<std::string>& overrides,
             const std::vector<std::string>& vary, const EnsembleCommand& command) {
  noether::EnsembleOptions options;
  for (const auto& v : vary) options.vary.push_back(noether::parse_variation(v));
  options.samples = command.samples;
  options.seed = command.seed;
  options.threads = command.threads;
  options.pair = command.pair;
  options.trajectories = command.trajectories;
  options.resume = command.resume;
  options.overwrite = command.force;
  const bool tty = isatty(STDERR_FILENO) != 0;
  const auto report = noether::run_ensemble(scene_file, overrides, options, command.output,
                                            [tty](std::size_t done, std::size_t total) {
                                              if (tty) std::fprintf(stderr, "\rensemble: %zu / %zu samples", done, total);
                                            });
  if (tty) std::fprintf(stderr, "\n");
  std::printf("scene                         %s\n", scene_file.c_str());
  std::printf("samples                       %zu (%zu run here, %zu finished before)\n", report.samples, report.run,
              report.skipped);
  std::printf("outcomes                      %zu completed, %zu stopped by an event, %zu failed\n", report.completed,
              report.stopped, report.failed);
  std::printf("threads                       %u\n", report.threads);
  std::printf("wall time                     %.3f s (%.1f samples/s; per sample %.4f s, of which set-up %.4f s)\n",
              report.wall_seconds, report.wall_seconds > 0 ? static_cast<double>(report.run) / report.wall_seconds : 0.0,
              report.run ? report.sample_seconds / static_cast<double>(report.run) : 0.0,
              report.run ? report.setup_seconds / static_cast<double>(report.run) : 0.0);
  std::printf("output                        %s\n", command.output.c_str());
  return report.failed > 0 ? 3 : 0;
}

}  // namespace noether::app
