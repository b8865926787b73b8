#pragma once
// The readers of a scene's sections, one file each, which parse_scene (scene.cpp) calls in the
// order a section needs the ones before it: units and G, the bodies (System), their initial
// state, the models, impulses, particles, run. Each checks its keys by the schema
// (scene_schema.hpp), reads its defaults from it and throws SceneError with file:line.
#include <noether/orbital_elements.hpp>
#include <noether/params.hpp>
#include <noether/scene.hpp>
#include <noether/solid.hpp>
#include <noether/stokes_coefficients.hpp>
#include <noether/units.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace noether::detail {

// shape.cpp — shape: {ellipsoid: {semi_axes}} or {polyhedron: {file | vertices + facets, units,
// frame, scale}} at density 1; then at the body's density (from `density` or `mass`), checked
// against `mass` and `inertia` when those are given too.
std::shared_ptr<const Solid> parse_solid(const Params& shape, const std::string& body,
                                         const std::filesystem::path& folder, const Units& scene_units);
std::shared_ptr<const Solid> scale_solid(const Solid& unit, const Params& b, const std::string& body);

// field_body.cpp — a body given by its gravity field (`gravity:`; docs/gravity-fields.md): its
// coefficients in the scene's units, its mass (the file's GM / G, or the body's `mass`), its
// inertia (the field's degree 2 and one more number: the body's `inertia` or the field's
// `polar_moment`, eq. 31.4) and its radius (the body's `radius`, else the reference radius).
struct FieldBody {
  std::shared_ptr<const StokesCoefficients> field;
  double mass = 0.0, radius = 0.0;
  Mat3 inertia = Mat3::Zero();
  // What the scene should be told: the file's defects as archived, values of the scene's that
  // override the file's (Scene::warnings).
  std::vector<std::string> notes;
};
FieldBody parse_field_body(const Params& b, const std::string& body, const std::filesystem::path& folder,
                           const Units& units, double G);

// bodies.cpp — G (as given, or from the declared units, eq. 17.1, or 1) and the bodies'
// constants: the System.
double scene_gravitational_constant(const Params& root, const Units& units);
System parse_bodies(const Params& root, const Units& units, double G, const std::filesystem::path& folder,
                    std::vector<std::string>& notes);  // `notes`: the bodies' FieldBody::notes

// initial_state.cpp — an `orbit:` mapping's osculating elements for `who` ("body 'moon'",
// "particle 3"), and the bodies' initial state (docs/user-guide.md, "Initial states").
OrbitalElements orbit_elements(const Params& o, const std::string& who);
State initial_state(const Params& bodies, const System& system, bool barycentric);

// impulses.cpp — impulses: [{body, time, delta_v, frame, around}], each after t0.
std::vector<Impulse> parse_impulses(const Params& list, const System& system, double t0);

// particles.cpp — particles: {around, states | file | orbits | ejecta, ...} (docs/user-guide.md,
// "Particles").
ParticleSettings parse_particles(const Params& p, const System& system, const State& initial,
                                 const std::filesystem::path& folder);

// run_settings.cpp — run: {t_end, output_every, events, trust, derivatives}; refuses bodies that
// overlap at the start when collisions are on.
RunSettings parse_run(const Params& run, const System& system, const State& initial, const Params& bodies);

}  // namespace noether::detail
