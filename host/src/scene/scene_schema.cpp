// The scene's schema (scene_schema.hpp): the tables, their checks and readers, and the reference
// they print into docs/user-guide.md.
#include "scene/scene_schema.hpp"

#include <noether/error.hpp>

#include <algorithm>
#include <array>
#include <stdexcept>

namespace noether::detail {

namespace {

using T = KeyType;
using U = SceneUnit;

// ---- the tables ----------------------------------------------------------------------------

constexpr SceneKey kScene[] = {
    {.key = "description", .type = T::text, .doc = "free text"},
    {.key = "units", .type = T::forms, .absent = "the scene's own units (G = 1 unless given)",
     .doc = "`SI` or `{length, mass, time}`: the units of every number in the scene (\"Units\")", .section = "units"},
    {.key = "G", .type = T::number, .unit = U::gravitational_constant,
     .absent = "1, or CODATA 2018's in the declared `units`",
     .doc = "the gravitational constant; with `units` declared it must agree with theirs to 1 %"},
    {.key = "barycentric", .type = T::flag, .otherwise = "false",
     .doc = "shift the initial positions and velocities so that the barycentre rests at the origin"},
    {.key = "bodies", .type = T::list, .required = true, .doc = "the bodies, a non-empty list", .section = "bodies[]"},
    {.key = "impulses", .type = T::list, .absent = "none",
     .doc = "changes of a body's velocity during the run (\"Impulses\")", .section = "impulses[]"},
    {.key = "potential", .type = T::plugin, .required = true,
     .doc = "the mutual potential: a plugin, or a list of them (summed)"},
    {.key = "forces", .type = T::plugin, .absent = "none",
     .doc = "forces beyond the potential (`tides`, `prescribed-body`, `radiation`, `cannonball`): a plugin or a list "
            "(\"Forces beyond gravity\", docs/forces.md)"},
    {.key = "integrator", .type = T::plugin, .required = true, .doc = "the integrator (\"Integrators\")"},
    {.key = "run", .type = T::mapping, .required = true, .doc = "how long, what to write, when to stop", .section = "run"},
    {.key = "particles", .type = T::mapping, .absent = "none",
     .doc = "massless particles in the bodies' field (\"Particles\")", .section = "particles"},
};

constexpr SceneKey kUnits[] = {
    {.key = "length", .type = T::text, .otherwise = "m", .doc = "`m`, `km` or `au`"},
    {.key = "mass", .type = T::text, .otherwise = "kg", .doc = "`kg`, `t`, `M_earth` or `M_sun`"},
    {.key = "time", .type = T::text, .otherwise = "s", .doc = "`s`, `min`, `h`, `day` or `yr`"},
};

constexpr SceneKey kBody[] = {
    {.key = "name", .type = T::text, .required = true,
     .doc = "unique; the name other keys and the output use (letters, digits, `_`, `-`)"},
    {.key = "mass", .type = T::number, .unit = U::mass, .absent = "required unless a shape's `density` or a field's GM gives it",
     .doc = "> 0"},
    {.key = "density", .type = T::number, .unit = U::density, .absent = "from `mass`",
     .doc = "an ellipsoid's or polyhedron's (homogeneous); given with `mass`, the two must agree to 1e-6"},
    {.key = "inertia", .type = T::forms, .unit = U::inertia, .absent = "a point mass (unless a shape or field gives it)",
     .doc = "makes the body rigid: principal moments `[J1, J2, J3]` or a symmetric 3×3 matrix (body frame), "
            "positive definite, with the triangle inequality; a shape's or field's must agree to 1e-6"},
    {.key = "position", .type = T::vector, .unit = U::length, .absent = "required unless `orbit`",
     .doc = "of the centre of mass: inertial, or relative to `relative_to` (\"Initial states\")"},
    {.key = "velocity", .type = T::vector, .unit = U::velocity, .absent = "[0, 0, 0]",
     .doc = "inertial, or relative to `relative_to`"},
    {.key = "relative_to", .type = T::body, .absent = "inertial",
     .doc = "a body whose position and velocity `position` and `velocity` are added to"},
    {.key = "orbit", .type = T::mapping, .absent = "none",
     .doc = "osculating elements about another body, instead of `position` and `velocity`", .section = "bodies[].orbit"},
    {.key = "attitude", .type = T::forms, .absent = "the identity",
     .doc = "rigid only: body → inertial, a 3×3 rotation matrix or a mapping (below); checked to "
            "‖I − RᵀR‖ ≤ 1e-10, det R = +1",
     .section = "bodies[].attitude"},
    {.key = "angular_velocity", .type = T::vector, .unit = U::angular_velocity, .absent = "[0, 0, 0]",
     .doc = "rigid only: Ω in the body frame"},
    {.key = "angular_momentum", .type = T::vector, .unit = U::angular_momentum, .absent = "J Ω",
     .doc = "rigid only: Π = J Ω in the body frame, instead of `angular_velocity`"},
    {.key = "shape", .type = T::mapping, .absent = "none",
     .doc = "one of `ellipsoid`, `polyhedron`, `dumbbell`, `spheres` (\"Shapes\")", .section = "bodies[].shape"},
    {.key = "radius", .type = T::number, .unit = U::length, .absent = "the shape's, the field's reference radius, or 0",
     .doc = "of a sphere about the centre of mass that holds the body, for collisions and landing particles "
            "(a solid shape's comes from the shape)"},
    {.key = "gravity", .type = T::mapping, .absent = "none",
     .doc = "the body given by its gravity field instead of a shape (\"Gravity fields\")", .section = "bodies[].gravity"},
};

// Osculating Keplerian elements (eqs. 17.2–17.4): a particle's about particles.around; a body's
// about its orbit's `around` (kBodyOrbit: these after it).
constexpr SceneKey kParticleOrbit[] = {
    {.key = "a", .type = T::number, .unit = U::length, .required = true, .doc = "semi-major axis, > 0 (bound orbits only)"},
    {.key = "e", .type = T::number, .otherwise = "0", .doc = "eccentricity, in [0, 1)"},
    {.key = "i", .type = T::number, .unit = U::degrees, .otherwise = "0", .doc = "inclination"},
    {.key = "Omega", .type = T::number, .unit = U::degrees, .otherwise = "0", .doc = "longitude of the ascending node"},
    {.key = "omega", .type = T::number, .unit = U::degrees, .otherwise = "0", .doc = "argument of periapsis"},
    {.key = "nu", .type = T::number, .unit = U::degrees, .absent = "from `M`", .doc = "true anomaly"},
    {.key = "M", .type = T::number, .unit = U::degrees, .otherwise = "0",
     .doc = "mean anomaly, when `nu` is not given (M = 0: at periapsis)"},
};

constexpr auto kBodyOrbit = [] {
  std::array<SceneKey, std::size(kParticleOrbit) + 1> out{};
  out[0] = {.key = "around", .type = T::body, .required = true,
            .doc = "the body orbited: μ = G (m + m_around), in the scene frame"};
  std::copy(std::begin(kParticleOrbit), std::end(kParticleOrbit), out.begin() + 1);
  return out;
}();

constexpr SceneKey kAttitude[] = {
    {.key = "matrix", .type = T::matrix, .doc = "a rotation matrix, body → inertial"},
    {.key = "quaternion", .type = T::list, .doc = "`[w, x, y, z]`, scalar first, of unit norm (to 1e-9)"},
    {.key = "euler_angles", .type = T::vector, .unit = U::degrees,
     .doc = "3-2-1 (yaw, pitch, roll) angles (eq. 17.9)"},
};

constexpr SceneKey kShape[] = {
    {.key = "ellipsoid", .type = T::mapping, .doc = "a homogeneous triaxial ellipsoid", .section = "bodies[].shape.ellipsoid"},
    {.key = "polyhedron", .type = T::mapping, .doc = "a homogeneous polyhedron from a shape file",
     .section = "bodies[].shape.polyhedron"},
    {.key = "dumbbell", .type = T::mapping, .doc = "two equal spheres (the sphere-cluster potential)",
     .section = "bodies[].shape.dumbbell"},
    {.key = "spheres", .type = T::list, .doc = "point masses rigidly joined (the sphere-cluster potential)",
     .section = "bodies[].shape.spheres[]"},
};

constexpr SceneKey kEllipsoid[] = {
    {.key = "semi_axes", .type = T::vector, .unit = U::length, .required = true,
     .doc = "`[a, b, c]` along the body's x, y, z, > 0"},
};

constexpr SceneKey kPolyhedron[] = {
    {.key = "file", .type = T::file, .absent = "`vertices` and `facets`",
     .doc = "a Wavefront OBJ file (`v` and `f` lines, 1-based, polygons fanned), or a PDS3 plate model's label "
            "`.lbl` (or its `.tab` beside it: 0-based offsets, the label's unit)"},
    {.key = "vertices", .type = T::file, .absent = "`file`", .doc = "GUBAS's CSV of rows `id, x, y, z`, with `facets`"},
    {.key = "facets", .type = T::file, .absent = "`file`", .doc = "GUBAS's CSV of 1-based rows `i, j, k`"},
    {.key = "units", .type = T::text, .absent = "a PDS3 label's (required otherwise)",
     .doc = "the file's length unit, `m`, `km` or `au` (an OBJ or CSV file does not say it)"},
    {.key = "frame", .type = T::text, .absent = "`principal`; `mesh` for a PDS3 plate model (its archive's body-fixed frame)",
     .doc = "`principal` (the mesh rotated onto its principal axes) or `mesh` (its own axes)"},
    {.key = "scale", .type = T::vector, .absent = "[1, 1, 1]",
     .doc = "the mesh stretched along the body axes about its centre of mass (a shape's extents as parameters)"},
};

constexpr SceneKey kDumbbell[] = {
    {.key = "length", .type = T::number, .unit = U::length, .required = true,
     .doc = "between the two spheres of mass m/2, along the body's x axis"},
};

constexpr SceneKey kSphere[] = {
    {.key = "mass", .type = T::number, .unit = U::mass, .required = true,
     .doc = "> 0; the spheres' masses sum to the body's"},
    {.key = "position", .type = T::vector, .unit = U::length, .required = true,
     .doc = "in the body frame; the spheres' centre of mass at the origin"},
};

constexpr SceneKey kGravity[] = {
    {.key = "stokes", .type = T::file, .required = true,
     .doc = "the coefficient file: an ICGEM `.gfc`, a PDS3 label `.lbl` (or the `.tab` beside it), a PDS SHADR "
            "`.tab` or a table of `n m C S`"},
    {.key = "format", .type = T::text, .absent = "from the file's extension",
     .doc = "`icgem`, `pds`, `shadr` or `table`"},
    {.key = "degree", .type = T::integer, .absent = "the file's", .doc = "use the field to this degree, ≥ 2"},
    {.key = "reference_radius", .type = T::number, .unit = U::length, .absent = "the file's (required for a table)",
     .doc = "may repeat the file's, or override it (said among the warnings: an archived file's defect)"},
    {.key = "normalized", .type = T::flag, .absent = "the file's (required for a table)",
     .doc = "fully normalized (geodesy's 4π) or not; may repeat the file's, not contradict it"},
    {.key = "draw", .type = T::integer, .otherwise = "0",
     .doc = "the coefficients drawn from the file's 1σ (independent normal draws, this seed; 0: as published) — "
            "`noether ensemble --vary 'bodies.B.gravity.draw=grid(1, N, N)'` samples the field's uncertainty"},
    {.key = "polar_moment", .type = T::number, .absent = "the body's `inertia`",
     .doc = "C/(M R²) about the field's z axis (R the reference radius): the field fixes the inertia only up to "
            "its trace; give this or `inertia`"},
};

constexpr SceneKey kImpulse[] = {
    {.key = "body", .type = T::body, .required = true, .doc = "the body whose velocity changes"},
    {.key = "time", .type = T::number, .unit = U::time, .required = true, .doc = "after the start"},
    {.key = "delta_v", .type = T::vector, .unit = U::velocity, .required = true, .doc = "the change, in `frame`"},
    {.key = "frame", .type = T::text, .otherwise = "inertial",
     .doc = "`inertial` (the scene's axes) or `rtn` (radial, along-track, normal of the orbit about `around`)"},
    {.key = "around", .type = T::body, .absent = "the heaviest other body", .doc = "with `frame: rtn` only"},
};

constexpr SceneKey kRun[] = {
    {.key = "t_end", .type = T::number, .unit = U::time, .required = true, .doc = "final time (the run starts at t = 0)"},
    {.key = "output_every", .type = T::number, .unit = U::time, .required = true,
     .doc = "interval between output frames, at most `t_end`"},
    {.key = "close_approach", .type = T::number, .unit = U::length, .otherwise = "0",
     .doc = "stop when two body centres come closer than this (0: off)"},
    {.key = "collisions", .type = T::flag, .otherwise = "true",
     .doc = "stop when two bodies touch: their surfaces when shaped, else their `radius` spheres"},
    {.key = "escape", .type = T::mapping, .absent = "off", .doc = "stop when a body leaves another", .section = "run.escape"},
    {.key = "trust", .type = T::mapping, .absent = "the defaults below", .doc = "the verdict's thresholds (\"Verdict\")",
     .section = "run.trust"},
    {.key = "stm", .type = T::flag, .otherwise = "false",
     .doc = "carry the state-transition matrix ∂z(t)/∂z(t0) of the integrator's map (`--stm`; docs/derivatives.md)"},
    {.key = "sensitivities", .type = T::forms, .absent = "none",
     .doc = "a key or a list of keys (`bodies.moon.velocity`, `G`, `bodies.moon.mass`, `impulses.0.delta_v`, …): "
            "∂z(t)/∂key at every frame (`--sensitivity KEY`; docs/derivatives.md)"},
    {.key = "chaos", .type = T::flag, .otherwise = "false",
     .doc = "MEGNO and the fast Lyapunov indicator from a deviation vector the tangent map carries (`--chaos`)"},
    {.key = "rerun_seconds", .type = T::number, .otherwise = "30",
     .doc = "the longest run (wall seconds) repeated whole when it finishes — at half the step, an adaptive method "
            "at a tenfold tighter tolerance — for its derived numbers' errors and a small orbit's resolution "
            "(\"Verdict\"); 0: never (the summary then says which errors were not estimated)"},
};

constexpr SceneKey kEscape[] = {
    {.key = "body", .type = T::body, .absent = "the lightest body", .doc = "the body that may leave"},
    {.key = "about", .type = T::body, .absent = "the heaviest other body", .doc = "the body it leaves"},
    {.key = "distance", .type = T::number, .unit = U::length, .otherwise = "0",
     .doc = "stop when they are farther apart (0: no distance)"},
    {.key = "unbound", .type = T::flag, .otherwise = "false",
     .doc = "stop when their two-body energy turns positive (osculating e ≥ 1); a distance, this or both"},
};

constexpr SceneKey kTrust[] = {
    {.key = "energy", .type = T::number, .otherwise = "1e-2", .doc = "max \\|E − E0\\| over the energy scale"},
    {.key = "momentum", .type = T::number, .otherwise = "1e-6",
     .doc = "relative linear and angular momentum errors, where conserved"},
    {.key = "orthogonality", .type = T::number, .otherwise = "1e-6", .doc = "max ‖I − RᵀR‖_F"},
    {.key = "position", .type = T::number, .otherwise = "1e-2",
     .doc = "a small body's relative position error at half the step over one orbit, and the checked particles'"},
    {.key = "particle_fates", .type = T::number, .otherwise = "0.05",
     .doc = "the fraction of the checked particles whose fate changes at half their step"},
    {.key = "period", .type = T::number, .otherwise = "1e-3",
     .doc = "a mutual orbit period's, or a body's rotation period's, estimated error (the run repeated at half the "
            "step, or at a tighter tolerance) over the period"},
    {.key = "period_change", .type = T::number, .otherwise = "1e-3",
     .doc = "an impulse's period change ΔP: its estimated error over \\|ΔP\\|"},
    {.key = "libration", .type = T::number, .otherwise = "0.1",
     .doc = "a libration amplitude's or period's estimated error (the run repeated finer; the period's with "
            "its turning points' interpolation) over the amplitude or period"},
    {.key = "closest_approach", .type = T::number, .otherwise = "1e-3",
     .doc = "an encounter's closest approach: its distance's estimated error (the run at half the step, and the "
            "frames' interpolation) over the distance"},
    {.key = "event_time", .type = T::number, .otherwise = "1e-3",
     .doc = "the time of the event that stopped the run (a collision, an escape): its estimated error (the run "
            "at half the step) over the time run until it"},
};

constexpr SceneKey kParticles[] = {
    {.key = "around", .type = T::body, .absent = "inertial states; escape from the barycentre",
     .doc = "the body `states`, `file` and `orbits` are relative to, and `escape` is measured from"},
    {.key = "states", .type = T::list, .absent = "none", .doc = "`[x, y, z, vx, vy, vz]` each"},
    {.key = "file", .type = T::file, .absent = "none", .doc = "six numbers a line, commas or blanks, `#` comments"},
    {.key = "orbits", .type = T::list, .absent = "none", .doc = "osculating elements about `around`",
     .section = "particles.orbits[]"},
    {.key = "ejecta", .type = T::forms, .absent = "none", .doc = "a cloud thrown from a surface, or a list of them",
     .section = "particles.ejecta"},
    {.key = "step", .type = T::number, .unit = U::time, .otherwise = "0",
     .doc = "the particles' longest Verlet step (0: the bodies' step; an integrator that chooses its steps needs one)"},
    {.key = "degree", .type = T::integer, .otherwise = "16", .doc = "of the bodies' series fields"},
    {.key = "tolerance", .type = T::number, .otherwise = "1e-10",
     .doc = "of the series against a polyhedron's exact field, in (0, 1)"},
    {.key = "escape", .type = T::number, .unit = U::length, .otherwise = "0",
     .doc = "a particle farther than this has escaped (0: never)"},
    {.key = "record", .type = T::integer, .otherwise = "100",
     .doc = "the first this many particles' positions at every output frame"},
    {.key = "check", .type = T::integer, .otherwise = "32",
     .doc = "this many, spread through the list, also carried at half the step for the verdict (0: none)"},
};

constexpr SceneKey kEjecta[] = {
    {.key = "body", .type = T::body, .required = true, .doc = "the body they leave (a shape, or a point mass with a radius)"},
    {.key = "site", .type = T::pair, .unit = U::degrees, .required = true,
     .doc = "`[latitude, longitude]` in the body frame: the surface on that ray"},
    {.key = "count", .type = T::integer, .required = true, .doc = "1..10^7"},
    {.key = "speed", .type = T::pair, .unit = U::velocity, .required = true,
     .doc = "`[min, max]` launch speeds relative to the spinning surface"},
    {.key = "exponent", .type = T::number, .otherwise = "1.2", .doc = "γ of N(>v) ∝ v^−γ (eq. 39.1)"},
    {.key = "cone", .type = T::number, .unit = U::degrees, .otherwise = "45",
     .doc = "between each launch and the surface's normal, in [0, 90); azimuths uniform"},
    {.key = "height", .type = T::number, .unit = U::length, .otherwise = "0",
     .doc = "above the surface at launch (0: 1e-6 of the body's radius)"},
    {.key = "seed", .type = T::integer, .absent = "k + 1 for the k-th cloud, from 0",
     .doc = "particle i's speed and azimuth depend on (seed, i) alone"},
};

constexpr SceneSection kSections[] = {
    {"", "the scene's top level", kScene},
    {"units", "the scene's units (\"Units\"); each optional", kUnits},
    {"bodies[]", "a body", kBody},
    {"bodies[].orbit", "a body's initial orbit (eqs. 17.2–17.4)", kBodyOrbit},
    {"bodies[].attitude", "a rigid body's initial attitude as a mapping: one of its keys", kAttitude},
    {"bodies[].shape", "a body's shape: one of its keys", kShape},
    {"bodies[].shape.ellipsoid", "an ellipsoid", kEllipsoid},
    {"bodies[].shape.polyhedron", "a polyhedron; file names are relative to the scene's folder", kPolyhedron},
    {"bodies[].shape.dumbbell", "a dumbbell (read by the sphere-cluster potential)", kDumbbell},
    {"bodies[].shape.spheres[]", "a sphere of a cluster (read by the sphere-cluster potential)", kSphere},
    {"bodies[].gravity", "a body given by its gravity field (\"Gravity fields\")", kGravity},
    {"impulses[]", "an impulse (\"Impulses\")", kImpulse},
    {"run", "the run", kRun},
    {"run.escape", "when a body has escaped", kEscape},
    {"run.trust", "the verdict's thresholds (\"Verdict\")", kTrust},
    {"particles", "massless particles (\"Particles\"): `states`, `file`, `orbits`, `ejecta` add particles, in that order",
     kParticles},
    {"particles.orbits[]", "a particle's orbit about `particles.around`", kParticleOrbit},
    {"particles.ejecta", "a cloud of ejecta (eqs. 39.1–39.2)", kEjecta},
};

// ---- checks and readers --------------------------------------------------------------------

const char* type_name(KeyType type) {
  switch (type) {
    case T::number: return "number";
    case T::integer: return "integer";
    case T::flag: return "true/false";
    case T::text: return "text";
    case T::file: return "file";
    case T::body: return "body name";
    case T::vector: return "[x, y, z]";
    case T::pair: return "[a, b]";
    case T::matrix: return "3×3 matrix";
    case T::list: return "list";
    case T::mapping: return "mapping";
    case T::plugin: return "{plugin: NAME, …}";
    case T::forms: return "forms (see meaning)";
  }
  return "";
}

const char* unit_name(SceneUnit unit) {
  switch (unit) {
    case U::none: return "";
    case U::length: return "length";
    case U::mass: return "mass";
    case U::time: return "time";
    case U::velocity: return "length/time";
    case U::density: return "mass/length³";
    case U::inertia: return "mass·length²";
    case U::angular_velocity: return "rad/time";
    case U::angular_momentum: return "mass·length²/time";
    case U::degrees: return "degrees";
    case U::gravitational_constant: return "length³/(mass·time²)";
  }
  return "";
}

// A value of the row's type, or SceneError at its line (the messages of Params' own readers).
void check_type(const SceneKey& row, const Params& value) {
  if (value.is_null()) return;  // the reader decides what an empty value means
  switch (row.type) {
    case T::number: (void)value.as_double(); break;
    case T::integer: (void)value.as_int(); break;
    case T::flag: (void)value.as_bool(); break;
    case T::text:
    case T::file:
    case T::body: (void)value.as_string(); break;
    case T::vector:
      if (const auto n = value.as_doubles().size(); n != 3)
        throw SceneError(value.here() + "'" + value.path() + "' must have 3 components, not " + std::to_string(n));
      break;
    case T::pair: (void)value.as_doubles(); break;
    default: break;  // lists, mappings, plugins and forms: their readers say what they expected
  }
}

// The sections other than `self` that have `key`, as "'run'" or "'run' and 'particles'".
std::string sections_having(std::string_view key, const SceneSection& self) {
  std::string out;
  for (const SceneSection& s : kSections) {
    if (&s == &self || std::none_of(s.keys.begin(), s.keys.end(), [&](const SceneKey& k) { return k.key == key; }))
      continue;
    out += (out.empty() ? "'" : ", '") + (s.path.empty() ? std::string("the top level") : std::string(s.path)) + "'";
  }
  return out;
}

Params default_of(const SceneSection& section, std::string_view key) {
  const SceneKey& row = section.row(key);
  if (row.otherwise.empty())
    throw std::logic_error("scene schema: '" + std::string(section.path) + "." + std::string(key) +
                           "' has no default; its reader must handle its absence");
  return Params::scalar(std::string(row.otherwise), "the scene reference's default");
}

const Params& value_or_default(const Params& node, const SceneSection& section, std::string_view key,
                               Params& fallback) {
  const std::string k(key);
  if (node.is_map() && node.has(k)) {
    (void)section.row(key);  // a key of the table
    return node.at(k);
  }
  fallback = default_of(section, key);
  return fallback;
}

}  // namespace

const SceneKey& SceneSection::row(std::string_view key) const {
  for (const SceneKey& k : keys)
    if (k.key == key) return k;
  throw std::logic_error("scene schema: section '" + std::string(path) + "' has no key '" + std::string(key) + "'");
}

void SceneSection::check(const Params& node, const std::string& what) const {
  std::vector<std::string> allowed;
  for (const SceneKey& k : keys) allowed.emplace_back(k.key);
  for (const auto& [key, value] : node.entries()) {
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string msg = value.here() + "unknown key '" + key + "' in " + what;
      if (const std::string guess = closest_match(key, allowed); !guess.empty()) msg += " (did you mean '" + guess + "'?)";
      msg += "; allowed keys:";
      for (const auto& a : allowed) msg += " " + a;
      if (const std::string elsewhere = sections_having(key, *this); !elsewhere.empty())
        msg += "; '" + key + "' is a key of " + elsewhere;
      throw SceneError(msg);
    }
    check_type(row(key), value);
  }
  for (const SceneKey& k : keys)
    if (k.required && !node.has(std::string(k.key)))
      throw SceneError(node.here() + what + " needs '" + std::string(k.key) + "' (" + std::string(k.doc) + ")");
}

double SceneSection::number(const Params& node, std::string_view key) const {
  Params fallback;
  return value_or_default(node, *this, key, fallback).as_double();
}

long SceneSection::integer(const Params& node, std::string_view key) const {
  Params fallback;
  return value_or_default(node, *this, key, fallback).as_int();
}

bool SceneSection::flag(const Params& node, std::string_view key) const {
  Params fallback;
  return value_or_default(node, *this, key, fallback).as_bool();
}

std::string SceneSection::text(const Params& node, std::string_view key) const {
  Params fallback;
  return value_or_default(node, *this, key, fallback).as_string();
}

std::span<const SceneSection> scene_sections() { return kSections; }

const SceneSection& scene_section(std::string_view path) {
  for (const SceneSection& s : kSections)
    if (s.path == path) return s;
  throw std::logic_error("scene schema: no section '" + std::string(path) + "'");
}

std::string scene_reference_markdown() {
  const auto code = [](std::string_view text) {  // `text`
    std::string out(1, '`');
    out.append(text);
    return out + '`';
  };
  std::string out;
  for (const SceneSection& s : kSections) {
    out += "\n**" + code(s.path.empty() ? "(top level)" : s.path) + "** — ";
    out.append(s.about);
    out += ".\n\n| key | type | unit | default | meaning |\n|-----|------|------|---------|---------|\n";
    for (const SceneKey& k : s.keys) {
      const std::string fallback = k.required ? std::string("required")
                                   : k.otherwise.empty() ? std::string(k.absent.empty() ? "—" : k.absent)
                                                         : code(k.otherwise);
      out += "| " + code(k.key) + " | " + type_name(k.type) + " | " + unit_name(k.unit) + " | " + fallback + " | ";
      out.append(k.doc);
      if (!k.section.empty()) out += " → " + code(k.section);
      out += " |\n";
    }
  }
  return out;
}

}  // namespace noether::detail
