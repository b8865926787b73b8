// A run's frames and shapes for a picture (picture_frames.hpp): the frames through RunRecord
// (checksums verified), a solid's shape from /parameters/shapes, a field's reference sphere from
// /parameters/fields, a cluster's points and a point mass's radius from the recorded scene.
#include "view/picture_frames.hpp"

#include <noether/error.hpp>
#include <noether/scene.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include "io/h5.hpp"
#include "io/h5.hpp"
#include "io/run_record.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

namespace noether::detail {

namespace {

using io::H5Handle;
using Kind = PictureShape::Kind;

// A numeric attribute as `T`; empty when absent or unreadable.
template <class T>
std::vector<T> attribute(hid_t object, const char* name, hid_t type) {
  if (H5Aexists(object, name) <= 0) return {};
  const H5Handle a(H5Aopen(object, name, H5P_DEFAULT));
  const H5Handle space(H5Aget_space(a));
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<T> out(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  if (!out.empty() && H5Aread(a, type, out.data()) < 0) return {};
  return out;
}

// A whole dataset as `T` (its dimensions in `dims`); empty when absent.
template <class T>
std::vector<T> dataset(hid_t location, const char* path, hid_t type, std::vector<hsize_t>& dims) {
  const H5Handle d = io::open_dataset(location, path);
  if (!d.valid()) return {};
  const H5Handle space(H5Dget_space(d));
  dims.assign(static_cast<std::size_t>(std::max(H5Sget_simple_extent_ndims(space), 0)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<T> out(n);
  if (n > 0 && H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw OutputError(std::string("cannot read ") + path);
  return out;
}

}  // namespace

bool is_ensemble_file(const std::filesystem::path& file) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  return f.valid() && H5Lexists(f, "outcome", H5P_DEFAULT) > 0 && H5Lexists(f, "frames_complete", H5P_DEFAULT) <= 0;
}

namespace {

PictureShape solid_shape(hid_t shapes, const std::string& name) {
  const std::string where = "/parameters/shapes/" + name;
  const H5Handle g(H5Gopen2(shapes, name.c_str(), H5P_DEFAULT));
  if (!g.valid()) throw OutputError(where + " does not open");
  PictureShape s;
  if (io::read_string(g, "kind", false) == "ellipsoid") {
    const auto a = attribute<double>(g, "semi_axes", H5T_NATIVE_DOUBLE);
    if (a.size() != 3) throw OutputError(where + " has no semi_axes");
    s.kind = Kind::ellipsoid;
    s.semi_axes = Vec3(a[0], a[1], a[2]);
    s.size = s.semi_axes.maxCoeff();
    return s;
  }
  std::vector<hsize_t> vdims, fdims;
  const auto vertices = dataset<double>(g, "vertices", H5T_NATIVE_DOUBLE, vdims);
  const auto faces = dataset<std::uint32_t>(g, "faces", H5T_NATIVE_UINT32, fdims);
  if (vdims.size() != 2 || vdims[1] != 3 || fdims.size() != 2 || fdims[1] != 3 || faces.empty())
    throw OutputError(where + " holds no mesh (vertices [n][3], faces [m][3])");
  s.kind = Kind::polyhedron;
  s.mesh.vertices = Eigen::Map<const Eigen::Matrix3Xd>(vertices.data(), 3, static_cast<Eigen::Index>(vdims[0]));
  for (std::size_t i = 0; i < faces.size(); i += 3) {
    if (std::max({faces[i], faces[i + 1], faces[i + 2]}) >= vdims[0])
      throw OutputError(where + "/faces names a vertex it does not have");
    s.mesh.faces.push_back({static_cast<int>(faces[i]), static_cast<int>(faces[i + 1]), static_cast<int>(faces[i + 2])});
  }
  s.size = s.mesh.vertices.colwise().norm().maxCoeff();
  return s;
}

// A rigid body known as point masses fixed in its frame (the sphere-cluster potential's dumbbell
// or spheres), from the scene's `shape`: drawn as spheres whose volumes go as their masses, the
// largest of radius a fifth of the cluster's extent (the model's points have no radius).
std::optional<PictureShape> cluster_shape(const Body& body) {
  if (!body.shape.is_map()) return std::nullopt;
  PictureShape s;
  s.kind = Kind::spheres;
  std::vector<double> masses;
  if (body.shape.has("dumbbell")) {  // as sphere_cluster.cpp: m/2 at ±(l/2) e1
    const double l = body.shape.at("dumbbell").at("length").as_double();
    s.centres = {Vec3(0.5 * l, 0, 0), Vec3(-0.5 * l, 0, 0)};
    masses = {0.5 * body.mass, 0.5 * body.mass};
  } else if (body.shape.has("spheres")) {
    for (const auto& p : body.shape.at("spheres").items()) {
      const auto c = p.at("position").as_doubles();
      if (c.size() == 3) s.centres.emplace_back(c[0], c[1], c[2]), masses.push_back(p.at("mass").as_double());
    }
  }
  if (s.centres.empty()) return std::nullopt;
  double extent = 0;
  for (const auto& c : s.centres) extent = std::max(extent, c.norm());
  const double m_max = *std::max_element(masses.begin(), masses.end());
  for (const double m : masses) s.radii.push_back(0.2 * extent * std::cbrt(m / m_max));
  s.size = 1.2 * extent;
  return s;
}

// The uniform ellipsoid of the same mass and inertia (J = m/5 diag(b²+c², a²+c², a²+b²) in its
// principal frame), for a rigid body whose shape the file does not give.
PictureShape inertia_ellipsoid(const Mat3& J, double mass) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
  const Vec3 I = eig.eigenvalues();
  PictureShape s;
  s.kind = Kind::ellipsoid;
  s.inferred = true;
  for (int k = 0; k < 3; ++k) s.semi_axes(k) = std::sqrt(std::max(0.0, 2.5 / mass * (I.sum() - 2 * I(k))));
  s.axes = Eigen::Quaterniond(eig.eigenvectors().determinant() > 0 ? eig.eigenvectors() : Mat3(-eig.eigenvectors()));
  s.size = s.semi_axes.maxCoeff();
  return s;
}

}  // namespace

const char* PictureShape::name() const {
  switch (kind) {
    case Kind::point: return "point";
    case Kind::sphere: return "sphere";
    case Kind::field: return "field";
    case Kind::ellipsoid: return "ellipsoid";
    case Kind::polyhedron: return "polyhedron";
    case Kind::spheres: return "spheres";
  }
  return "point";
}

PictureFrames read_picture_frames(const std::filesystem::path& file, std::size_t max_frames,
                                  const std::vector<std::uint32_t>* frames_wanted) {
  if (max_frames < 2) throw SceneError("a picture of a run needs at least 2 frames (--max-frames)");
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && is_ensemble_file(file))
    throw OutputError(file.string() +
                      " is an ensemble's file: it holds each sample's inputs and end state, not its trajectory. "
                      "Write the first K samples' runs with `noether ensemble … --trajectories K` and use "
                      "those (" + file.stem().string() + "-sample-I.h5)");
  const io::RunRecord run(file);
  PictureFrames out;
  const auto frames = static_cast<std::size_t>(run.frames);
  out.frames_in_file = frames;
  if (run.outcome.empty())
    out.notes.push_back(file.filename().string() + " has no /work: the run was killed or is still running; its " +
                        std::to_string(frames) + " complete frames are shown");

  // The frames kept: those asked for that the file has, or evenly spaced by index, the first and
  // the last among them.
  if (frames_wanted) {
    for (const auto k : *frames_wanted)
      if (k < frames) out.shown.push_back(k);
  } else if (frames <= max_frames) {
    for (std::size_t k = 0; k < frames; ++k) out.shown.push_back(static_cast<std::uint32_t>(k));
  } else {
    for (std::size_t i = 0; i < max_frames; ++i)
      out.shown.push_back(static_cast<std::uint32_t>(std::llround(
          static_cast<double>(i) * static_cast<double>(frames - 1) / static_cast<double>(max_frames - 1))));
    out.notes.push_back("decimated: " + std::to_string(max_frames) + " of the file's " + std::to_string(frames) +
                        " frames, evenly spaced (--max-frames)");
  }

  out.names = run.body_names();
  out.masses = run.body_masses();
  const std::size_t n = run.bodies;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const H5Handle h5(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!h5.valid()) throw OutputError(file.string() + " does not open");
  const H5Handle parameters(H5Gopen2(h5, "parameters", H5P_DEFAULT));
  std::vector<int> body_of_rigid;
  if (run.rigid > 0) {
    const H5Handle orientation(H5Oopen(h5, "particles/bodies/orientation", H5P_DEFAULT));
    if (orientation.valid()) body_of_rigid = attribute<int>(orientation, "body_index", H5T_NATIVE_INT);
    if (body_of_rigid.size() != run.rigid)
      throw OutputError(file.string() + ": /particles/bodies/orientation has no body_index for its " +
                        std::to_string(run.rigid) + " rigid bodies");
  }
  out.rigid_of_body.assign(n, -1);
  for (std::size_t k = 0; k < body_of_rigid.size(); ++k) {
    if (body_of_rigid[k] < 0 || static_cast<std::size_t>(body_of_rigid[k]) >= n)
      throw OutputError(file.string() + ": /particles/bodies/orientation's body_index names no body");
    out.rigid_of_body[static_cast<std::size_t>(body_of_rigid[k])] = static_cast<int>(k);
  }

  std::size_t next = 0;
  run.read(0, frames, [&](std::size_t k, const io::RecordedFrame& f) {
    for (; next < out.shown.size() && out.shown[next] == k; ++next) {
      out.t.push_back(f.state.t);
      out.x.push_back(f.state.x);
      out.R.push_back(f.state.R);
      const std::span<const double> particles = f.series_named("particle_positions");
      if (next == 0) out.particles = particles.size() / 3;
      if (particles.size() != 3 * out.particles)
        throw OutputError(file.string() + ": frame " + std::to_string(k) + " holds " +
                          std::to_string(particles.size() / 3) + " recorded particles, frame " +
                          std::to_string(out.shown[0]) + " " + std::to_string(out.particles));
      out.particle_x.insert(out.particle_x.end(), particles.begin(), particles.end());
    }
  });

  const H5Handle shapes(H5Lexists(parameters, "shapes", H5P_DEFAULT) > 0 ? H5Gopen2(parameters, "shapes", H5P_DEFAULT) : -1);
  const H5Handle fields(H5Lexists(parameters, "fields", H5P_DEFAULT) > 0 ? H5Gopen2(parameters, "fields", H5P_DEFAULT) : -1);
  std::optional<Scene> scene;
  std::string scene_problem;
  const auto recorded_scene = [&]() -> const Scene* {
    if (!scene && scene_problem.empty()) {
      try {
        scene = parse_scene(run.scene_text, run.scene_path, run.overrides);
        if (scene->system.size() != n) scene.reset(), scene_problem = "its bodies are not the file's";
      } catch (const Error& e) {
        scene_problem = e.what();
      }
    }
    return scene ? &*scene : nullptr;
  };
  for (std::size_t j = 0; j < n; ++j) {
    const std::string& name = out.names[j];
    PictureShape s;
    if (shapes.valid() && H5Lexists(shapes, name.c_str(), H5P_DEFAULT) > 0) {
      s = solid_shape(shapes, name);
    } else if (fields.valid() && H5Lexists(fields, name.c_str(), H5P_DEFAULT) > 0) {
      const H5Handle g(H5Gopen2(fields, name.c_str(), H5P_DEFAULT));
      const auto r = attribute<double>(g, "reference_radius", H5T_NATIVE_DOUBLE);
      s.kind = Kind::field;
      s.radius = s.size = r.empty() ? 0.0 : r[0];
    } else if (const Scene* sc = recorded_scene()) {
      const Body& b = sc->system.body(j);
      if (auto c = cluster_shape(b)) {
        s = *c;
      } else if (b.rigid) {
        s = inertia_ellipsoid(b.inertia, b.mass);
      } else if (b.radius > 0) {
        s.kind = Kind::sphere;
        s.radius = s.size = b.radius;
      }
    } else if (out.rigid_of_body[j] >= 0) {
      std::vector<hsize_t> dims;
      const auto J = dataset<double>(h5, "particles/bodies/inertia", H5T_NATIVE_DOUBLE, dims);
      const auto k = static_cast<std::size_t>(out.rigid_of_body[j]);
      if (J.size() < 9 * (k + 1)) throw OutputError(file.string() + ": /particles/bodies/inertia is missing");
      s = inertia_ellipsoid(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(J.data() + 9 * k), out.masses[j]);
      out.notes.push_back("body '" + name + "' is drawn as the ellipsoid of its mass and inertia: the scene the file "
                          "records does not read here (" + scene_problem + ")");
    }
    out.shapes.push_back(std::move(s));
  }

  // The impulses, from the scene as run (its --set applied): times and bodies only.
  if (parameters.valid()) {
    const std::string as_run = io::read_string(parameters, "scene_as_run", true);
    try {
      const Params root = as_run.empty() ? Params() : parse_params(as_run, file.string() + ":/parameters/scene_as_run");
      if (root.is_map() && root.has("impulses"))
        for (const Params& impulse : root.at("impulses").items())
          out.impulses.push_back({impulse.at("time").as_double(), impulse.at("body").as_string()});
    } catch (const Error& e) {
      out.impulses.clear();
      out.notes.push_back(std::string("the run's impulses are not marked: its scene does not read here (") + e.what() +
                          ")");
    }
    if (H5Aexists(parameters, "unit_length") > 0) out.unit_length = io::read_string(parameters, "unit_length", false);
    if (H5Aexists(parameters, "unit_time") > 0) out.unit_time = io::read_string(parameters, "unit_time", false);
  }
  return out;
}

Mesh picture_surface(const PictureShape& shape, int level) {
  switch (shape.kind) {
    case Kind::point: return {};
    case Kind::polyhedron: return shape.mesh;
    case Kind::sphere:
    case Kind::field: return tessellated_ellipsoid(Vec3::Constant(shape.radius), level);
    case Kind::ellipsoid: {
      Mesh m = tessellated_ellipsoid(shape.semi_axes, level);
      m.vertices = shape.axes.toRotationMatrix() * m.vertices;
      return m;
    }
    case Kind::spheres: {
      Mesh all;
      for (std::size_t i = 0; i < shape.centres.size(); ++i) {
        const Mesh m = tessellated_ellipsoid(Vec3::Constant(shape.radii[i]), level);
        const auto offset = static_cast<int>(all.vertices.cols());
        all.vertices.conservativeResize(3, offset + m.vertices.cols());
        all.vertices.rightCols(m.vertices.cols()) = m.vertices.colwise() + shape.centres[i];
        for (const auto& f : m.faces) all.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
      }
      return all;
    }
  }
  return {};
}

}  // namespace noether::detail
