#include <noether/error.hpp>
#include <noether/mesh.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace noether {

namespace {

std::ifstream open(const std::filesystem::path& file, const char* what) {
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot open the " + what);
  return in;
}

[[noreturn]] void bad_line(const std::filesystem::path& file, int line, const std::string& why) {
  throw SceneError(file.string() + ":" + std::to_string(line) + ": " + why);
}

// A 1-based (or negative, relative) OBJ index → 0-based.
int obj_index(const std::string& token, int vertex_count, const std::filesystem::path& file,
              int line) {
  const std::string number = token.substr(0, token.find('/'));
  long i = 0;
  try {
    std::size_t used = 0;
    i = std::stol(number, &used);
    if (used != number.size()) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    bad_line(file, line, "face index '" + token + "' is not an integer");
  }
  if (i < 0) i += vertex_count + 1;
  if (i < 1 || i > vertex_count)
    bad_line(file, line, "face index " + number + " is out of range (the file has " +
                             std::to_string(vertex_count) + " vertices before this line)");
  return static_cast<int>(i - 1);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) {
    const auto a = f.find_first_not_of(" \t\r");
    const auto b = f.find_last_not_of(" \t\r");
    fields.push_back(a == std::string::npos ? std::string() : f.substr(a, b - a + 1));
  }
  while (!fields.empty() && fields.back().empty()) fields.pop_back();
  return fields;
}

double to_number(const std::string& s, const std::filesystem::path& file, int line) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument("bad");
    return v;
  } catch (const std::exception&) {
    bad_line(file, line, "'" + s + "' is not a finite number");
  }
}

}  // namespace

Mesh read_obj(const std::filesystem::path& file, double scale) {
  auto in = open(file, "shape file");
  Mesh mesh;
  mesh.source = file.string();
  std::vector<Vec3> vertices;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream ls(text);
    std::string tag;
    if (!(ls >> tag)) continue;
    if (tag == "v") {
      std::string a, b, c;
      if (!(ls >> a >> b >> c)) bad_line(file, line, "a vertex needs three coordinates");
      vertices.emplace_back(to_number(a, file, line), to_number(b, file, line),
                            to_number(c, file, line));
    } else if (tag == "f") {
      std::vector<int> idx;
      for (std::string tok; ls >> tok;)
        idx.push_back(obj_index(tok, static_cast<int>(vertices.size()), file, line));
      if (idx.size() < 3) bad_line(file, line, "a face needs at least three vertices");
      for (std::size_t k = 1; k + 1 < idx.size(); ++k) {  // fan
        mesh.faces.push_back({idx[0], idx[k], idx[k + 1]});
        mesh.face_lines.push_back(line);
      }
    }
  }
  if (vertices.empty() || mesh.faces.empty())
    throw SceneError(file.string() + ": no 'v' and 'f' lines: not a Wavefront OBJ surface");
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i)
    mesh.vertices.col(static_cast<Eigen::Index>(i)) = scale * vertices[i];
  return mesh;
}

Mesh read_vertex_facet_csv(const std::filesystem::path& vertex_file,
                           const std::filesystem::path& facet_file, double scale) {
  Mesh mesh;
  mesh.source = vertex_file.string() + " + " + facet_file.string();
  std::vector<Vec3> vertices;
  {
    auto in = open(vertex_file, "vertex file");
    std::string text;
    for (int line = 1; std::getline(in, text); ++line) {
      const auto f = split_csv(text);
      if (f.empty()) continue;
      if (f.size() != 3 && f.size() != 4)
        bad_line(vertex_file, line, "a vertex row needs 'x, y, z' or 'id, x, y, z', not " +
                                        std::to_string(f.size()) + " fields");
      const std::size_t o = f.size() - 3;
      vertices.emplace_back(to_number(f[o], vertex_file, line), to_number(f[o + 1], vertex_file, line),
                            to_number(f[o + 2], vertex_file, line));
    }
  }
  auto in = open(facet_file, "facet file");
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const auto f = split_csv(text);
    if (f.empty()) continue;
    if (f.size() != 3)
      bad_line(facet_file, line, "a facet row needs three vertex indices, not " +
                                     std::to_string(f.size()) + " fields");
    std::array<int, 3> face{};
    for (int k = 0; k < 3; ++k) {
      const double v = to_number(f[static_cast<std::size_t>(k)], facet_file, line);
      if (v != std::floor(v) || v < 1 || v > static_cast<double>(vertices.size()))
        bad_line(facet_file, line, "vertex index " + f[static_cast<std::size_t>(k)] +
                                       " is not an integer from 1 to " +
                                       std::to_string(vertices.size()));
      face[static_cast<std::size_t>(k)] = static_cast<int>(v) - 1;
    }
    mesh.faces.push_back(face);
    mesh.face_lines.push_back(line);
  }
  if (vertices.empty() || mesh.faces.empty())
    throw SceneError(mesh.source + ": no vertices or no facets");
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i)
    mesh.vertices.col(static_cast<Eigen::Index>(i)) = scale * vertices[i];
  return mesh;
}

double mesh_volume(const Mesh& mesh) {
  double six_v = 0.0;
  for (const auto& f : mesh.faces) {
    Mat3 J;
    J << mesh.vertices.col(f[0]), mesh.vertices.col(f[1]), mesh.vertices.col(f[2]);
    six_v += J.determinant();
  }
  return six_v / 6.0;
}

void validate_mesh(const Mesh& mesh) {
  auto where = [&](std::size_t k) {
    std::ostringstream s;
    s << mesh.source << ": face " << k + 1;
    if (k < mesh.face_lines.size()) s << " (line " << mesh.face_lines[k] << ")";
    return s.str();
  };
  double extent = 0.0;
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i)
    extent = std::max(extent, mesh.vertices.col(i).cwiseAbs().maxCoeff());
  // Directed edge (i, j) → the face that traverses it.
  std::map<std::pair<int, int>, std::size_t> directed;
  for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
    const auto& f = mesh.faces[k];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
      throw SceneError(where(k) + " repeats a vertex: a degenerate face");
    const Vec3 a = mesh.vertices.col(f[0]), b = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
    if ((b - a).cross(c - a).norm() <= 1e-14 * extent * extent)
      throw SceneError(where(k) + " has zero area: a degenerate face");
    for (int e = 0; e < 3; ++e) {
      const std::pair<int, int> edge{f[static_cast<std::size_t>(e)], f[static_cast<std::size_t>((e + 1) % 3)]};
      const auto [it, inserted] = directed.emplace(edge, k);
      if (!inserted) {
        std::ostringstream msg;
        msg << where(k) << " traverses the edge between vertices " << edge.first + 1 << " and "
            << edge.second + 1 << " in the same direction as " << where(it->second).substr(mesh.source.size() + 2)
            << ": the faces are not consistently oriented (one of them is inverted), or more than"
               " two faces share the edge";
        throw SceneError(msg.str());
      }
    }
  }
  for (const auto& [edge, k] : directed)
    if (!directed.count({edge.second, edge.first})) {
      std::ostringstream msg;
      msg << where(k) << ": its edge between vertices " << edge.first + 1 << " and "
          << edge.second + 1 << " belongs to no other face: the surface is not closed";
      throw SceneError(msg.str());
    }
  const double volume = mesh_volume(mesh);
  if (!(volume > 0.0)) {
    std::ostringstream msg;
    msg << mesh.source << ": the enclosed volume is " << volume
        << " (not positive): the faces point inwards; reverse the vertex order of every face";
    throw SceneError(msg.str());
  }
}

}  // namespace noether
