// noether shape stokes: a body's Stokes coefficients from its shape (docs/gravity-fields.md).
#include "commands.hpp"

#include <noether/body_stokes.hpp>
#include <noether/error.hpp>
#include <noether/scene.hpp>
#include <noether/stokes_file.hpp>

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace noether::app {

namespace {

struct StokesOptions {
  std::string scene, body, output, format;
  std::vector<std::string> overrides;
  int degree = 8;
  double radius = 0.0;
  bool unnormalized = false, force = false;
};

int shape_stokes(const StokesOptions& o) {
  const Scene scene = load_scene(o.scene, o.overrides);
  const BodyStokes s = body_stokes(scene, o.body, o.degree, o.radius, !o.unnormalized);
  const StokesCoefficients& cs = s.coefficients;
  const std::string format = !o.format.empty() ? o.format : o.output.empty() ? "table" : stokes_format_of(o.output);
  if (format != "icgem" && format != "table")
    throw SceneError("--format must be icgem (.gfc) or table, not '" + format + "'");
  char line[256];
  std::vector<std::string> about;
  std::snprintf(line, sizeof line, "noether shape stokes: body '%s' of %s, from %s", o.body.c_str(), o.scene.c_str(),
                s.source.c_str());
  about.emplace_back(line);
  std::snprintf(line, sizeof line,
                "about its centre of mass in its body frame; mass %.17g, GM %.17g, reference radius %.17g (%s)",
                cs.mass, s.gm, cs.reference_radius, scene.units.describe().c_str());
  about.emplace_back(line);
  std::snprintf(line, sizeof line, "polar moment C/(M R^2) %.17g (gravity.polar_moment)", s.polar_moment);
  about.emplace_back(line);
  std::ostringstream text;
  if (format == "icgem") {
    if (!scene.units.declared)
      throw SceneError(o.scene + ": an ICGEM file gives GM in m^3/s^2 and its radius in m, and the scene declares no "
                       "units: declare them ('units: SI') or write a table (--format table)");
    const double L = scene.units.length_si, T = scene.units.time_si;
    write_icgem(text, cs, s.gm * L * L * L / (T * T), cs.reference_radius * L, "noether-" + o.body, about);
  } else {
    write_stokes_table(text, cs, about);
  }
  if (o.output.empty()) {
    std::cout << text.str();
    return 0;
  }
  std::error_code ec;
  if (std::filesystem::exists(o.output, ec) && !o.force)
    throw OutputError(o.output + " exists; --force replaces it");
  std::ofstream out(o.output);
  out << text.str();
  out.close();
  if (!out) throw OutputError(o.output + ": cannot write");
  for (const std::string& a : about) std::cout << a << "\n";
  std::cout << "degree " << cs.degree << ", " << (cs.normalized ? "fully normalized" : "unnormalized") << ", written to "
            << o.output << " (" << format << ")\n";
  return 0;
}

}  // namespace

void add_shape_command(CLI::App& app, Command& chosen) {
  auto* shape = app.add_subcommand("shape", "a body's shape as other tools use it: stokes (its gravity field)");
  shape->require_subcommand(1);
  auto o = std::make_shared<StokesOptions>();
  auto* cmd = shape->add_subcommand(
      "stokes", "a body's Stokes coefficients from its shape (or field, or inertia) about its centre of mass, in its "
                "body frame (docs/gravity-fields.md)");
  cmd->add_option("scene", o->scene, "the scene (YAML)")->required();
  cmd->add_option("--body", o->body, "the body's name")->required();
  cmd->add_option("--degree", o->degree, "the highest degree")->capture_default_str();
  cmd->add_option("--radius", o->radius, "the reference radius, in the scene's length unit (default: the body's radius)");
  cmd->add_flag("--unnormalized", o->unnormalized, "unnormalized coefficients (default: fully normalized, geodesy's 4π)");
  cmd->add_option("--format", o->format, "icgem (ICGEM .gfc) or table (n m C S); default from -o's extension, table");
  cmd->add_option("-o,--output", o->output, "the file to write (default: the table on standard output)");
  cmd->add_flag("--force", o->force, "replace an existing output file");
  cmd->add_option("--set", o->overrides, "override a scene value: key=value")->take_all();
  cmd->callback([o, &chosen] { chosen = [o] { return shape_stokes(*o); }; });
}

}  // namespace noether::app
