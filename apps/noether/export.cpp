// noether export: a run's bodies for other tools — ParaView's VTK time series (docs/visualisation.md).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/export.hpp>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>

namespace noether::app {

namespace {

struct ExportCommand {
  std::string run, output, format = "vtk";
  ExportOptions options;
};

int export_run(const ExportCommand& c) {
  if (c.format != "vtk")
    throw SceneError("--format " + c.format + ": the formats are vtk (ParaView's .pvd time series of .vtu files)");
  const std::filesystem::path collection =
      c.output.empty() ? std::filesystem::path(c.run).replace_extension(".pvd") : std::filesystem::path(c.output);
  const ExportReport r = export_vtk(c.run, collection, c.options);
  for (const auto& note : r.notes) std::fprintf(stderr, "noether: note: %s\n", note.c_str());
  std::printf("export: %s and %s/ (%zu of %zu frames, %.1f MB); open the .pvd in ParaView\n", r.collection.c_str(),
              r.folder.c_str(), r.frames_written, r.frames_in_file, static_cast<double>(r.bytes) / 1e6);
  return 0;
}

}  // namespace

void add_export_command(CLI::App& app, Command& chosen) {
  auto c = std::make_shared<ExportCommand>();
  auto* sub = app.add_subcommand("export", "a run's bodies for other tools: ParaView's time series (VTK .pvd + .vtu)");
  sub->add_option("run", c->run, "the run's output file (noether run -o)")->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", c->output,
                  "the collection to write, NAME.pvd, and its frames in the folder NAME/ (default: the run's name)");
  sub->add_option("--format", c->format, "vtk: a .pvd collection of VTK XML unstructured grids (.vtu)")->capture_default_str();
  sub->add_option("--max-frames", c->options.max_frames,
                  "at most this many frames, evenly spaced, the first and last among them")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{2}, std::size_t{1} << 26));
  sub->add_option("--tessellation", c->options.tessellation,
                  "ellipsoids and spheres as the icosahedron subdivided this many times (20·4^level triangles)")
      ->capture_default_str()
      ->check(CLI::Range(0, 6));
  sub->add_flag("--force", c->options.force, "replace an earlier export of the same name");
  sub->callback([c, &chosen] { chosen = [c] { return export_run(*c); }; });
}

}  // namespace noether::app
