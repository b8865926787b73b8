// noether export --format vtk: ParaView's time series — a .pvd collection naming one VTK XML
// unstructured grid (.vtu, "appended" raw binary data, UInt64 block headers) per frame. The
// layout follows VTK's file-format description ("VTK File Formats", XML formats: Collection,
// UnstructuredGrid, AppendedData).
#include <noether/error.hpp>
#include <noether/export.hpp>

#include "io/safe_publish.hpp"
#include "io/json_text.hpp"
#include "view/picture_frames.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace noether {

namespace {

namespace fs = std::filesystem;
using detail::PictureFrames;

// One frame's grid: every body's surface (triangles), point masses as vertices.
class FrameGrid {
 public:
  FrameGrid(const PictureFrames& run, const std::vector<Mesh>& surfaces, std::size_t i) {
    const std::size_t n = run.names.size();
    for (std::size_t j = 0; j < n; ++j) {
      const Vec3 x = run.x[i].col(static_cast<Eigen::Index>(j));
      const Mat3 R = run.rigid_of_body[j] < 0 ? Mat3::Identity() : run.R[i][static_cast<std::size_t>(run.rigid_of_body[j])];
      const auto first = static_cast<std::int32_t>(points_.size() / 3);
      const Mesh& m = surfaces[j];
      if (m.faces.empty()) {  // a point: one vertex cell
        add_point(x, static_cast<std::int32_t>(j));
        connectivity_.push_back(first);
        types_.push_back(1);  // VTK_VERTEX
      } else {
        for (Eigen::Index v = 0; v < m.vertices.cols(); ++v) add_point(x + R * m.vertices.col(v), static_cast<std::int32_t>(j));
        for (const auto& f : m.faces) {
          for (const int v : f) connectivity_.push_back(first + v);
          types_.push_back(5);  // VTK_TRIANGLE
        }
      }
      for (std::size_t c = cell_body_.size(); c < types_.size(); ++c) {
        cell_body_.push_back(static_cast<std::int32_t>(j));
        offsets_.push_back(static_cast<std::int32_t>(offsets_.empty() ? 0 : offsets_.back()) + (types_[c] == 1 ? 1 : 3));
      }
    }
    time_ = run.t[i];
  }

  // The .vtu file's text: the XML header with each array's offset into the appended block, then
  // the block (each array as its byte count, UInt64, and its bytes).
  std::string text(const std::string& comment) const {
    std::string block;
    std::ostringstream xml;
    const auto array = [&block](const std::string& attributes, const void* data, std::size_t bytes) {
      std::ostringstream a;
      a << "<DataArray " << attributes << " format=\"appended\" offset=\"" << block.size() << "\"/>";
      const std::uint64_t size = bytes;
      block.append(reinterpret_cast<const char*>(&size), sizeof size);
      block.append(static_cast<const char*>(data), bytes);
      return a.str();
    };
    const std::size_t points = points_.size() / 3, cells = types_.size();
    xml << "<?xml version=\"1.0\"?>\n<!-- " << comment << " -->\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        << "  <UnstructuredGrid>\n    <FieldData>\n      "
        << array("type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\"", &time_, sizeof time_)
        << "\n    </FieldData>\n    <Piece NumberOfPoints=\"" << points << "\" NumberOfCells=\"" << cells << "\">\n"
        << "      <PointData Scalars=\"body\">\n        "
        << array("type=\"Int32\" Name=\"body\"", point_body_.data(), point_body_.size() * 4)
        << "\n      </PointData>\n      <CellData Scalars=\"body\">\n        "
        << array("type=\"Int32\" Name=\"body\"", cell_body_.data(), cell_body_.size() * 4)
        << "\n      </CellData>\n      <Points>\n        "
        << array("type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", points_.data(), points_.size() * 8)
        << "\n      </Points>\n      <Cells>\n        "
        << array("type=\"Int32\" Name=\"connectivity\"", connectivity_.data(), connectivity_.size() * 4) << "\n        "
        << array("type=\"Int32\" Name=\"offsets\"", offsets_.data(), offsets_.size() * 4) << "\n        "
        << array("type=\"UInt8\" Name=\"types\"", types_.data(), types_.size())
        << "\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
    return xml.str() + block + "\n  </AppendedData>\n</VTKFile>\n";
  }

 private:
  void add_point(const Vec3& p, std::int32_t body) {
    points_.insert(points_.end(), {p.x(), p.y(), p.z()});
    point_body_.push_back(body);
  }
  std::vector<double> points_;
  std::vector<std::int32_t> point_body_, cell_body_, connectivity_, offsets_;
  std::vector<std::uint8_t> types_;
  double time_ = 0.0;
};

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw OutputError(path.string() + ": cannot write (a full disk?)");
}

// A folder an earlier export wrote: nothing in it but frame-*.vtu files.
bool is_export_folder(const fs::path& folder) {
  for (const auto& e : fs::directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name.rfind("frame-", 0) != 0 || e.path().extension() != ".vtu") return false;
  }
  return true;
}

}  // namespace

ExportReport export_vtk(const fs::path& run_file, const fs::path& collection, const ExportOptions& options) {
  if (options.tessellation < 0 || options.tessellation > 6)
    throw SceneError("--tessellation must be 0 to 6 (20·4^level triangles per ellipsoid), not " +
                     std::to_string(options.tessellation));
  if (collection.extension() != ".pvd") throw SceneError(collection.string() + ": a ParaView collection's name ends in .pvd");
  const fs::path folder = fs::path(collection).replace_extension();
  // Refused before any work: the collection as every output file (io/safe_publish.hpp), the
  // folder unless it is an earlier export's.
  if (const int held = io::claim_output(collection, options.force, {run_file}); held >= 0) ::close(held);
  std::error_code ec;
  if (fs::is_symlink(folder, ec)) throw OutputError(folder.string() + " is a symbolic link; give the place it points to");
  if (fs::exists(folder, ec)) {
    if (!fs::is_directory(folder, ec) || !is_export_folder(folder))
      throw OutputError(folder.string() + " exists and holds files noether export did not write; give another name");
    if (!options.force) throw OutputError(folder.string() + " exists; --force replaces it");
  }

  const PictureFrames run = detail::read_picture_frames(run_file, options.max_frames);
  std::vector<Mesh> surfaces;
  std::string bodies;
  for (std::size_t j = 0; j < run.names.size(); ++j) {
    surfaces.push_back(detail::picture_surface(run.shapes[j], options.tessellation));
    bodies += (j ? ", " : "") + std::to_string(j) + " " + run.names[j] + " (" + run.shapes[j].name() + ")";
  }
  // No "--" inside an XML comment.
  std::string comment = "noether export of " + run_file.filename().string() + "; body: " + bodies + "; lengths in " +
                        run.unit_length + ", time in " + run.unit_time;
  for (std::size_t at; (at = comment.find("--")) != std::string::npos;) comment.replace(at, 2, "- -");

  ExportReport report;
  report.frames_in_file = run.frames_in_file;
  report.collection = collection;
  report.folder = folder;
  report.notes = run.notes;
  const fs::path partial_folder = io::partial_name(folder);
  const int digits = static_cast<int>(std::to_string(run.frames_in_file - 1).size());
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n<!-- " << comment << " -->\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  try {
    fs::create_directory(partial_folder);
    for (std::size_t i = 0; i < run.t.size(); ++i) {
      char name[48];
      std::snprintf(name, sizeof name, "frame-%0*u.vtu", digits, run.shown[i]);
      const std::string text = FrameGrid(run, surfaces, i).text(comment + "; file frame " + std::to_string(run.shown[i]));
      write_file(partial_folder / name, text);
      report.bytes += text.size();
      pvd << "    <DataSet timestep=\"" << detail::exact_text(run.t[i]) << "\" part=\"0\" file=\""
          << folder.filename().string() << "/" << name << "\"/>\n";
    }
    pvd << "  </Collection>\n</VTKFile>\n";
    if (fs::exists(folder, ec)) fs::remove_all(folder);  // an earlier export (checked above), with --force
    fs::rename(partial_folder, folder);
  } catch (...) {
    fs::remove_all(partial_folder, ec);
    throw;
  }
  io::write_whole_file(collection, pvd.str(), options.force, {run_file});
  report.bytes += pvd.str().size();
  report.frames_written = run.t.size();
  return report;
}

}  // namespace noether
