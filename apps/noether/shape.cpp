// noether shape stokes: a body's Stokes coefficients from its shape (docs/gravity-fields.md).
#include "commands.hpp"

#include <noether/body_stokes.hpp>
#include <noether/error.hpp>
#include <noether/pds3_label.hpp>
#include <noether/scene.hpp>
#include <noether/stokes_file.hpp>

#include <CLI/CLI.hpp>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>

namespace noether::app {

namespace {

struct StokesOptions {
  std::string scene, body, output, format, units, frame;
  std::vector<std::string> overrides;
  int degree = 8;
  double radius = 0.0, density = 0.0;
  bool unnormalized = false, force = false;
};

bool is_mesh_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".obj" || !pds3_label_of(path).empty();  // an OBJ, or a PDS3 plate model (its label or table)
}

// A mesh file given instead of a scene: the scene of one homogeneous body of that shape, in SI
// units (its `units` and `frame` as a scene's polyhedron takes them), named after the file.
Scene mesh_scene(StokesOptions& o) {
  const std::filesystem::path mesh(o.scene);
  if (!(o.density > 0.0) || !std::isfinite(o.density))
    throw SceneError(o.scene + ": a mesh alone needs --density (kg/m^3, the homogeneous body's; it gives the mass "
                     "and GM, not the normalized coefficients)");
  const bool pds = !pds3_label_of(mesh).empty();  // a PDS3 plate model says its unit
  if (o.units.empty() && !pds)
    throw SceneError(o.scene + ": a mesh file does not say its units: give --units m or --units km");
  if (o.body.empty()) o.body = mesh.stem().string();
  char density[32];
  std::snprintf(density, sizeof density, "%.17g", o.density);
  // JSON strings are YAML: the file name and body name quoted whatever they hold.
  auto quoted = [](const std::string& text) {
    std::string out = "\"";
    for (char c : text) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    return out + "\"";
  };
  const std::string text = "units: SI\nbodies:\n  - {name: " + quoted(o.body) + ", density: " + density +
                           ", position: [0, 0, 0], shape: {polyhedron: {file: " + quoted(mesh.filename().string()) +
                           (o.units.empty() ? "" : ", units: " + quoted(o.units)) +
                           (o.frame.empty() ? "" : ", frame: " + quoted(o.frame)) +
                           "}}}\npotential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 1}\n"
                           "run: {t_end: 1, output_every: 1}\n";
  return parse_scene(text, o.scene, o.overrides);
}

int shape_stokes(StokesOptions o) {
  const bool mesh = is_mesh_file(o.scene);
  if (!mesh && (o.density > 0.0 || !o.units.empty() || !o.frame.empty()))
    throw SceneError("--density, --units and --frame go with a mesh file (.obj) given instead of a scene; a scene's "
                     "body has its own");
  if (!mesh && o.body.empty()) throw SceneError("--body: which body of " + o.scene + " (a scene names its bodies)");
  const Scene scene = mesh ? mesh_scene(o) : load_scene(o.scene, o.overrides);
  const BodyStokes s = body_stokes(scene, o.body, o.degree, o.radius, !o.unnormalized);
  const StokesCoefficients& cs = s.coefficients;
  // From -o's name: .gfc is ICGEM, .tab SHADR (read, not written), any other name a table.
  const std::string named = o.output.empty() ? "" : stokes_format_of(o.output);
  const std::string format = !o.format.empty() ? o.format : named.empty() ? "table" : named;
  if (format != "icgem" && format != "table")
    throw SceneError("--format must be icgem (.gfc) or table, not '" + format + "'" +
                     (format == "shadr" ? " (noether reads SHADR .tab files but does not write them)" : ""));
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
  // A shape file's own origin and axes are not the expansion's: say where the homogeneous body's
  // centre of mass lies in the file (an archived plate model's origin is its tracked centre of
  // mass, about which a published field is taken) and how the axes turn.
  if (const int k = scene.system.index_of(o.body); k >= 0)
    if (const auto& solid = scene.system.body(static_cast<std::size_t>(k)).solid;
        solid && solid->kind == Solid::Kind::Polyhedron) {
      std::snprintf(line, sizeof line,
                    "the homogeneous body's centre of mass lies at (%.6g, %.6g, %.6g) in the file's frame, %.4g from "
                    "its origin; axes turned by %.4g deg onto the body frame",
                    solid->offset.x(), solid->offset.y(), solid->offset.z(), solid->offset.norm(),
                    log_so3(solid->rotation).norm() * 180.0 / std::numbers::pi);
      about.emplace_back(line);
    }
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
  cmd->add_option("scene", o->scene,
                  "the scene (YAML), or a mesh file (.obj, with --density and --units; a PDS3 plate model's .lbl or "
                  ".tab, with --density)")
      ->required();
  cmd->add_option("--body", o->body, "the body's name (a scene's; for a mesh the file's name, as the output names it)");
  cmd->add_option("--density", o->density, "a mesh's homogeneous density in kg/m^3 (its mass and GM)");
  cmd->add_option("--units", o->units, "a mesh file's length unit: m or km (an OBJ does not say; a PDS3 label does)");
  cmd->add_option("--frame", o->frame,
                  "a mesh's body frame: principal (an OBJ's default: its principal axes about its centre of mass) or "
                  "mesh (the file's axes, moved to the centre of mass: a published field's frame; a PDS3 plate "
                  "model's default)");
  cmd->add_option("--degree", o->degree, "the highest degree")->capture_default_str();
  cmd->add_option("--radius", o->radius, "the reference radius, in the scene's length unit (default: the body's radius)");
  cmd->add_flag("--unnormalized", o->unnormalized, "unnormalized coefficients (default: fully normalized, geodesy's 4π)");
  cmd->add_option("--format", o->format, "icgem (ICGEM .gfc) or table (n m C S); default from -o's extension, table");
  cmd->add_option("-o,--output", o->output, "the file to write (default: the table on standard output)");
  cmd->add_flag("--force", o->force, "replace an existing output file");
  cmd->add_option("--set", o->overrides, "override a scene value: key=value")->take_all();
  cmd->callback([o, &chosen] { chosen = [o] { return shape_stokes(*o); }; });  // a copy: a mesh names its body
}

}  // namespace noether::app
