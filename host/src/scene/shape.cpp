// A body's solid shape: an ellipsoid or a polyhedron read from its file, at the body's density
// (scene_sections.hpp; docs/user-guide.md "Shapes").
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"

#include <noether/error.hpp>
#include <noether/mesh.hpp>
#include <noether/pds3_label.hpp>
#include <noether/pds_plate_model.hpp>

#include <cmath>
#include <sstream>

namespace noether::detail {

std::shared_ptr<const Solid> parse_solid(const Params& shape, const std::string& body,
                                         const std::filesystem::path& folder, const Units& scene_units) {
  const std::string who = "body '" + body + "'";
  if (shape.has("ellipsoid")) {
    const Params& e = shape.at("ellipsoid");
    scene_section("bodies[].shape.ellipsoid").check(e, "the ellipsoid of " + who);
    const Vec3 axes = vec3(e.at("semi_axes"));
    if (!axes.allFinite() || axes.minCoeff() <= 0.0)
      throw SceneError(e.at("semi_axes").here() + who + ": ellipsoid semi-axes must be positive");
    return make_ellipsoid(axes, 1.0);
  }
  const Params& p = shape.at("polyhedron");
  const SceneSection& keys = scene_section("bodies[].shape.polyhedron");
  keys.check(p, "the polyhedron of " + who);
  auto resolve = [&](const Params& f) { return scene_file(f, folder, who, "shape file"); };
  if (p.has("file") == (p.has("vertices") || p.has("facets")))
    throw SceneError(p.here() + who + ": give either 'file' (Wavefront OBJ, or a PDS3 plate model's label) or "
                     "'vertices' and 'facets' (CSV pair)");
  // A PDS3 plate model says its unit and is in its archive's body-fixed frame; an OBJ or CSV file
  // says neither.
  const std::filesystem::path pds = p.has("file") ? pds3_label_of(resolve(p.at("file"))) : std::filesystem::path();
  double file_unit = 0.0;
  if (p.has("units")) {
    const std::string units = p.at("units").as_string();
    file_unit = length_unit_in_metres(units);
    if (file_unit == 0.0)
      throw SceneError(p.at("units").here() + who + ": unknown units '" + units + "'; use m, km or au");
  } else if (pds.empty()) {
    throw SceneError(p.here() + who + ": give the shape file's 'units' (m, km or au): an OBJ or CSV file does not say "
                     "them");
  }
  // Into the scene's length unit; metres when the scene declares none.
  const double scale = file_unit / scene_units.length_si;
  const std::string frame = p.has("frame") ? keys.text(p, "frame") : pds.empty() ? "principal" : "mesh";
  if (frame != "principal" && frame != "mesh")
    throw SceneError(p.at("frame").here() + who + ": frame must be 'principal' (rotate the "
                     "mesh onto its principal axes) or 'mesh' (keep its axes), not '" + frame + "'");
  Mesh mesh;
  const std::filesystem::path first = resolve(p.at(p.has("file") ? "file" : "vertices"));
  const std::filesystem::path facets = p.has("file") ? std::filesystem::path() : resolve(p.at("facets"));
  std::shared_ptr<const Solid> solid;
  try {
    if (!pds.empty()) {
      PdsPlateModel model = read_pds_plate_model(pds, 1.0 / scene_units.length_si);
      if (p.has("units") && std::abs(file_unit - model.unit_in_metres) > 1e-12 * model.unit_in_metres)
        throw SceneError(p.at("units").here() + who + ": units '" + p.at("units").as_string() + "' contradict " +
                         pds.string() + ", whose vertices are in " + std::to_string(model.unit_in_metres) +
                         " m; omit 'units'");
      mesh = std::move(model.mesh);
    } else {
      mesh = p.has("file") ? read_obj(first, scale) : read_vertex_facet_csv(first, facets, scale);
    }
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

}  // namespace noether::detail
