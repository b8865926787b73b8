// noether view: a run's output file → one self-contained HTML page (docs/visualisation.md).
// The page is viewer/page.html with three.js, the viewer's script and the run's data put in
// place of its markers; the data are the run's frames (decimated to ViewOptions::max_frames),
// attitudes as quaternions and each body's shape, read from the file alone (a cluster's points
// and a point mass's radius come from the scene the file records).
#include <noether/error.hpp>
#include <noether/scene.hpp>
#include <noether/view.hpp>

#include "h5_helpers.hpp"
#include "io/h5_handle.hpp"
#include "io/run_record.hpp"
#include "json_text.hpp"
#include "view_assets.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <sstream>

namespace noether {

namespace {

using detail::json_number;
using io::H5Handle;
using h5::read_string;

// JSON text that is safe inside a <script> element: no "</script>" or "<!--" can appear.
std::string script_safe(std::string json) {
  std::string out;
  out.reserve(json.size());
  for (char c : json) {
    if (c == '<') out += "\\u003c";
    else out += c;
  }
  return out;
}

std::string json_string(const std::string& s) { return script_safe(detail::json_string(s)); }

// Raw little-endian bytes as base64 (RFC 4648), for typed arrays in the page.
std::string base64(const void* data, std::size_t bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes; i += 3) {
    const std::uint32_t v = (p[i] << 16) | (p[i + 1] << 8) | p[i + 2];
    out += digits[v >> 18], out += digits[(v >> 12) & 63], out += digits[(v >> 6) & 63], out += digits[v & 63];
  }
  if (i + 1 == bytes) {
    const std::uint32_t v = p[i] << 16;
    out += digits[v >> 18], out += digits[(v >> 12) & 63], out += "==";
  } else if (i + 2 == bytes) {
    const std::uint32_t v = (p[i] << 16) | (p[i + 1] << 8);
    out += digits[v >> 18], out += digits[(v >> 12) & 63], out += digits[(v >> 6) & 63], out += '=';
  }
  return out;
}

template <class T>
std::string typed_array(const std::vector<T>& values) {
  std::string text = "\"";
  text += base64(values.data(), values.size() * sizeof(T));
  return text += '"';
}

// A numeric attribute as doubles; empty when absent.
std::vector<double> double_attribute(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) return {};
  const H5Handle a(H5Aopen(object, name, H5P_DEFAULT));
  const H5Handle space(H5Aget_space(a));
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<double> out(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  if (!out.empty() && H5Aread(a, H5T_NATIVE_DOUBLE, out.data()) < 0) return {};
  return out;
}

std::vector<int> int_attribute(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) return {};
  const H5Handle a(H5Aopen(object, name, H5P_DEFAULT));
  const H5Handle space(H5Aget_space(a));
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<int> out(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  if (!out.empty() && H5Aread(a, H5T_NATIVE_INT, out.data()) < 0) return {};
  return out;
}

// A whole dataset as `T` (its dimensions in `dims`).
template <class T>
std::vector<T> read_dataset(hid_t location, const char* path, hid_t mem_type, std::vector<hsize_t>& dims) {
  const H5Handle d = io::open_dataset(location, path);
  if (!d.valid()) return {};
  const H5Handle space(H5Dget_space(d));
  dims.assign(static_cast<std::size_t>(std::max(H5Sget_simple_extent_ndims(space), 0)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<T> out(n);
  if (n > 0 && H5Dread(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw OutputError(std::string("cannot read ") + path);
  return out;
}

bool is_ensemble_file(const std::filesystem::path& file) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  return f.valid() && H5Lexists(f, "outcome", H5P_DEFAULT) > 0 && H5Lexists(f, "frames_complete", H5P_DEFAULT) <= 0;
}

// The shape of one body as the page's JSON: {"kind": …, …} in the file's length unit.
struct BodyShape {
  std::string json;
  double size = 0;  // a length that bounds the body (0: a dot)
};

BodyShape solid_shape(hid_t shapes, const std::string& name) {
  const H5Handle g(H5Gopen2(shapes, name.c_str(), H5P_DEFAULT));
  if (!g.valid()) throw OutputError("/parameters/shapes/" + name + " does not open");
  const std::string kind = read_string(g, "kind", false);
  if (kind == "ellipsoid") {
    const auto a = double_attribute(g, "semi_axes");
    if (a.size() != 3) throw OutputError("/parameters/shapes/" + name + " has no semi_axes");
    return {"{\"kind\":\"ellipsoid\",\"semi_axes\":[" + json_number(a[0]) + "," + json_number(a[1]) + "," +
                json_number(a[2]) + "]}",
            *std::max_element(a.begin(), a.end())};
  }
  std::vector<hsize_t> vdims, fdims;
  const auto vertices = read_dataset<double>(g, "vertices", H5T_NATIVE_DOUBLE, vdims);
  const auto faces = read_dataset<std::uint32_t>(g, "faces", H5T_NATIVE_UINT32, fdims);
  if (vdims.size() != 2 || vdims[1] != 3 || fdims.size() != 2 || fdims[1] != 3 || faces.empty())
    throw OutputError("/parameters/shapes/" + name + " holds no mesh (vertices [n][3], faces [m][3])");
  for (const auto f : faces)
    if (f >= vdims[0]) throw OutputError("/parameters/shapes/" + name + "/faces names a vertex it does not have");
  double size = 0;
  for (std::size_t i = 0; i < vertices.size(); i += 3)
    size = std::max(size, std::sqrt(vertices[i] * vertices[i] + vertices[i + 1] * vertices[i + 1] +
                                    vertices[i + 2] * vertices[i + 2]));
  const std::vector<float> v32(vertices.begin(), vertices.end());
  return {"{\"kind\":\"polyhedron\",\"vertices\":" + typed_array(v32) + ",\"faces\":" + typed_array(faces) + "}", size};
}

// A rigid body known as point masses fixed in its frame (the sphere-cluster potential's
// dumbbell or spheres), from the scene's `shape`; nullopt when it is not one.
std::optional<BodyShape> cluster_shape(const Body& body) {
  if (!body.shape.is_map()) return std::nullopt;
  std::vector<Vec3> points;
  std::vector<double> masses;
  if (body.shape.has("dumbbell")) {  // as sphere_cluster.cpp: m/2 at ±(l/2) e1
    const double l = body.shape.at("dumbbell").at("length").as_double();
    points = {Vec3(0.5 * l, 0, 0), Vec3(-0.5 * l, 0, 0)};
    masses = {0.5 * body.mass, 0.5 * body.mass};
  } else if (body.shape.has("spheres")) {
    for (const auto& s : body.shape.at("spheres").items()) {
      const auto p = s.at("position").as_doubles();
      if (p.size() == 3) points.emplace_back(p[0], p[1], p[2]), masses.push_back(s.at("mass").as_double());
    }
  }
  if (points.empty()) return std::nullopt;
  double extent = 0;
  for (const auto& p : points) extent = std::max(extent, p.norm());
  // Drawn as spheres whose volumes go as their masses, the largest a fifth of the cluster's
  // extent (the potential's spheres are points: their radius is not part of the model).
  const double m_max = *std::max_element(masses.begin(), masses.end());
  std::string json = "{\"kind\":\"spheres\",\"centres\":[";
  for (std::size_t i = 0; i < points.size(); ++i)
    json += (i ? "," : "") + ("[" + json_number(points[i].x()) + "," + json_number(points[i].y()) + "," +
                              json_number(points[i].z()) + "]");
  json += "],\"radii\":[";
  for (std::size_t i = 0; i < masses.size(); ++i)
    json += (i ? "," : "") + json_number(0.2 * extent * std::cbrt(masses[i] / m_max));
  return BodyShape{json + "]}", 1.2 * extent};
}

// The uniform ellipsoid of the same mass and inertia (J = m/5 diag(b²+c², a²+c², a²+b²) in its
// principal frame), for a rigid body whose shape the file does not give.
BodyShape inertia_ellipsoid(const Mat3& J, double mass) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
  const Vec3 I = eig.eigenvalues();
  const double trace = I.sum();
  Vec3 a;
  for (int k = 0; k < 3; ++k) a(k) = std::sqrt(std::max(0.0, 2.5 / mass * (trace - 2 * I(k))));
  const Eigen::Quaterniond q(eig.eigenvectors().determinant() > 0 ? eig.eigenvectors() : Mat3(-eig.eigenvectors()));
  std::ostringstream s;
  s.precision(17);
  s << "{\"kind\":\"ellipsoid\",\"semi_axes\":[" << a(0) << "," << a(1) << "," << a(2) << "],\"rotation\":[" << q.x()
    << "," << q.y() << "," << q.z() << "," << q.w() << "],\"inferred\":true}";
  return {s.str(), a.maxCoeff()};
}

// Checks `params` ("key=value&…") against the page's parameters and the run's bodies.
void check_params(const std::string& params, const std::vector<std::string>& names, const std::vector<int>& rigid_of_body) {
  static const std::vector<std::string> keys{"frame", "t", "view", "camera", "target", "up", "fov", "trails",
                                             "trail", "labels", "axes", "hud", "size", "flat", "play"};
  std::size_t start = 0;
  while (start <= params.size() && !params.empty()) {
    const std::size_t end = std::min(params.find('&', start), params.size());
    const std::string item = params.substr(start, end - start);
    const std::size_t eq = item.find('=');
    const std::string key = item.substr(0, eq), value = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      std::string known;
      for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k;
      throw SceneError("the view's parameter '" + key + "' is not one the page knows (" + known + ")");
    }
    if (key == "view" && value != "inertial" && value != "barycentric") {
      const std::size_t colon = value.find(':');
      const std::string kind = value.substr(0, colon), body = colon == std::string::npos ? "" : value.substr(colon + 1);
      const auto at = std::find(names.begin(), names.end(), body);
      if ((kind != "centre" && kind != "frame") || at == names.end())
        throw SceneError("view=" + value + ": give inertial, barycentric, centre:BODY or frame:BODY with a body of the run");
      if (kind == "frame" && rigid_of_body[static_cast<std::size_t>(at - names.begin())] < 0)
        throw SceneError("view=" + value + ": '" + body + "' is a point mass, which has no body frame; centre:" + body +
                         " follows it without turning");
    }
    start = end + 1;
  }
}

}  // namespace

bool view_available() { return view_assets::available(); }

std::string view_html(const std::filesystem::path& run_file, const ViewOptions& options, ViewReport* report) {
  if (!view_assets::available())
    throw Error("this noether was built without three.js, which `noether view` embeds in its pages: install "
                "Debian's libjs-three (tools/install-deps.sh does) and build noether again");
  if (options.max_frames < 2) throw SceneError("a view needs at least 2 frames (--max-frames)");
  std::error_code ec;
  if (std::filesystem::exists(run_file, ec) && is_ensemble_file(run_file))
    throw OutputError(run_file.string() +
                      " is an ensemble's file: it holds each sample's inputs and end state, not its trajectory. "
                      "Write the first K samples' runs with `noether ensemble … --trajectories K` and view "
                      "those (" + run_file.stem().string() + "-sample-I.h5)");
  const io::RunRecord run(run_file);
  ViewReport local;
  ViewReport& out = report ? *report : local;
  out = ViewReport{};
  const auto frames = static_cast<std::size_t>(run.frames);
  out.frames_in_file = frames;
  if (run.outcome.empty())
    out.notes.push_back("the run has no /work: it was killed or is still running; its " + std::to_string(frames) +
                        " complete frames are shown");

  // Frames shown: evenly spaced by index, first and last included (docs/visualisation.md, "Size").
  std::vector<std::uint32_t> shown;
  if (frames <= options.max_frames) {
    for (std::size_t k = 0; k < frames; ++k) shown.push_back(static_cast<std::uint32_t>(k));
  } else {
    for (std::size_t i = 0; i < options.max_frames; ++i)
      shown.push_back(static_cast<std::uint32_t>(
          std::llround(static_cast<double>(i) * static_cast<double>(frames - 1) / static_cast<double>(options.max_frames - 1))));
    out.notes.push_back("decimated: " + std::to_string(options.max_frames) + " of the file's " +
                        std::to_string(frames) + " frames, evenly spaced (--max-frames)");
  }
  out.frames_shown = shown.size();

  const auto names = run.body_names();
  const auto masses = run.body_masses();
  const std::size_t n = run.bodies;

  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const H5Handle file(H5Fopen(run_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.valid()) throw OutputError(run_file.string() + " does not open");
  const H5Handle parameters(H5Gopen2(file, "parameters", H5P_DEFAULT));
  std::vector<int> body_of_rigid;
  if (run.rigid > 0) {
    const H5Handle orientation(H5Oopen(file, "particles/bodies/orientation", H5P_DEFAULT));
    if (orientation.valid()) body_of_rigid = int_attribute(orientation, "body_index");
    if (body_of_rigid.size() != run.rigid)
      throw OutputError(run_file.string() + ": /particles/bodies/orientation has no body_index for its " +
                        std::to_string(run.rigid) + " rigid bodies");
  }
  std::vector<int> rigid_of_body(n, -1);
  for (std::size_t k = 0; k < body_of_rigid.size(); ++k) {
    if (body_of_rigid[k] < 0 || static_cast<std::size_t>(body_of_rigid[k]) >= n)
      throw OutputError(run_file.string() + ": /particles/bodies/orientation's body_index names no body");
    rigid_of_body[static_cast<std::size_t>(body_of_rigid[k])] = static_cast<int>(k);
  }
  check_params(options.params, names, rigid_of_body);

  // Positions (float64: a body's metres must survive heliocentric distances) and attitudes
  // (float32 quaternions x, y, z, w, as three.js orders them) of the frames shown.
  std::vector<double> t, x;
  std::vector<float> q;
  t.reserve(shown.size());
  x.reserve(shown.size() * n * 3);
  q.reserve(shown.size() * run.rigid * 4);
  std::size_t next = 0;
  run.read(0, frames, [&](std::size_t k, const io::RecordedFrame& f) {
    while (next < shown.size() && shown[next] == k) {  // a frame may be shown twice (max_frames > frames is not)
      t.push_back(f.state.t);
      for (std::size_t j = 0; j < n; ++j)
        for (int c = 0; c < 3; ++c) x.push_back(f.state.x(c, static_cast<Eigen::Index>(j)));
      for (const auto& R : f.state.R) {
        const Eigen::Quaterniond qq(R);
        q.insert(q.end(), {static_cast<float>(qq.x()), static_cast<float>(qq.y()), static_cast<float>(qq.z()),
                           static_cast<float>(qq.w())});
      }
      ++next;
    }
  });

  // Shapes: a solid's from /parameters/shapes, a field's reference sphere from
  // /parameters/fields, a cluster's points and a point mass's radius from the recorded scene.
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
  std::vector<std::string> shape_json(n);
  double largest_body = 0;
  for (std::size_t j = 0; j < n; ++j) {
    BodyShape s;
    if (shapes.valid() && H5Lexists(shapes, names[j].c_str(), H5P_DEFAULT) > 0) {
      s = solid_shape(shapes, names[j]);
    } else if (fields.valid() && H5Lexists(fields, names[j].c_str(), H5P_DEFAULT) > 0) {
      const H5Handle g(H5Gopen2(fields, names[j].c_str(), H5P_DEFAULT));
      const auto r = double_attribute(g, "reference_radius");
      s.size = r.empty() ? 0 : r[0];
      s.json = "{\"kind\":\"field\",\"radius\":" + json_number(s.size) + "}";
    } else if (const Scene* sc = recorded_scene()) {
      const Body& b = sc->system.body(j);
      if (auto c = cluster_shape(b)) {
        s = *c;
      } else if (b.rigid) {
        s = inertia_ellipsoid(b.inertia, b.mass);
      } else if (b.radius > 0) {
        s = {"{\"kind\":\"sphere\",\"radius\":" + json_number(b.radius) + "}", b.radius};
      } else {
        s = {"{\"kind\":\"point\"}", 0};
      }
    } else if (rigid_of_body[j] >= 0) {
      std::vector<hsize_t> dims;
      const auto J = read_dataset<double>(file, "particles/bodies/inertia", H5T_NATIVE_DOUBLE, dims);
      const auto k = static_cast<std::size_t>(rigid_of_body[j]);
      if (J.size() < 9 * (k + 1)) throw OutputError(run_file.string() + ": /particles/bodies/inertia is missing");
      s = inertia_ellipsoid(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(J.data() + 9 * k), masses[j]);
      out.notes.push_back("body '" + names[j] + "' is drawn as the ellipsoid of its mass and inertia: the scene the file records does not read here (" +
                          scene_problem + ")");
    } else {
      s = {"{\"kind\":\"point\"}", 0};
    }
    shape_json[j] = s.json;
    largest_body = std::max(largest_body, s.size);
  }

  std::string unit_length = "L", unit_time = "T";
  if (parameters.valid()) {
    if (H5Aexists(parameters, "unit_length") > 0) unit_length = read_string(parameters, "unit_length", false);
    if (H5Aexists(parameters, "unit_time") > 0) unit_time = read_string(parameters, "unit_time", false);
  }

  // The page's data (viewer.js reads it as NOETHER_RUN).
  std::string data = "{\"title\":" + json_string(options.title.empty() ? run_file.filename().string() : options.title);
  data += ",\"file\":" + json_string(run_file.filename().string()) + ",\"params\":" + json_string(options.params);
  data += ",\"unit_length\":" + json_string(unit_length) + ",\"unit_time\":" + json_string(unit_time);
  data += ",\"frames_in_file\":" + std::to_string(frames) + ",\"bodies\":[";
  for (std::size_t j = 0; j < n; ++j) {
    data += (j ? "," : "") + ("{\"name\":" + json_string(names[j]) + ",\"mass\":" + json_number(masses[j]) +
                              ",\"rigid\":" + std::to_string(rigid_of_body[j]) + ",\"shape\":" + shape_json[j] + "}");
  }
  data += "],\"largest_body\":" + json_number(largest_body);
  data += ",\"frame_index\":" + typed_array(shown) + ",\"t\":" + typed_array(t) + ",\"x\":" + typed_array(x) +
          ",\"q\":" + typed_array(q) + ",\"notes\":[";
  for (std::size_t i = 0; i < out.notes.size(); ++i) data += (i ? "," : "") + json_string(out.notes[i]);
  data += "]}";
  return view_assets::page(data);
}

}  // namespace noether
