// parse_scene: the scene's tree (scene_yaml.cpp) checked and built into bodies, shapes, initial
// states, plugins and run settings (docs/user-guide.md, "Scenes").
#include <noether/ejecta.hpp>
#include <noether/error.hpp>
#include <noether/euler_angles.hpp>
#include <noether/force_model.hpp>
#include <noether/orbital_elements.hpp>
#include <noether/scene.hpp>
#include <noether/stokes_file.hpp>
#include <noether/units.hpp>

#include "run/event_watch.hpp"
#include "scene/scene_yaml.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <cmath>
#include <optional>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

namespace noether {

namespace {

Vec3 vec3(const Params& p) {
  const auto v = p.as_doubles();
  if (v.size() != 3)
    throw SceneError(p.here() + "'" + p.path() + "' must have 3 components, not " +
                     std::to_string(v.size()));
  return Vec3(v[0], v[1], v[2]);
}

// A 3×3 matrix from [[a,b,c],[d,e,f],[g,h,i]].
Mat3 mat3(const Params& p) {
  if (!p.is_sequence() || p.size() != 3)
    throw SceneError(p.here() + "'" + p.path() + "' must be a 3×3 matrix: three rows of three");
  Mat3 m;
  for (int r = 0; r < 3; ++r) m.row(r) = vec3(p.items()[static_cast<std::size_t>(r)]).transpose();
  return m;
}

Mat3 inertia(const Params& p) {
  if (p.is_sequence() && p.size() == 3 && p.items()[0].is_scalar())
    return vec3(p).asDiagonal();  // principal moments
  if (p.is_sequence() && p.size() == 3) return mat3(p);
  throw SceneError(p.here() + "'" + p.path() +
                   "' must be three principal moments [J1, J2, J3] or a 3×3 matrix");
}

Mat3 attitude(const Params& p, const std::string& body) {
  Mat3 R;
  if (p.is_map()) {
    p.check_keys({"quaternion", "matrix", "euler_angles"}, "attitude of body '" + body + "'");
    if (p.has("matrix")) return attitude(p.at("matrix"), body);
    if (p.has("euler_angles")) {  // 3-2-1 (yaw, pitch, roll) in degrees, eq. 17.9
      const Vec3 angles = vec3(p.at("euler_angles"));
      if (!angles.allFinite())
        throw SceneError(p.at("euler_angles").here() + "euler_angles of body '" + body + "' must be finite");
      return rotation_from_euler_321(angles * (std::numbers::pi / 180.0));
    }
    const auto q = p.at("quaternion").as_doubles();
    if (q.size() != 4)
      throw SceneError(p.here() + "quaternion of body '" + body + "' needs 4 numbers [w, x, y, z]");
    const Vec4 qv(q[0], q[1], q[2], q[3]);
    if (std::abs(qv.norm() - 1.0) > 1e-9) {
      std::ostringstream msg;
      msg << p.here() << "quaternion of body '" << body << "' has norm " << qv.norm()
          << "; a rotation needs a unit quaternion (scalar first)";
      throw SceneError(msg.str());
    }
    R = rotation_from_quaternion(qv);
  } else {
    R = mat3(p);
  }
  const double err = orthogonality_error(R);
  if (err > 1e-10 || R.determinant() <= 0.0) {
    std::ostringstream msg;
    msg << p.here() << "attitude of body '" << body
        << "' is not a rotation matrix: ‖I − RᵀR‖ = " << err << ", det R = " << R.determinant()
        << " (needs ‖I − RᵀR‖ ≤ 1e-10 and det R = +1)";
    throw SceneError(msg.str());
  }
  return R;
}

// A file a scene names (`f`): relative to the scene file's folder, not to the working directory,
// so that a copied scene without its files is told where they were looked for.
std::filesystem::path scene_file(const Params& f, const std::filesystem::path& folder, const std::string& who,
                                 const std::string& what) {
  const std::filesystem::path path(f.as_string());
  const std::filesystem::path resolved = path.is_absolute() ? path : folder / path;
  std::error_code ec;
  if (!std::filesystem::exists(resolved, ec)) {
    const std::filesystem::path shown = std::filesystem::absolute(resolved, ec).lexically_normal();
    throw SceneError(f.here() + who + ": " + what + " '" + f.as_string() + "' not found" +
                     (path.is_absolute() ? std::string() : " (relative to the scene's folder: " + shown.string() + ")"));
  }
  return resolved;
}

// shape: {ellipsoid: {semi_axes: [a, b, c]}} or {polyhedron: {file | vertices + facets,
// units: m | km, frame: principal | mesh}}, density 1 (scaled by the caller).
std::shared_ptr<const Solid> parse_solid(const Params& shape, const std::string& body,
                                         const std::filesystem::path& folder, const Units& scene_units) {
  const std::string who = "body '" + body + "'";
  if (shape.has("ellipsoid")) {
    const Params& e = shape.at("ellipsoid");
    e.check_keys({"semi_axes"}, "the ellipsoid of " + who);
    const Vec3 axes = vec3(e.at("semi_axes"));
    if (!axes.allFinite() || axes.minCoeff() <= 0.0)
      throw SceneError(e.at("semi_axes").here() + who + ": ellipsoid semi-axes must be positive");
    return make_ellipsoid(axes, 1.0);
  }
  const Params& p = shape.at("polyhedron");
  p.check_keys({"file", "vertices", "facets", "units", "frame", "scale"}, "the polyhedron of " + who);
  if (!p.has("units"))
    throw SceneError(p.here() + who + ": the polyhedron needs 'units: m' or 'units: km' (a "
                     "shape file does not say its units)");
  const std::string units = p.at("units").as_string();
  const double file_unit = length_unit_in_metres(units);
  if (file_unit == 0.0)
    throw SceneError(p.at("units").here() + who + ": unknown units '" + units +
                     "'; use m, km or au");
  // Into the scene's length unit; metres when the scene declares none.
  const double scale = file_unit / scene_units.length_si;
  const std::string frame = p.get("frame", std::string("principal"));
  if (frame != "principal" && frame != "mesh")
    throw SceneError(p.at("frame").here() + who + ": frame must be 'principal' (rotate the "
                     "mesh onto its principal axes) or 'mesh' (keep its axes), not '" + frame + "'");
  auto resolve = [&](const Params& f) { return scene_file(f, folder, who, "shape file"); };
  Mesh mesh;
  if (p.has("file") == (p.has("vertices") || p.has("facets")))
    throw SceneError(p.here() + who + ": give either 'file' (Wavefront OBJ) or 'vertices' and "
                     "'facets' (CSV pair)");
  const std::filesystem::path first = resolve(p.at(p.has("file") ? "file" : "vertices"));
  const std::filesystem::path facets = p.has("file") ? std::filesystem::path() : resolve(p.at("facets"));
  std::shared_ptr<const Solid> solid;
  try {
    mesh = p.has("file") ? read_obj(first, scale) : read_vertex_facet_csv(first, facets, scale);
    solid = make_polyhedron(std::move(mesh), 1.0, frame == "principal");
  } catch (const SceneError& e) {
    throw SceneError(p.here() + who + ": " + e.what());
  }
  if (!p.has("scale")) return solid;
  // scale: [sx, sy, sz], the mesh stretched along the body axes about its centre of mass (a
  // shape model's extents as parameters: fitted, or differentiated by run.sensitivities).
  const Vec3 stretch = vec3(p.at("scale"));
  if (!stretch.allFinite() || stretch.minCoeff() <= 0.0)
    throw SceneError(p.at("scale").here() + who + ": the polyhedron's scale factors must be positive");
  return stretched_polyhedron(*solid, stretch);
}

// The solid at the body's density (from `density` or `mass`), checked against `mass` and
// `inertia` when those are given too.
std::shared_ptr<const Solid> scale_solid(const Solid& unit, const Params& b, const std::string& body) {
  const std::string who = "body '" + body + "'";
  if (!b.has("density") && !b.has("mass"))
    throw SceneError(b.here() + who + " has a shape: give its 'density' or its 'mass'");
  double density = b.has("density") ? b.at("density").as_double() : b.at("mass").as_double() / unit.volume;
  if (!std::isfinite(density) || density <= 0.0)
    throw SceneError((b.has("density") ? b.at("density") : b.at("mass")).here() + who +
                     ": density and mass must be positive");
  auto s = std::make_shared<Solid>(unit);
  s->density = density;
  s->mass = density * unit.volume;
  s->inertia = density * unit.inertia;
  if (b.has("density") && b.has("mass")) {
    const double m = b.at("mass").as_double();
    if (std::abs(m - s->mass) > 1e-6 * s->mass) {
      std::ostringstream msg;
      msg.precision(10);
      msg << b.at("mass").here() << who << ": mass " << m << " contradicts density " << density
          << " × shape volume " << unit.volume << " = " << s->mass
          << "; give one of 'mass' and 'density'";
      throw SceneError(msg.str());
    }
  }
  if (b.has("inertia")) {
    const Mat3 J = inertia(b.at("inertia"));
    if ((J - s->inertia).cwiseAbs().maxCoeff() > 1e-6 * s->inertia.cwiseAbs().maxCoeff()) {
      std::ostringstream msg;
      msg.precision(10);
      msg << b.at("inertia").here() << who << ": 'inertia' " << J.format(Eigen::IOFormat(10, 0, ", ", "; ", "", "", "[", "]"))
          << " contradicts the shape's inertia "
          << s->inertia.format(Eigen::IOFormat(10, 0, ", ", "; ", "", "", "[", "]"))
          << " (body frame, agreement to 1e-6 relative required); omit 'inertia' to use the shape's";
      throw SceneError(msg.str());
    }
  }
  return s;
}

// A body given by its gravity field (`gravity: {stokes: FILE, format, degree, reference_radius,
// normalized, polar_moment}`; docs/gravity-fields.md): its coefficients in the scene's units, its
// mass (the file's GM / G, or the body's `mass`), its inertia (the field's degree 2 and one more
// number: the body's `inertia` or the field's `polar_moment`, eq. 31.4) and its radius (the
// body's `radius`, else the reference radius).
struct FieldBody {
  std::shared_ptr<const StokesCoefficients> field;
  double mass = 0.0, radius = 0.0;
  Mat3 inertia = Mat3::Zero();
};

FieldBody parse_field_body(const Params& b, const std::string& body, const std::filesystem::path& folder,
                           const Units& units, double G) {
  const std::string who = "body '" + body + "'";
  const Params& g = b.at("gravity");
  if (!g.is_map() || !g.has("stokes"))
    throw SceneError(g.here() + who + ": 'gravity' needs 'stokes: FILE' (an ICGEM .gfc file, a PDS SHADR .tab "
                     "table or a table of n m C S)");
  g.check_keys({"stokes", "format", "degree", "reference_radius", "normalized", "polar_moment"},
               "the gravity field of " + who);
  for (const char* key : {"shape", "density"})
    if (b.has(key))
      throw SceneError(b.at(key).here() + who + " is given by its gravity field; it cannot have a '" + key +
                       "' as well");
  const std::filesystem::path path = scene_file(g.at("stokes"), folder, who, "gravity-field file");
  const std::string format = g.has("format") ? g.at("format").as_string() : stokes_format_of(path);
  if (format.empty())
    throw SceneError(g.at("stokes").here() + who + ": say the field file's 'format' (icgem, shadr or table); "
                     "its name does not tell (.gfc is icgem, .tab shadr)");
  if (format != "icgem" && format != "shadr" && format != "table")
    throw SceneError(g.at("format").here() + who + ": unknown gravity-field format '" + format +
                     "'; use icgem (.gfc), shadr (PDS .tab) or table (n m C S)");
  StokesFile file;
  try {
    file = read_stokes_file(path, format);
  } catch (const SceneError& e) {
    throw SceneError(g.at("stokes").here() + who + ": " + e.what());
  }
  // The reference radius, GM and normalization are the file's (the scene may repeat them, not
  // contradict them); a table's come from the scene.
  if (file.gm && !units.declared)
    throw SceneError(g.here() + who + ": the " + format + " file gives GM in m^3/s^2 and its reference radius in "
                     "m; declare the scene's units ('units: SI', or {length: km, ...}) so they can be converted");
  double R = file.reference_radius ? *file.reference_radius / units.length_si : 0.0;
  if (g.has("reference_radius")) {
    const double given = g.at("reference_radius").as_double();
    if (!(given > 0.0) || !std::isfinite(given))
      throw SceneError(g.at("reference_radius").here() + who + ": the reference radius must be positive");
    if (file.reference_radius && std::abs(given - R) > 1e-9 * R)
      throw SceneError(g.at("reference_radius").here() + who + ": reference_radius " + g.at("reference_radius").as_string() +
                       " contradicts the file's " + std::to_string(R) + " (in the scene's length unit); omit it");
    R = given;
  } else if (!file.reference_radius) {
    throw SceneError(g.here() + who + ": a table does not say its reference radius: give gravity.reference_radius "
                     "(in the scene's length unit)");
  }
  bool normalized = file.normalized.value_or(false);
  if (g.has("normalized")) {
    const bool given = g.at("normalized").as_bool();
    if (file.normalized && given != *file.normalized)
      throw SceneError(g.at("normalized").here() + who + ": the file says its coefficients are " +
                       (*file.normalized ? "fully normalized" : "unnormalized") + "; omit 'normalized'");
    normalized = given;
  } else if (!file.normalized) {
    throw SceneError(g.here() + who + ": a table does not say its normalization: give gravity.normalized (true: "
                     "fully normalized, geodesy's 4π; false: unnormalized)");
  }
  StokesCoefficients cs = file.coefficients;
  cs.normalized = normalized;
  cs.reference_radius = R;
  int degree = cs.degree;
  if (g.has("degree")) {
    const long d = g.at("degree").as_int();
    if (d < 2 || d > cs.degree)
      throw SceneError(g.at("degree").here() + who + ": degree must be 2.." + std::to_string(cs.degree) +
                       " (the file's), not " + std::to_string(d));
    degree = static_cast<int>(d);
  }
  if (degree < 2)
    throw SceneError(g.at("stokes").here() + who + ": the field has degree " + std::to_string(degree) +
                     "; a rigid body needs degree 2 (its inertia)");
  cs = truncated(cs, degree, normalized);
  FieldBody out;
  if (b.has("mass")) {
    out.mass = b.at("mass").as_double();
  } else if (file.gm) {
    out.mass = *file.gm * units.time_si * units.time_si / std::pow(units.length_si, 3) / G;  // GM / G
  } else {
    throw SceneError(b.here() + who + ": a table gives no GM: give the body's 'mass'");
  }
  if (!std::isfinite(out.mass) || out.mass <= 0.0)
    throw SceneError((b.has("mass") ? b.at("mass") : g).here() + who + ": mass must be positive");
  cs.mass = out.mass;
  // The inertia: the field's degree 2 fixes all but its trace (31.4).
  if (g.has("polar_moment") == b.has("inertia"))
    throw SceneError(g.here() + who + ": give the body's 'inertia' (body frame) or gravity.polar_moment (C/(M R^2) "
                     "about the field's z axis, R the reference radius), " +
                     (b.has("inertia") ? "not both" : "one of them") +
                     ": the field fixes the inertia only up to its trace");
  double trace = 0.0;
  if (g.has("polar_moment")) {
    const double k = g.at("polar_moment").as_double();
    if (!(k > 0.0) || !std::isfinite(k))
      throw SceneError(g.at("polar_moment").here() + who + ": polar_moment must be positive");
    trace = second_moment_trace(cs, k * out.mass * R * R);
  } else {
    trace = 0.5 * inertia(b.at("inertia")).trace();
  }
  out.inertia = inertia_of(field_integrals(truncated(cs, 2, normalized), trace));
  if (b.has("inertia")) {
    const Mat3 J = inertia(b.at("inertia"));
    if ((J - out.inertia).cwiseAbs().maxCoeff() > 1e-6 * J.cwiseAbs().maxCoeff()) {
      std::ostringstream msg;
      msg.precision(10);
      const Eigen::IOFormat f(10, 0, ", ", "; ", "", "", "[", "]");
      msg << b.at("inertia").here() << who << ": 'inertia' " << J.format(f) << " contradicts the field's degree 2, "
          << "which with its trace gives " << out.inertia.format(f)
          << " (body frame, 1e-6 relative); give gravity.polar_moment instead, or an inertia in the field's frame";
      throw SceneError(msg.str());
    }
  }
  validate_inertia(out.inertia, g.here() + who + "'s inertia from its field");
  out.radius = R;
  out.field = std::make_shared<const StokesCoefficients>(std::move(cs));
  return out;
}

// G: as given, or from the declared units (eq. 17.1), or 1. A G that contradicts the declared
// units by more than 1 % is a unit mistake, not a choice of constant.
double scene_gravitational_constant(const Params& root, const Units& units) {
  if (!root.has("G")) return units.declared ? units.gravitational_constant() : 1.0;
  const double G = root.at("G").as_double();
  if (units.declared && std::isfinite(G) && G > 0.0) {
    const double expected = units.gravitational_constant();
    if (std::abs(G - expected) > 0.01 * expected) {
      std::ostringstream msg;
      msg.precision(6);
      msg << root.at("G").here() << "G = " << G << " contradicts the declared units ("
          << units.describe() << "), in which G = " << expected << " " << units.of_G()
          << "; omit G to use that value, or fix 'units'";
      throw SceneError(msg.str());
    }
  }
  return G;
}

// An `orbit:` mapping's osculating elements (a, e, i, Omega, omega, nu | M; angles in degrees)
// for `who` ("body 'moon'", "particle 3"): bound orbits only.
OrbitalElements orbit_elements(const Params& o, const std::string& who) {
  const double deg = M_PI / 180.0;
  OrbitalElements el;
  el.a = o.at("a").as_double();
  el.e = o.get("e", 0.0);
  el.i = o.get("i", 0.0) * deg;
  el.Omega = o.get("Omega", 0.0) * deg;
  el.omega = o.get("omega", 0.0) * deg;
  if (!(std::isfinite(el.a) && el.a > 0.0))
    throw SceneError(o.at("a").here() + "the orbit of " + who + ": 'a' must be positive (bound orbits only; "
                     "give position and velocity for others)");
  if (!(el.e >= 0.0 && el.e < 1.0))
    throw SceneError(o.at("e").here() + "the orbit of " + who + ": 'e' must be in [0, 1) (bound orbits "
                     "only; give position and velocity for others)");
  if (o.has("nu") && o.has("M"))
    throw SceneError(o.here() + "the orbit of " + who + ": give the true anomaly 'nu' or the mean anomaly "
                     "'M' (degrees), not both (neither: M = 0, at periapsis)");
  el.nu = o.has("nu") ? o.at("nu").as_double() * deg : true_from_mean_anomaly(o.get("M", 0.0) * deg, el.e);
  if (!std::isfinite(el.i + el.Omega + el.omega + el.nu))
    throw SceneError(o.here() + "the orbit of " + who + ": angles must be finite numbers (degrees)");
  return el;
}

// Each body's initial position and velocity (docs/user-guide.md, "Initial states"): absolute,
// relative to another body (`relative_to`), or osculating elements about another body
// (`orbit`, eqs. 17.2–17.4, angles in degrees); then, with `barycentric: true`, shifted so
// that the barycentre rests at the origin.
std::pair<std::vector<Vec3>, std::vector<Vec3>> initial_translation(const Params& bodies, const System& sys,
                                                                    bool barycentric) {
  const std::size_t n = sys.size();
  std::vector<Vec3> x(n, Vec3::Zero()), v(n, Vec3::Zero());
  std::vector<int> mark(n, 0);  // 0 open, 1 resolving, 2 done
  std::unordered_map<std::string, std::size_t> index;  // name → body (O(1) per reference)
  for (std::size_t j = 0; j < n; ++j) index.emplace(sys.body(j).name, j);
  auto index_of = [&](const Params& name_node, const std::string& who) {
    const std::string name = name_node.as_string();
    if (const auto found = index.find(name); found != index.end()) return found->second;
    std::string known;
    for (const auto& b : sys.bodies()) known += (known.empty() ? "" : ", ") + b.name;
    throw SceneError(name_node.here() + who + " refers to body '" + name + "', which the scene does not "
                     "have (bodies: " + known + ")");
  };
  // The body whose state body i's is given relative to, if any (keys checked here).
  auto reference_of = [&](std::size_t i) -> std::optional<std::size_t> {
    const Params& b = bodies.items()[i];
    const std::string who = "body '" + sys.body(i).name + "'";
    if (b.has("orbit")) {
      for (const char* key : {"position", "velocity", "relative_to"})
        if (b.has(key))
          throw SceneError(b.at(key).here() + who + ": 'orbit' gives the position and velocity; remove '" +
                           key + "'");
      const Params& o = b.at("orbit");
      o.check_keys({"around", "a", "e", "i", "Omega", "omega", "nu", "M"}, "the orbit of " + who);
      const std::size_t c = index_of(o.at("around"), "the orbit of " + who);
      if (c == i) throw SceneError(o.at("around").here() + who + " cannot orbit itself");
      return c;
    }
    if (!b.has("position"))
      throw SceneError(b.here() + who + " needs 'position' (or 'orbit': osculating elements about another body)");
    if (!b.has("relative_to")) return std::nullopt;
    const std::size_t c = index_of(b.at("relative_to"), who + "'s 'relative_to'");
    if (c == i) throw SceneError(b.at("relative_to").here() + who + " cannot be relative to itself");
    return c;
  };
  // Body i's state once its reference body's (if any) is known.
  auto place = [&](std::size_t i, std::optional<std::size_t> c) {
    const Params& b = bodies.items()[i];
    const std::string who = "body '" + sys.body(i).name + "'";
    if (!b.has("orbit")) {
      x[i] = vec3(b.at("position"));
      if (b.has("velocity")) v[i] = vec3(b.at("velocity"));
      if (c) x[i] += x[*c], v[i] += v[*c];
      return;
    }
    const OrbitalElements el = orbit_elements(b.at("orbit"), who);
    const double mu = sys.G() * (sys.body(i).mass + sys.body(*c).mass);
    const RelativeState rel = state_from_elements(el, mu);  // (17.2)–(17.4)
    x[i] = x[*c] + rel.r;
    v[i] = v[*c] + rel.v;
  };
  // Follow each chain of references up to a placed body (iteratively: a chain may be as long as
  // the scene), then place it from the top down.
  std::vector<std::size_t> chain;
  for (std::size_t i = 0; i < n; ++i) {
    chain.clear();
    for (std::size_t j = i; mark[j] != 2;) {
      if (mark[j] == 1)
        throw SceneError(bodies.items()[j].here() + "body '" + sys.body(j).name + "': its initial state refers, "
                         "through relative_to / orbit.around, back to itself");
      mark[j] = 1;
      chain.push_back(j);
      const auto c = reference_of(j);
      if (!c) break;
      j = *c;
    }
    for (auto k = chain.rbegin(); k != chain.rend(); ++k) {
      place(*k, reference_of(*k));
      mark[*k] = 2;
    }
  }
  if (barycentric) {
    Vec3 mx = Vec3::Zero(), mv = Vec3::Zero();
    double m = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      mx += sys.body(i).mass * x[i];
      mv += sys.body(i).mass * v[i];
      m += sys.body(i).mass;
    }
    for (std::size_t i = 0; i < n; ++i) {
      x[i] -= mx / m;
      v[i] -= mv / m;
    }
  }
  return {x, v};
}

PluginConfig plugin_config(const Params& p, const std::string& what) {
  if (!p.is_map() || !p.has("plugin"))
    throw SceneError(p.here() + "'" + p.path() + "' must be a mapping naming a plugin, e.g. " +
                     what + ": {plugin: NAME}");
  return {p.at("plugin").as_string(), p};
}

// The index of the body a key names, or SceneError naming the key (and the closest name).
std::size_t body_named(const Params& key, const System& system) {
  std::vector<std::string> names;
  for (const auto& b : system.bodies()) names.push_back(b.name);
  const std::string name = key.as_string();
  const auto found = std::find(names.begin(), names.end(), name);
  if (found == names.end()) {
    const std::string near = closest_match(name, names);
    throw SceneError(key.here() + "'" + key.path() + "': no body '" + name + "'" +
                     (near.empty() ? std::string() : "; did you mean '" + near + "'?"));
  }
  return static_cast<std::size_t>(found - names.begin());
}

// The heaviest body other than `body` (the first of equals).
std::size_t heaviest_other(const System& system, std::size_t body) {
  std::size_t heaviest = body == 0 ? 1 : 0;
  for (std::size_t i = 0; i < system.size(); ++i)
    if (i != body && system.body(i).mass > system.body(heaviest).mass) heaviest = i;
  return heaviest;
}

// impulses: [{body, time, delta_v}], each at a time after t0 (docs/user-guide.md "Impulses").
std::vector<Impulse> parse_impulses(const Params& list, const System& system, double t0) {
  const char* form = "'impulses' must be a list of {body: NAME, time: T, delta_v: [x, y, z]} (optionally "
                     "frame: rtn, around: NAME)";
  if (!list.is_sequence()) throw SceneError(list.here() + form);
  std::vector<Impulse> out;
  for (const Params& item : list.items()) {
    if (!item.is_map()) throw SceneError(item.here() + form);
    item.check_keys({"body", "time", "delta_v", "frame", "around"}, "an impulse");
    for (const char* key : {"body", "time", "delta_v"})
      if (!item.has(key)) throw SceneError(item.here() + "'" + item.path() + "' needs '" + key + "': " + form);
    Impulse impulse;
    impulse.body = body_named(item.at("body"), system);
    impulse.time = item.at("time").as_double();
    if (!std::isfinite(impulse.time) || !(impulse.time > t0))
      throw SceneError(item.at("time").here() + "'" + item.at("time").path() + "' must be a time after the start (" +
                       std::to_string(t0) + "); a change of velocity at the start is the body's velocity");
    impulse.delta_v = vec3(item.at("delta_v"));
    if (!impulse.delta_v.allFinite())
      throw SceneError(item.at("delta_v").here() + "'" + item.at("delta_v").path() + "' must be finite");
    const std::string frame = item.get("frame", std::string("inertial"));
    if (frame == "rtn") {
      impulse.frame = Impulse::Frame::rtn;
      if (system.size() < 2)
        throw SceneError(item.at("frame").here() + "'" + item.path() + ".frame: rtn' needs a second body to orbit");
      impulse.around = item.has("around") ? body_named(item.at("around"), system) : heaviest_other(system, impulse.body);
      if (impulse.around == impulse.body)
        throw SceneError(item.at("around").here() + "'" + item.at("around").path() + "': a body cannot orbit itself");
    } else if (frame != "inertial") {
      throw SceneError(item.at("frame").here() + "'" + item.at("frame").path() + "' is '" + frame +
                       "'; it must be inertial (the scene's axes, the default) or rtn (radial, along-track, normal "
                       "of the body's orbit about 'around' at the impulse's time)");
    } else if (item.has("around")) {
      throw SceneError(item.at("around").here() + "'" + item.at("around").path() +
                       "' is used only with frame: rtn (an inertial delta_v needs no orbit)");
    }
    out.push_back(impulse);
  }
  return out;
}

// run.escape: {body, about, distance, unbound}; body defaults to the lightest body, about to
// the heaviest other one.
Escape parse_escape(const Params& e, const System& system) {
  if (!e.is_map()) throw SceneError(e.here() + "'run.escape' must be a mapping: {body: NAME, about: NAME, distance: D, unbound: true}");
  e.check_keys({"body", "about", "distance", "unbound"}, "'run.escape'");
  if (system.size() < 2) throw SceneError(e.here() + "'run.escape' needs two bodies");
  std::size_t lightest = 0;
  for (std::size_t i = 1; i < system.size(); ++i)
    if (system.body(i).mass < system.body(lightest).mass) lightest = i;
  Escape out;
  out.body = e.has("body") ? body_named(e.at("body"), system) : lightest;
  out.about = e.has("about") ? body_named(e.at("about"), system) : heaviest_other(system, out.body);
  if (out.about == out.body)
    throw SceneError(e.here() + "'run.escape': body and about are both '" + system.body(out.body).name + "'");
  out.distance = e.get("distance", 0.0);
  out.unbound = e.get("unbound", false);
  if (!std::isfinite(out.distance) || out.distance < 0.0)
    throw SceneError(e.at("distance").here() + "'run.escape.distance' must be a positive distance");
  if (!(out.distance > 0) && !out.unbound)
    throw SceneError(e.here() + "'run.escape' needs a distance (stop beyond it) or unbound: true (stop when the "
                     "two-body energy turns positive), or both");
  return out;
}

// particles.ejecta: {body, site: [latitude, longitude], count, speed: [min, max], exponent, cone,
// height, seed} (ejecta.hpp; docs/equations.md §39). `index`: the cloud's place in the list, whose
// default seed is index + 1, so that clouds without a seed draw different speeds and azimuths.
EjectaSettings parse_ejecta(const Params& e, const System& sys, std::size_t index) {
  e.check_keys({"body", "site", "count", "speed", "exponent", "cone", "height", "seed"}, "'particles.ejecta'");
  for (const char* key : {"body", "site", "count", "speed"})
    if (!e.has(key))
      throw SceneError(e.here() + "'particles.ejecta' needs '" + key +
                       "' (body, site: [latitude, longitude], count, speed: [min, max])");
  EjectaSettings out;
  out.body = body_named(e.at("body"), sys);
  const std::vector<double> site = e.at("site").as_doubles();
  if (site.size() != 2 || !(std::abs(site[0]) <= 90.0) || !std::isfinite(site[1]))
    throw SceneError(e.at("site").here() + "'particles.ejecta.site' is [latitude, longitude] in degrees, in the body "
                     "frame, latitude in [-90, 90]");
  out.latitude = site[0];
  out.longitude = site[1];
  const long count = e.get("count", 0L);
  if (count < 1 || count > 10000000L)  // 10^7 particles hold ~0.5 GB of states
    throw SceneError(e.at("count").here() + "'particles.ejecta.count' must be 1..10^7");
  out.count = static_cast<std::size_t>(count);
  const std::vector<double> speed = e.at("speed").as_doubles();
  if (speed.size() != 2 || !(speed[0] > 0.0) || !(speed[1] >= speed[0]) || !std::isfinite(speed[1]))
    throw SceneError(e.at("speed").here() + "'particles.ejecta.speed' is [min, max], 0 < min <= max: launch speeds "
                     "relative to the surface");
  out.speed_min = speed[0];
  out.speed_max = speed[1];
  out.exponent = e.get("exponent", out.exponent);
  if (!(out.exponent > 0.0) || !std::isfinite(out.exponent))
    throw SceneError(e.at("exponent").here() + "'particles.ejecta.exponent' (gamma of N(>v) ∝ v^-gamma) must be > 0");
  out.cone = e.get("cone", out.cone);
  if (!(out.cone >= 0.0 && out.cone < 90.0))
    throw SceneError(e.at("cone").here() + "'particles.ejecta.cone' (degrees from the surface's normal) must be in "
                     "[0, 90)");
  out.height = e.get("height", out.height);
  if (!(out.height >= 0.0) || !std::isfinite(out.height))
    throw SceneError(e.at("height").here() + "'particles.ejecta.height' must be a distance ≥ 0");
  const long seed = e.get("seed", static_cast<long>(index) + 1);
  if (seed < 0) throw SceneError(e.at("seed").here() + "'particles.ejecta.seed' must be ≥ 0");
  out.seed = static_cast<std::uint64_t>(seed);
  return out;
}

}  // namespace

// particles: {around, states | file | orbits | ejecta, step, degree, tolerance, escape, record, check}
// (docs/user-guide.md, "Particles"): each source adds particles, in the order states, file, orbits,
// ejecta.
ParticleSettings parse_particles(const Params& p, const System& sys, const State& initial,
                                 const std::filesystem::path& folder) {
  p.check_keys({"around", "states", "file", "orbits", "ejecta", "step", "degree", "tolerance", "escape", "record",
                "check"},
               "'particles'");
  ParticleSettings out;
  Vec3 x0 = Vec3::Zero(), v0 = Vec3::Zero();
  if (p.has("around")) {
    const std::size_t c = body_named(p.at("around"), sys);
    out.around = c;
    x0 = initial.x.col(static_cast<Eigen::Index>(c));
    v0 = initial.p.col(static_cast<Eigen::Index>(c)) / sys.body(c).mass;
  }
  auto add = [&](const std::vector<double>& z, const std::string& where) {
    if (z.size() != 6 || !std::all_of(z.begin(), z.end(), [](double u) { return std::isfinite(u); }))
      throw SceneError(where + "a particle's state is six finite numbers: x, y, z, vx, vy, vz");
    out.position.push_back(x0 + Vec3(z[0], z[1], z[2]));
    out.velocity.push_back(v0 + Vec3(z[3], z[4], z[5]));
  };
  if (p.has("states")) {
    const Params& list = p.at("states");
    if (!list.is_sequence()) throw SceneError(list.here() + "'particles.states' must be a list of [x, y, z, vx, vy, vz]");
    for (const Params& z : list.items()) add(z.as_doubles(), z.here());
  }
  if (p.has("file")) {  // six numbers a line (commas or blanks); '#' starts a comment
    const std::filesystem::path path = scene_file(p.at("file"), folder, "'particles'", "file of particle states");
    std::ifstream in(path);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream fields(line);
      std::vector<double> z;
      std::string word;
      const std::string where = path.string() + ":" + std::to_string(number) + ": ";
      while (fields >> word) {
        char* end = nullptr;
        const double u = std::strtod(word.c_str(), &end);
        if (*end != '\0') throw SceneError(where + "'" + word + "' is not a number");
        z.push_back(u);
      }
      if (!z.empty()) add(z, where);
    }
  }
  if (p.has("orbits")) {  // osculating elements about `around` (17.2)–(17.4), angles in degrees
    if (!out.around) throw SceneError(p.at("orbits").here() + "'particles.orbits' needs 'particles.around': the body they orbit");
    const double mu = sys.G() * sys.body(*out.around).mass;
    for (const Params& o : p.at("orbits").items()) {
      o.check_keys({"a", "e", "i", "Omega", "omega", "nu", "M"}, "a particle's orbit");
      const RelativeState rel = state_from_elements(orbit_elements(o, "particle " + std::to_string(out.position.size())), mu);
      add({rel.r.x(), rel.r.y(), rel.r.z(), rel.v.x(), rel.v.y(), rel.v.z()}, o.here());
    }
  }
  if (p.has("ejecta")) {  // a cloud thrown from a surface, or a list of them (39.1)–(39.2)
    const Params& list = p.at("ejecta");
    const auto clouds = list.is_sequence() ? list.items() : std::vector<Params>{list};
    for (std::size_t k = 0; k < clouds.size(); ++k) {
      const EjectaSettings cloud = parse_ejecta(clouds[k], sys, k);
      try {
        launch_ejecta(cloud, sys, initial, out.position, out.velocity);
      } catch (const SceneError& error) {  // a body without a surface, named with the scene's line
        throw SceneError(clouds[k].at("body").here() + error.what());
      }
    }
  }
  if (out.empty())
    throw SceneError(p.here() + "'particles' gives no particle: list 'states', a 'file', 'orbits' or 'ejecta'");
  out.step = p.get("step", 0.0);
  out.degree = static_cast<int>(p.get("degree", 16L));
  out.tolerance = p.get("tolerance", out.tolerance);
  out.escape = p.get("escape", 0.0);
  const long record = p.get("record", 100L);
  if (record < 0) throw SceneError(p.at("record").here() + "'particles.record' must be a count ≥ 0");
  out.record = std::min(static_cast<std::size_t>(record), out.position.size());
  const long check = p.get("check", 32L);
  if (check < 0) throw SceneError(p.at("check").here() + "'particles.check' must be a count ≥ 0 (0: no check)");
  out.check = std::min(static_cast<std::size_t>(check), out.position.size());
  if (!(out.step > 0.0 && std::isfinite(out.step)) && p.has("step"))
    throw SceneError(p.at("step").here() + "'particles.step' must be a positive time (the particles' longest Verlet step)");
  if (out.degree < 0 || out.degree > multi_index::kMaxDegree)
    throw SceneError(p.at("degree").here() + "'particles.degree' must be 0.." + std::to_string(multi_index::kMaxDegree));
  if (!(out.tolerance > 0.0 && out.tolerance < 1.0))
    throw SceneError(p.at("tolerance").here() + "'particles.tolerance' must be in (0, 1)");
  if (!(out.escape >= 0.0) || !std::isfinite(out.escape))
    throw SceneError(p.at("escape").here() + "'particles.escape' must be a distance ≥ 0 (0: never)");
  return out;
}

Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::string>& overrides) {
  Scene scene;
  scene.file = file;
  scene.text = text;
  scene.overrides = overrides;
  Params root = parse_yaml(text, file);
  if (!root.is_map()) throw SceneError(file + ": a scene must be a YAML mapping (G, bodies, ...)");
  for (const auto& o : overrides) apply_override(root, o);
  root.set_path("");
  root.check_keys({"description", "units", "G", "bodies", "potential", "forces", "integrator", "run", "barycentric", "impulses",
                   "particles"},
                  "the scene");
  if (root.has("units")) scene.units = parse_units(root.at("units"));
  const double G = scene_gravitational_constant(root, scene.units);

  // Bodies: constants into System, initial values into State.
  const Params& bodies = root.at("bodies");
  if (!bodies.is_sequence() || bodies.size() == 0)
    throw SceneError(bodies.here() + "'bodies' must be a non-empty list of bodies");
  std::vector<Body> list;
  for (const auto& b : bodies.items()) {
    if (!b.is_map()) throw SceneError(b.here() + "each body must be a mapping");
    b.check_keys({"name", "mass", "density", "inertia", "position", "velocity", "relative_to", "orbit",
                  "attitude", "angular_velocity", "angular_momentum", "shape", "radius", "gravity"},
                 "body '" + b.get("name", std::string("?")) + "'");
    Body body;
    body.name = b.at("name").as_string();
    if (const std::string why = System::name_problem(body.name); !why.empty())  // with the line
      throw SceneError(b.at("name").here() + "body " + std::to_string(list.size()) + " is named '" + body.name +
                       "': " + why);
    if (b.has("shape")) {
      const Params& shape = b.at("shape");
      if (!shape.is_map() || shape.size() != 1)
        throw SceneError(shape.here() + "body '" + body.name + "': 'shape' must name one of "
                         "ellipsoid, polyhedron, dumbbell or spheres");
      shape.check_keys({"ellipsoid", "polyhedron", "dumbbell", "spheres"}, "the shape of body '" + body.name + "'");
      if (shape.has("ellipsoid") || shape.has("polyhedron"))
        body.solid = scale_solid(*parse_solid(shape, body.name, std::filesystem::path(file).parent_path(),
                                              scene.units),
                                 b, body.name);
    }
    FieldBody field;
    if (b.has("gravity")) {
      field = parse_field_body(b, body.name, std::filesystem::path(file).parent_path(), scene.units, G);
      body.field = field.field;
      body.radius = field.radius;
    }
    if (b.has("radius")) {
      if (body.solid)
        throw SceneError(b.at("radius").here() + "body '" + body.name + "': 'radius' comes from "
                         "the shape (" + std::to_string(body.solid->radius) + "); remove it");
      body.radius = b.at("radius").as_double();
      if (!std::isfinite(body.radius) || body.radius < 0.0)
        throw SceneError(b.at("radius").here() + "body '" + body.name +
                         "': radius must be non-negative");
    }
    if (body.solid) body.radius = body.solid->radius;
    if (b.has("density") && !body.solid)
      throw SceneError(b.at("density").here() + "body '" + body.name + "': 'density' needs a "
                       "shape (ellipsoid or polyhedron)");
    body.mass = body.solid ? body.solid->mass : body.field ? field.mass : b.at("mass").as_double();
    if (!std::isfinite(body.mass) || body.mass <= 0.0)
      throw SceneError(b.at("mass").here() + "body '" + body.name + "': mass must be positive, not " +
                       b.at("mass").as_string());
    body.rigid = b.has("inertia") || body.solid || body.field;
    if (body.solid) {
      body.inertia = body.solid->inertia;
    } else if (body.field) {
      body.inertia = field.inertia;
    } else if (body.rigid) {
      body.inertia = inertia(b.at("inertia"));
      validate_inertia(body.inertia, b.at("inertia").here() + "body '" + body.name + "'");
    }
    if (b.has("shape")) body.shape = b.at("shape");
    if (!body.rigid)
      for (const char* key : {"attitude", "angular_velocity", "angular_momentum"})
        if (b.has(key))
          throw SceneError(b.at(key).here() + "body '" + body.name + "' has no 'inertia', so it" +
                           " is a point mass and cannot have '" + key +
                           "'; add 'inertia' to make it a rigid body");
    if (b.has("angular_velocity") && b.has("angular_momentum"))
      throw SceneError(b.here() + "body '" + body.name +
                       "': give 'angular_velocity' or 'angular_momentum', not both");
    list.push_back(std::move(body));
  }
  try {
    scene.system = System(G, std::move(list));  // validates what is left: G, unique names
  } catch (const SceneError& e) {
    throw SceneError((root.has("G") ? root.at("G").here() : bodies.here()) + e.what());
  }

  const System& sys = scene.system;
  State s = State::zeros(sys);
  const auto [positions, velocities] = initial_translation(bodies, sys, root.get("barycentric", false));
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Params& b = bodies.items()[i];
    const Body& body = sys.body(i);
    const auto col = static_cast<Eigen::Index>(i);
    s.x.col(col) = positions[i];
    s.p.col(col) = body.mass * velocities[i];
    if (const int k = sys.rigid_index(i); k >= 0) {
      if (b.has("attitude")) s.R[static_cast<std::size_t>(k)] = attitude(b.at("attitude"), body.name);
      if (b.has("angular_velocity"))
        s.Pi.col(k) = body.inertia * vec3(b.at("angular_velocity"));  // Π = J Ω
      if (b.has("angular_momentum")) s.Pi.col(k) = vec3(b.at("angular_momentum"));
    }
  }
  {  // coincident bodies: equal positions are neighbours in lexicographic order (O(N log N))
    std::vector<std::size_t> order(sys.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    auto key = [&](std::size_t i) {
      const auto c = s.x.col(static_cast<Eigen::Index>(i));
      return std::array<double, 3>{c.x(), c.y(), c.z()};
    };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
    for (std::size_t k = 1; k < order.size(); ++k) {
      const std::size_t i = std::min(order[k - 1], order[k]), j = std::max(order[k - 1], order[k]);
      if (key(i) == key(j))
        throw SceneError(bodies.items()[j].here() + "bodies '" + sys.body(i).name + "' and '" +
                         sys.body(j).name + "' start at the same position");
    }
  }
  scene.initial = std::move(s);

  // Models, integrator, run.
  const Params& potential = root.at("potential");
  if (potential.is_sequence()) {
    for (const auto& item : potential.items())
      scene.potentials.push_back(plugin_config(item, "potential"));
    if (scene.potentials.empty())
      throw SceneError(potential.here() + "'potential' must name at least one plugin");
  } else {
    scene.potentials.push_back(plugin_config(potential, "potential"));
  }
  if (root.has("forces")) {  // forces beyond the potential (docs/forces.md): a list, or one mapping
    const Params& forces = root.at("forces");
    if (forces.is_sequence())
      for (const auto& item : forces.items()) scene.forces.push_back(plugin_config(item, "forces"));
    else
      scene.forces.push_back(plugin_config(forces, "forces"));
  }
  if (!scene.forces.empty())  // what the forces put in since t0 (docs/equations.md eq. 33.3)
    scene.initial.force_balance = Eigen::MatrixXd::Zero(kBalanceRows, static_cast<Eigen::Index>(scene.forces.size()));
  scene.integrator = plugin_config(root.at("integrator"), "integrator");
  if (root.has("impulses")) scene.impulses = parse_impulses(root.at("impulses"), scene.system, scene.initial.t);
  if (root.has("particles"))
    scene.particles = parse_particles(root.at("particles"), scene.system, scene.initial,
                                      std::filesystem::path(file).parent_path());
  const Params& run = root.at("run");
  run.check_keys({"t_end", "output_every", "close_approach", "collisions", "escape", "trust", "stm", "sensitivities",
                  "chaos"},
                 "'run'");
  if (run.has("escape")) scene.run.escape = parse_escape(run.at("escape"), scene.system);
  if (run.has("trust")) {
    const Params& trust = run.at("trust");
    trust.check_keys({"energy", "momentum", "orthogonality", "position", "particle_fates"}, "'run.trust'");
    TrustThresholds& t = scene.run.trust;
    for (auto [key, value] : {std::pair<const char*, double*>{"energy", &t.energy}, {"momentum", &t.momentum},
                              {"orthogonality", &t.orthogonality}, {"position", &t.position},
                              {"particle_fates", &t.particle_fates}}) {
      *value = trust.get(key, *value);
      if (!(*value > 0.0))
        throw SceneError(trust.at(key).here() + "'run.trust." + key + "' must be a positive number");
    }
  }
  scene.run.close_approach = run.get("close_approach", 0.0);
  scene.run.collisions = run.get("collisions", true);
  scene.run.stm = run.get("stm", false);
  scene.run.chaos = run.get("chaos", false);
  if (run.has("sensitivities")) {  // keys, checked against the bodies where the run starts
    const Params& keys = run.at("sensitivities");
    if (keys.is_scalar() && !keys.as_string().empty()) {
      scene.run.sensitivities.push_back(keys.as_string());
    } else if (keys.is_sequence()) {
      for (const Params& key : keys.items()) {
        if (!key.is_scalar() || key.as_string().empty())
          throw SceneError(key.here() + "'run.sensitivities' must list keys such as bodies.moon.velocity");
        scene.run.sensitivities.push_back(key.as_string());
      }
    } else if (!keys.is_scalar()) {
      throw SceneError(keys.here() + "'run.sensitivities' must list keys such as bodies.moon.velocity");
    }
  }
  if (!std::isfinite(scene.run.close_approach) || scene.run.close_approach < 0.0)
    throw SceneError(run.at("close_approach").here() + "'run.close_approach' must be non-negative");
  scene.run.t_end = run.at("t_end").as_double();
  scene.run.output_every = run.at("output_every").as_double();
  if (scene.run.t_end <= 0.0)
    throw SceneError(run.at("t_end").here() + "'run.t_end' must be positive");
  if (scene.run.output_every <= 0.0 || scene.run.output_every > scene.run.t_end)
    throw SceneError(run.at("output_every").here() +
                     "'run.output_every' must be positive and at most run.t_end");
  // A body inside another's shape: impossible, unless the scene turned contacts off (then the
  // verdict says so). O(N²) pairs: small scenes.
  if (scene.run.collisions && sys.size() <= 64)
    for (const Watch& w : watches(sys, Events{0.0, true, {}})) {
      const double gap = w.samples ? w.gap(sys, scene.initial) : 0.0;
      if (gap < -1e-9 * w.threshold) {
        const auto separation = (scene.initial.x.col(static_cast<Eigen::Index>(w.a)) -
                                 scene.initial.x.col(static_cast<Eigen::Index>(w.b))).norm();
        std::ostringstream msg;
        msg.precision(4);
        msg << bodies.items()[w.b].here() << "bodies '" << sys.body(w.a).name << "' and '" << sys.body(w.b).name
            << "' overlap at the start: " << -gap << " inside each other's surface (centres " << separation
            << " apart); move them apart";
        throw SceneError(msg.str());
      }
    }
  scene.root = std::move(root);
  return scene;
}

}  // namespace noether
