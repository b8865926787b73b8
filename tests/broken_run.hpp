#pragma once
// The two files a continuation starts from: a scene run to a break with an output file, saved
// there (Simulation::save) and finished — for tests of `--resume` (Simulation::resume) and of
// Simulation::load against the uninterrupted run.
#include <noether/simulation.hpp>

#include <unistd.h>

#include <filesystem>
#include <string>

namespace noether::test {

struct BrokenRun {
  std::filesystem::path saved, output;  // temporary, removed with this

  BrokenRun(const Scene& scene, PluginRegistry& registry, double t_break, const std::string& name) {
    const std::string tag = name + "-" + std::to_string(::getpid());
    saved = std::filesystem::temp_directory_path() / ("noether-" + tag + "-saved.h5");
    output = std::filesystem::temp_directory_path() / ("noether-" + tag + "-output.h5");
    RunOptions options;
    options.output = output;
    options.overwrite = true;
    Simulation run(scene, registry, options);
    run.integrate(t_break);
    run.save(saved);
    run.finish();
  }
  BrokenRun(const BrokenRun&) = delete;
  BrokenRun& operator=(const BrokenRun&) = delete;
  ~BrokenRun() {
    std::error_code ignored;
    std::filesystem::remove(saved, ignored);
    std::filesystem::remove(output, ignored);
  }
};

}  // namespace noether::test
