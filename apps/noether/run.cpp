// noether run, noether plugins.
#include "commands.hpp"
#include "progress.hpp"

#include <noether/error.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <csignal>
#include <cstdio>
#include <unistd.h>
#include <iostream>

namespace noether::app {

void print_shapes(const noether::Scene& scene, std::ostream& out) {
  for (const auto& b : scene.system.bodies()) {
    if (!b.solid) continue;
    const auto& s = *b.solid;
    char line[512];
    const double angle = noether::log_so3(s.rotation).norm() * 180.0 / M_PI;
    std::snprintf(line, sizeof line, "shape %-23s %s, mass %.10g, density %.10g\n", b.name.c_str(),
                  s.describe().c_str(), s.mass, s.density);
    out << line;
    if (s.kind == noether::Solid::Kind::Polyhedron) {
      std::snprintf(line, sizeof line,
                    "%-29s centre of mass at (%.6g, %.6g, %.6g) in the file, axes rotated by "
                    "%.4g deg onto the body frame\n",
                    "", s.offset.x(), s.offset.y(), s.offset.z(), angle);
      out << line;
    }
  }
}

namespace {

// SIGINT and SIGTERM ask the run to stop after its current step, or a continuation to stop
// reading its file between blocks (both read the flag); a second one of either ends the process
// at once (SA_RESETHAND). Whatever phase the run is in, it has kStopGrace seconds to end
// cleanly: past them (a call that does not return, such as HDF5 inside a damaged file), SIGALRM
// ends the process with 128 + the signal, the output as its last flush left it.
constexpr unsigned kStopGrace = 20;
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_stop_signal(int signal) {
  g_signal = signal;
  alarm(kStopGrace);
}
extern "C" void on_stop_grace_over(int) {
  static const char message[] =
      "noether: the run did not stop within 20 s of the signal; ended without finishing its output\n";
  [[maybe_unused]] const auto written = write(STDERR_FILENO, message, sizeof message - 1);
  _exit(128 + (g_signal > 0 ? g_signal : SIGTERM));
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  struct sigaction grace {};
  grace.sa_handler = on_stop_grace_over;
  sigemptyset(&grace.sa_mask);
  sigaction(SIGALRM, &grace, nullptr);
}

}  // namespace

int run(const std::string& scene_file, const std::string& output_given,
        const std::vector<std::string>& overrides, bool progress, bool force, bool json, double max_wall_time,
        const std::string& resume, double resume_t_end) {
  noether::PluginRegistry registry;
  noether::RunOptions options;
  const std::string output = resume.empty() ? output_given : resume;
  if (!output_given.empty()) options.output = output_given;
  options.overwrite = force;
  Progress progress_line;
  if (progress) options.progress = std::ref(progress_line);
  options.interrupt = &g_signal;
  options.max_wall_seconds = max_wall_time;
  std::unique_ptr<noether::Simulation> sim;
  double resumed_at = 0.0;
  install_stop_handlers();
  try {
    if (resume.empty()) {
      sim = std::make_unique<noether::Simulation>(noether::load_scene(scene_file, overrides), registry, options);
    } else {
      try {
        sim = noether::Simulation::resume(resume, registry, options, resume_t_end);
      } catch (const noether::Error& e) {
        if (g_signal == 0) throw;
        std::cerr << "noether: " << (g_signal == SIGINT ? "SIGINT" : "SIGTERM") << ": " << e.what() << "\n";
        return 128 + g_signal;
      }
      resumed_at = sim->time();
    }
    const noether::Scene& scene = sim->scene();
    sim->integrate(scene.run.t_end);
    const auto summary = sim->finish();
    if (json) {
      std::cout << noether::format_summary_json(summary);
    } else {
      std::cout << "scene                         " << (resume.empty() ? scene_file : scene.file) << "\n";
      if (!resume.empty())
        std::cout << "resumed                       " << resume << " from t = " << resumed_at
                  << " (the summary covers the whole run)\n";
      print_shapes(scene, std::cout);
      std::cout << noether::format_summary(summary);
      if (!output.empty()) std::cout << "output                        " << output << "\n";
    }
    if (!summary.verdict.trustworthy) {
      std::cout.flush();
      std::cerr << "noether: UNTRUSTWORTHY RUN:";
      for (const auto& r : summary.verdict.reasons) std::cerr << " " << r << ";";
      std::cerr << " the run finished, but its numbers cannot be trusted (a smaller step or tolerance? "
                   "thresholds: run.trust in the scene)\n";
    }
    if (summary.stop_reason.rfind("wall-time budget", 0) == 0) {
      std::cout.flush();
      std::cerr << "noether: " << summary.stop_reason << " (--max-wall-time); the run did not reach t_end"
                << (output.empty() ? std::string() : "; the output up to there is in " + output) << "\n";
    }
    if (g_signal != 0) {
      std::cerr << "noether: " << (g_signal == SIGINT ? "SIGINT" : "SIGTERM") << ": stopped at t = "
                << summary.final_state.t << " after a complete step"
                << (output.empty() ? std::string() : "; the output up to there is in " + output) << "\n";
      return 128 + g_signal;
    }
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
