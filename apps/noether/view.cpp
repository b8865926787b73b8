// noether view: a run's output file as one self-contained HTML page (docs/visualisation.md).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/view.hpp>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>

namespace noether::app {

namespace {

struct ViewCommand {
  std::vector<std::string> runs;
  std::string output;
  ViewOptions options;
  bool force = false;
};

int view(const ViewCommand& c) {
  namespace fs = std::filesystem;
  const fs::path page = c.output.empty() ? fs::path(c.runs[0]).replace_extension(".html") : fs::path(c.output);
  const ViewReport report = write_view(std::vector<fs::path>(c.runs.begin(), c.runs.end()), page, c.options, c.force);
  for (const auto& note : report.notes) std::fprintf(stderr, "noether: note: %s\n", note.c_str());
  std::string runs;
  if (report.runs.size() > 1) runs = ", " + std::to_string(report.runs.size()) + " runs";
  std::printf("view: %s (%zu of %zu frames%s, %.1f MB); open it in a web browser\n", page.c_str(), report.frames_shown,
              report.frames_in_file, runs.c_str(), static_cast<double>(report.bytes) / 1e6);
  return 0;
}

}  // namespace

void add_view_command(CLI::App& app, Command& chosen) {
  auto c = std::make_shared<ViewCommand>();
  auto* sub = app.add_subcommand("view", "a run's bodies in 3-D: one HTML page to open in a browser, offline");
  sub->add_option("runs", c->runs,
                  "the run's output file (noether run -o); more runs of the same bodies and frame times are drawn "
                  "with it, translucent; or an ensemble's file (noether ensemble -o), for its samples' runs")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", c->output, "the page to write (default: the run's name with .html)");
  sub->add_option("--max-frames", c->options.max_frames,
                  "at most this many frames in the page, evenly spaced, the first and last among them")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{2}, std::size_t{1} << 26));
  sub->add_option("--title", c->options.title, "the page's title (default: the run's file name)");
  sub->add_option("--params", c->options.params,
                  "the page's parameters when its address gives none, e.g. 'view=frame:alpha&axes=1' "
                  "(docs/visualisation.md, \"Parameters\")");
  sub->add_option("--samples", c->options.samples,
                  "with an ensemble's file: the samples whose runs (ENS-sample-I.h5, written by noether ensemble "
                  "--trajectories K) to show, e.g. 0,3,5 (default: those there are, at most 8)")
      ->delimiter(',');
  sub->add_flag("--force", c->force, "replace an existing page");
  sub->callback([c, &chosen] { chosen = [c] { return view(*c); }; });
}

}  // namespace noether::app
