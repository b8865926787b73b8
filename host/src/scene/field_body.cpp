// A body given by its gravity field (scene_sections.hpp; docs/user-guide.md "Gravity fields").
#include "scene/portable_random.hpp"
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"

#include <noether/error.hpp>
#include <noether/stokes_file.hpp>

#include <cmath>
#include <numbers>
#include <sstream>

namespace noether::detail {

FieldBody parse_field_body(const Params& b, const std::string& body, const std::filesystem::path& folder,
                           const Units& units, double G) {
  const std::string who = "body '" + body + "'";
  const Params& g = b.at("gravity");
  if (!g.is_map() || !g.has("stokes"))
    throw SceneError(g.here() + who + ": 'gravity' needs 'stokes: FILE' (an ICGEM .gfc file, a PDS3 label .lbl "
                     "and its table, a PDS SHADR .tab table or a table of n m C S)");
  scene_section("bodies[].gravity").check(g, "the gravity field of " + who);
  for (const char* key : {"shape", "density"})
    if (b.has(key))
      throw SceneError(b.at(key).here() + who + " is given by its gravity field; it cannot have a '" + key +
                       "' as well");
  const std::filesystem::path path = scene_file(g.at("stokes"), folder, who, "gravity-field file");
  const std::string format = g.has("format") ? g.at("format").as_string() : stokes_format_of(path);
  if (format.empty())
    throw SceneError(g.at("stokes").here() + who + ": say the field file's 'format' (icgem, pds, shadr or table); "
                     "its name does not tell (.gfc is icgem, .lbl pds, .tab shadr or, with its label beside it, pds)");
  if (format != "icgem" && format != "shadr" && format != "table" && format != "pds")
    throw SceneError((g.has("format") ? g.at("format") : g.at("stokes")).here() + who +
                     ": unknown gravity-field format '" + format +
                     "'; use icgem (.gfc), pds (a PDS3 label .lbl), shadr (PDS .tab) or table (n m C S)");
  StokesFile file;
  try {
    file = read_stokes_file(path, format);
  } catch (const SceneError& e) {
    throw SceneError(g.at("stokes").here() + who + ": " + e.what());
  }
  FieldBody out;
  for (const std::string& defect : file.defects) out.notes.push_back(who + ": " + defect);
  // The reference radius, GM and normalization are the file's; the scene may repeat them, or
  // override an archived file's defect (NLR393V3's label prints 1600 m for 16 km), said in the
  // warnings; a table's come from the scene.
  if (file.gm && !units.declared)
    throw SceneError(g.here() + who + ": the " + format + " file gives GM in m^3/s^2 and its reference radius in "
                     "m; declare the scene's units ('units: SI', or {length: km, ...}) so they can be converted");
  double R = file.reference_radius ? *file.reference_radius / units.length_si : 0.0;
  if (g.has("reference_radius")) {
    const double given = g.at("reference_radius").as_double();
    if (!(given > 0.0) || !std::isfinite(given))
      throw SceneError(g.at("reference_radius").here() + who + ": the reference radius must be positive");
    if (file.reference_radius && std::abs(given - R) > 1e-9 * R) {
      std::ostringstream note;
      note.precision(10);
      note << who << ": gravity.reference_radius " << given << " overrides the file's " << R
           << " (the scene's length unit); the coefficients are taken about the scene's";
      out.notes.push_back(note.str());
    }
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
  // A draw from the file's 1σ: C + σ z, z independent standard normals from (seed, coefficient),
  // the same on every platform (portable_random.hpp) — the published uncertainty sampled (the 1σ
  // columns, not a covariance: correlations between coefficients are not drawn).
  if (g.has("draw")) {
    const long draw = g.at("draw").as_int();
    if (draw < 0) throw SceneError(g.at("draw").here() + who + ": draw must be 0 (as published) or a positive seed");
    if (draw > 0 && file.sigma_C.empty())
      throw SceneError(g.at("draw").here() + who + ": " + g.at("stokes").as_string() +
                       " gives no uncertainties of its coefficients to draw from");
    if (draw > 0)
      for (std::size_t k = 0; k < cs.C.size(); ++k)
        for (int part = 0; part < 2; ++part) {
          const double sigma = part == 0 ? file.sigma_C[k] : file.sigma_S[k];
          if (!(sigma > 0.0)) continue;
          const auto seed = static_cast<std::uint64_t>(draw), stream = static_cast<std::uint64_t>(2 * part);
          const double u1 = uniform01(seed, k, stream), u2 = uniform01(seed, k, stream + 1);
          const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);  // Box–Muller
          (part == 0 ? cs.C[k] : cs.S[k]) += sigma * z;
        }
  }
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
  // A reference radius far from any body of this mass's size: less than half the radius of a
  // sphere of it at 8000 kg/m³ (iron; the expansion's sphere would lie inside the body), or more
  // than ten times one at 500 kg/m³ (a units slip, or NLR393V3's label's "1600m" for 16 km).
  if (units.declared) {
    const double mass_kg = out.mass * units.mass_si, R_m = R * units.length_si;
    const double dense = std::cbrt(3 * mass_kg / (4 * std::numbers::pi * 8000.0)), light = std::cbrt(3 * mass_kg / (4 * std::numbers::pi * 500.0));
    if (R_m < 0.5 * dense || R_m > 10 * light) {
      std::ostringstream note;
      note.precision(4);
      note << who << ": the field's reference radius " << R_m << " m is " << (R_m < 0.5 * dense ? "less than half" : "more than ten times")
           << " the radius of a sphere of its mass at " << (R_m < 0.5 * dense ? "8000" : "500") << " kg/m^3 ("
           << (R_m < 0.5 * dense ? dense : light) << " m): a unit slipped? (give gravity.reference_radius to override "
           << "the file's)";
      out.notes.push_back(note.str());
    }
  }
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

}  // namespace noether::detail
