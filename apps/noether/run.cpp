// noether run, noether plugins.
#include "commands.hpp"
#include "progress.hpp"

#include <noether/error.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <cmath>
#include <csignal>
#include <limits>
#include <memory>
#include <cstdio>
#include <unistd.h>
#include <iostream>

namespace noether::app {

void print_shapes(const noether::Scene& scene, std::ostream& out) {
  for (std::size_t i = 0; i < scene.system.size(); ++i) {
    const noether::Body& b = scene.system.body(i);
    if (b.field) {  // given by its gravity field (docs/gravity-fields.md)
      const noether::StokesCoefficients& f = *b.field;
      const noether::Params& g = scene.root.at("bodies").items()[i].at("gravity");
      char line[512];
      std::snprintf(line, sizeof line,
                    "field %-23s %s, degree %d (%s), reference radius %.10g, GM %.10g, mass %.10g, polar moment "
                    "C/(M R^2) %.6g\n",
                    b.name.c_str(), g.at("stokes").as_string().c_str(), f.degree,
                    f.normalized ? "normalized" : "unnormalized", f.reference_radius, scene.system.G() * b.mass, b.mass,
                    b.inertia(2, 2) / (b.mass * f.reference_radius * f.reference_radius));
      out << line;
      continue;
    }
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
        const std::string& resume, double resume_t_end, int threads) {
  noether::PluginRegistry registry;
  noether::RunOptions options;
  options.threads = threads;
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
    if (resume.empty())  // the scene's input warnings, before the run (the summary repeats them)
      for (const std::string& warning : scene.warnings) spdlog::warn("{}", warning);
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

// A documented default as `noether plugins` shows it: a value, or what the plugin works out
// ("(0.9 x osculating periapsis)" shown without its parentheses).
std::string default_text(const noether::ParamDoc& d) {
  if (!d.default_value) return "";
  const std::string text = d.default_value;
  return text.size() > 1 && text.front() == '(' && text.back() == ')' ? text.substr(1, text.size() - 2) : text;
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
                  d.default_value ? ", default " : ", required", default_text(d).c_str());
    std::printf("%30sfrom %s\n", "", p.file.string().c_str());
  }
  for (const auto& f : failures) std::fprintf(stderr, "noether: %s\n", f.c_str());
  return failures.empty() ? 0 : 1;
}

void add_run_command(CLI::App& app, Command& chosen) {
  struct Options {
    std::string scene, output, resume, summary = "text";
    std::vector<std::string> overrides, sensitivities;
    bool no_progress = false, force = false, stm = false, chaos = false;
    double max_wall_time = 0.0, resume_t_end = std::numeric_limits<double>::quiet_NaN();
    int threads = 0;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("run", "integrate a scene and print a summary");
  cmd->add_option("scene", o->scene, "scene file (YAML)");
  cmd->add_option("-o,--output", o->output, "HDF5 output file");
  cmd->add_option("--resume", o->resume,
                  "continue the run recorded in this output file from its last complete frame, appending to it "
                  "(instead of a scene)");
  cmd->add_option("--t-end", o->resume_t_end, "with --resume: a later end time, to extend a run");
  cmd->add_option("--set", o->overrides, "override a scene key: --set integrator.step=1e-3")->take_all();
  cmd->add_flag("--no-progress", o->no_progress, "no progress line on stderr");
  cmd->add_flag("--stm", o->stm,
                "carry the state-transition matrix of the integrator's map and write it at every frame "
                "(/derivatives/stm; the same as --set run.stm=true)");
  cmd->add_flag("--chaos", o->chaos,
                "compute the chaos indicators MEGNO and FLI from a deviation vector the tangent map carries, at every "
                "frame (/derivatives/megno, /derivatives/fli) and in the summary (the same as --set run.chaos=true)");
  cmd->add_option("--sensitivity", o->sensitivities,
                  "write the derivative of the state at every frame with respect to this key of a body's initial "
                  "state, e.g. bodies.moon.velocity or bodies.moon.orbit.e (/derivatives/sensitivity; repeatable; "
                  "the same as --set run.sensitivities+=KEY)")
      ->take_all();
  cmd->add_flag("--force", o->force, "overwrite an existing output file (never a link or the scene)");
  cmd->add_option("--summary", o->summary, "the summary on stdout: text, or json (one object)")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  cmd->add_option("--max-wall-time", o->max_wall_time,
                  "stop after this many seconds of wall time, like an event (output complete up to there)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", o->threads,
                  "threads inside each evaluation of the potential (mutual-series' pairs); the result is the same "
                  "bit for bit for any number (default: NOETHER_THREADS from the environment, else 1)")
      ->check(CLI::Range(1, 1024));
  cmd->callback([o, &chosen] {
    chosen = [o] {
      if (o->resume.empty() == o->scene.empty()) {
        std::cerr << "noether run: give a scene, or --resume FILE.h5 (not both)\n";
        return 2;
      }
      if (!o->resume.empty() && (!o->output.empty() || !o->overrides.empty() || o->force || o->stm ||
                                  o->chaos || !o->sensitivities.empty())) {
        std::cerr << "noether run: --resume appends to the file it continues, with the scene recorded there: "
                     "-o, --set, --stm, --chaos, --sensitivity and --force do not apply (extend a run with --t-end)\n";
        return 2;
      }
      if (o->resume.empty() && !std::isnan(o->resume_t_end)) {
        std::cerr << "noether run: --t-end goes with --resume; for a new run use --set run.t_end=T\n";
        return 2;
      }
      if (o->stm) o->overrides.push_back("run.stm=true");
      if (o->chaos) o->overrides.push_back("run.chaos=true");
      for (const std::string& key : o->sensitivities) o->overrides.push_back("run.sensitivities+=" + key);
      return run(o->scene, o->output, o->overrides, !o->no_progress, o->force, o->summary == "json", o->max_wall_time,
                 o->resume, o->resume_t_end, o->threads);
    };
  });
}

void add_plugins_command(CLI::App& app, Command& chosen) {
  app.add_subcommand("plugins", "list every plugin found")->callback([&chosen] { chosen = list_plugins; });
}

}  // namespace noether::app
