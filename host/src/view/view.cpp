// noether view: a run's output file → one self-contained HTML page (docs/visualisation.md).
// The page is viewer/page.html with three.js, the viewer's script and the run's data put in
// place of its markers; the data are the run's frames (decimated to ViewOptions::max_frames),
// attitudes as quaternions and each body's shape, as picture_frames.hpp reads them.
#include <noether/ensemble.hpp>
#include <noether/error.hpp>
#include <noether/view.hpp>

#include "io/safe_publish.hpp"
#include "io/json_text.hpp"
#include "view/picture_frames.hpp"
#include "view/view_assets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace noether {

namespace {

using detail::json_number;

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

// A shape as the page's JSON: {"kind": …, …} in the file's length unit (viewer.js, bodyObject).
std::string shape_json(const detail::PictureShape& s) {
  using Kind = detail::PictureShape::Kind;
  std::string json = "{\"kind\":\"";
  json += s.name();
  json += '"';
  const auto key = [&json](const char* name) { (json += ",\"") += name, json += "\":"; };
  const auto numbers = [&json](std::initializer_list<double> values) {
    json += '[';
    for (const double v : values) (json += json_number(v)) += ',';
    json.back() = ']';
  };
  switch (s.kind) {
    case Kind::point: break;
    case Kind::sphere:
    case Kind::field: key("radius"), json += json_number(s.radius); break;
    case Kind::ellipsoid:
      key("semi_axes"), numbers({s.semi_axes.x(), s.semi_axes.y(), s.semi_axes.z()});
      key("rotation"), numbers({s.axes.x(), s.axes.y(), s.axes.z(), s.axes.w()});
      if (s.inferred) key("inferred"), json += "true";
      break;
    case Kind::polyhedron: {
      const std::vector<float> vertices(s.mesh.vertices.data(), s.mesh.vertices.data() + s.mesh.vertices.size());
      std::vector<std::uint32_t> faces;
      for (const auto& f : s.mesh.faces)
        for (const int v : f) faces.push_back(static_cast<std::uint32_t>(v));
      key("vertices"), json += typed_array(vertices);
      key("faces"), json += typed_array(faces);
      break;
    }
    case Kind::spheres:
      key("centres"), json += '[';
      for (const auto& c : s.centres) numbers({c.x(), c.y(), c.z()}), json += ',';
      json.back() = ']';
      key("radii"), json += '[';
      for (const double r : s.radii) (json += json_number(r)) += ',';
      json.back() = ']';
      break;
  }
  return json += '}';
}

// Checks `params` ("key=value&…") against the page's parameters and the run's bodies.
void check_params(const std::string& params, const std::vector<std::string>& names, const std::vector<int>& rigid_of_body) {
  static const std::vector<std::string> keys{"frame", "t", "view", "camera", "target", "up", "fov", "trails",
                                             "trail", "labels", "axes", "hud", "size", "flat", "play",
                                             "particles"};
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

// An ensemble's sample runs, as ViewOptions::samples picks them.
std::vector<std::filesystem::path> sample_runs(const std::filesystem::path& ensemble, const std::vector<std::size_t>& samples) {
  namespace fs = std::filesystem;
  const auto sample = [&ensemble](std::size_t i) { return sample_run_path(ensemble, i); };
  std::vector<fs::path> runs;
  std::error_code ec;
  if (samples.empty()) {
    for (std::size_t i = 0; i < 8 && fs::exists(sample(i), ec); ++i) runs.push_back(sample(i));
  } else {
    for (const std::size_t i : samples) {
      if (!fs::exists(sample(i), ec))
        throw OutputError(sample(i).string() + " does not exist: `noether ensemble … --trajectories K -o " +
                          ensemble.filename().string() + "` writes the runs of samples 0 to K − 1");
      runs.push_back(sample(i));
    }
  }
  if (runs.empty())
    throw OutputError(ensemble.string() + " is an ensemble's file and no sample's run is beside it (" +
                      sample(0).filename().string() + " …): write them with `noether ensemble … --trajectories K`");
  return runs;
}

// A run's positions (float64: a body's metres must survive heliocentric distances) and attitudes
// (float32 quaternions x, y, z, w, as three.js orders them) at its frames kept.
void frame_arrays(const detail::PictureFrames& run, std::vector<double>& x, std::vector<float>& q) {
  for (std::size_t i = 0; i < run.t.size(); ++i) {
    x.insert(x.end(), run.x[i].data(), run.x[i].data() + run.x[i].size());
    for (const auto& R : run.R[i]) {
      const Eigen::Quaterniond qq(R);
      q.insert(q.end(), {static_cast<float>(qq.x()), static_cast<float>(qq.y()), static_cast<float>(qq.z()),
                         static_cast<float>(qq.w())});
    }
  }
}

}  // namespace

bool view_available() { return view_assets::available(); }

std::string view_html(const std::filesystem::path& run_file, const ViewOptions& options, ViewReport* report) {
  return view_html(std::vector<std::filesystem::path>{run_file}, options, report);
}

std::string view_html(const std::vector<std::filesystem::path>& given, const ViewOptions& options, ViewReport* report) {
  if (!view_assets::available())
    throw Error("this noether was built without three.js, which `noether view` embeds in its pages: install "
                "Debian's libjs-three (tools/install-deps.sh does) and build noether again");
  if (given.empty()) throw SceneError("no run to view");
  std::vector<std::filesystem::path> files = given;
  std::string title = options.title;
  std::error_code ec;
  if (given.size() == 1 && std::filesystem::exists(given[0], ec) && detail::is_ensemble_file(given[0])) {
    files = sample_runs(given[0], options.samples);
    if (title.empty()) {
      title = given[0].filename().string() + ", samples ";
      for (const auto& f : files) {
        const std::string stem = f.stem().string();
        (title += stem.substr(stem.rfind('-') + 1)) += f == files.back() ? "" : ", ";
      }
    }
  } else if (!options.samples.empty()) {
    throw SceneError("--samples picks an ensemble's sample runs; " + given[0].string() + " is not an ensemble's file");
  }
  const detail::PictureFrames run = detail::read_picture_frames(files[0], options.max_frames);
  check_params(options.params, run.names, run.rigid_of_body);
  ViewReport local;
  ViewReport& out = report ? *report : local;
  out = ViewReport{run.frames_in_file, run.shown.size(), files, 0, run.notes};
  const std::size_t n = run.names.size();
  std::vector<double> x;
  std::vector<float> q;
  frame_arrays(run, x, q);

  // The other runs at the first's frames: the same bodies, the same times.
  std::string others = "[";
  for (std::size_t r = 1; r < files.size(); ++r) {
    const detail::PictureFrames other = detail::read_picture_frames(files[r], options.max_frames, &run.shown);
    if (other.names != run.names)
      throw OutputError(files[r].string() + " is a run of other bodies than " + files[0].string() + "'s");
    for (std::size_t i = 0; i < other.t.size(); ++i)
      if (std::abs(other.t[i] - run.t[i]) > 1e-12 * std::max(1.0, std::abs(run.t[i])))
        throw OutputError(files[r].string() + "'s frame " + std::to_string(other.shown[i]) + " is at t = " +
                          detail::exact_text(other.t[i]) + ", " + files[0].string() + "'s at " +
                          detail::exact_text(run.t[i]) + ": runs shown together need the same frame times");
    if (other.t.size() < run.t.size())
      out.notes.push_back(files[r].filename().string() + " ends at t = " + detail::exact_text(other.t.back()) +
                          " (" + std::to_string(other.frames_in_file) + " frames): not drawn after it");
    out.notes.insert(out.notes.end(), other.notes.begin(), other.notes.end());  // a killed run's
    std::vector<double> ox;
    std::vector<float> oq;
    frame_arrays(other, ox, oq);
    if (others.size() > 1) others += ',';
    ((others += "{\"label\":") += json_string(files[r].filename().string())) += ",\"frames\":";
    ((others += std::to_string(other.t.size())) += ",\"x\":") += typed_array(ox);
    ((others += ",\"q\":") += typed_array(oq)) += '}';
  }
  others += ']';

  double largest_body = 0;
  for (const auto& s : run.shapes) largest_body = std::max(largest_body, s.size);

  // The page's data (viewer.js reads it as NOETHER_RUN), built by appending (GCC 12 warns
  // falsely about "literal" + std::string&&).
  std::string data = "{";
  const auto field = [&data](const char* name, const std::string& value) {
    if (data.size() > 1) data += ',';
    ((data += '"') += name) += "\":";
    data += value;
  };
  if (title.empty()) {
    title = files[0].filename().string();
    if (files.size() > 1) title += " and " + std::to_string(files.size() - 1) + " more";
  }
  field("title", json_string(title));
  field("file", json_string(files[0].filename().string()));
  field("params", json_string(options.params));
  field("unit_length", json_string(run.unit_length));
  field("unit_time", json_string(run.unit_time));
  field("frames_in_file", std::to_string(run.frames_in_file));
  std::string bodies = "[";
  for (std::size_t j = 0; j < n; ++j) {
    ((bodies += "{\"name\":") += json_string(run.names[j])) += ",\"mass\":";
    ((bodies += json_number(run.masses[j])) += ",\"rigid\":") += std::to_string(run.rigid_of_body[j]);
    ((bodies += ",\"shape\":") += shape_json(run.shapes[j])) += j + 1 < n ? "}," : "}";
  }
  field("bodies", bodies += "]");
  field("largest_body", json_number(largest_body));
  field("frame_index", typed_array(run.shown));
  field("t", typed_array(run.t));
  field("x", typed_array(x));
  field("q", typed_array(q));
  field("others", others);
  field("particles", std::to_string(run.particles));
  if (run.particles > 0) field("particle_x", typed_array(run.particle_x));
  std::string impulses = "[";
  for (const auto& impulse : run.impulses) {
    if (impulses.size() > 1) impulses += ',';
    ((((impulses += "{\"t\":") += json_number(impulse.t)) += ",\"body\":") += json_string(impulse.body)) += '}';
  }
  field("impulses", impulses += "]");
  std::string notes = "[";
  for (const auto& note : out.notes) (notes += json_string(note)) += ',';
  if (notes.size() > 1) notes.pop_back();
  field("notes", notes += "]");
  data += '}';
  return view_assets::page(data);
}

ViewReport write_view(const std::vector<std::filesystem::path>& runs, const std::filesystem::path& page,
                      const ViewOptions& options, bool force) {
  ViewReport report;
  const std::string html = view_html(runs, options, &report);
  std::vector<std::filesystem::path> inputs = runs;
  inputs.insert(inputs.end(), report.runs.begin(), report.runs.end());
  io::write_whole_file(page, html, force, inputs);
  report.bytes = html.size();
  return report;
}

}  // namespace noether
