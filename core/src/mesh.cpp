#include <noether/error.hpp>
#include <noether/mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>

namespace noether {

namespace {

[[noreturn]] void bad_line(const std::filesystem::path& file, int line, const std::string& why) {
  throw SceneError(file.string() + ":" + std::to_string(line) + ": " + why);
}

// A token from a file, quoted for a message: bytes that are not printable ASCII as \xNN, and
// at most 40 characters of it (a file may hold a line of any length, or binary data).
std::string quoted(const std::string& token) {
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  out += "'";
  if (token.size() > 40) out += " (" + std::to_string(token.size()) + " characters; the first 40 shown)";
  return out;
}

// Opens a shape file after checking that it is a regular file of at most kMaxShapeFileBytes
// (a FIFO or a device such as /dev/zero would be read without end).
std::ifstream open(const std::filesystem::path& file, const char* what) {
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw SceneError(file.string() + ": the " + what + " is not a regular file");
  const auto bytes = std::filesystem::file_size(file, ec);
  if (!ec && bytes > kMaxShapeFileBytes)
    throw SceneError(file.string() + ": the " + what + " has " + std::to_string(bytes) +
                     " bytes; noether reads shape files of at most " +
                     std::to_string(kMaxShapeFileBytes) + " bytes (1 GiB): decimate the mesh");
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot open the " + what);
  return in;
}

// Refuses a mesh past the face or vertex bound (mesh.hpp), at the line that crosses it.
void check_size(std::size_t vertices, std::size_t faces, const std::filesystem::path& file, int line) {
  if (vertices > kMaxMeshVertices)
    bad_line(file, line, "more than " + std::to_string(kMaxMeshVertices) +
                             " vertices: noether reads meshes of at most that many; decimate the mesh");
  if (faces > kMaxMeshFaces)
    bad_line(file, line, "more than " + std::to_string(kMaxMeshFaces) +
                             " faces: noether reads meshes of at most that many; decimate the mesh");
}

// The vertices, multiplied by `scale` (into the scene's unit), as the mesh's columns; a
// coordinate that overflows when scaled is refused.
Eigen::Matrix3Xd scaled(const std::vector<Vec3>& vertices, double scale, const std::string& source) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    m.col(static_cast<Eigen::Index>(i)) = scale * vertices[i];
    if (!m.col(static_cast<Eigen::Index>(i)).allFinite())
      throw SceneError(source + ": vertex " + std::to_string(i + 1) +
                       " is not finite in the scene's length unit (its coordinates overflow)");
  }
  return m;
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
    bad_line(file, line, "face index " + quoted(token) + " is not an integer");
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
    bad_line(file, line, quoted(s) + " is not a finite number");
  }
}

// The pieces of a mesh (faces connected through shared vertices), as a piece index per face.
std::vector<std::size_t> pieces(const Mesh& mesh, std::size_t& count) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.vertices.cols()));
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  };
  for (const auto& f : mesh.faces)
    for (int e = 1; e < 3; ++e) parent[static_cast<std::size_t>(root(f[static_cast<std::size_t>(e)]))] = root(f[0]);
  std::vector<std::size_t> label(parent.size(), SIZE_MAX), piece(mesh.faces.size());
  count = 0;
  for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
    std::size_t& l = label[static_cast<std::size_t>(root(mesh.faces[k][0]))];
    if (l == SIZE_MAX) l = count++;
    piece[k] = l;
  }
  return piece;
}

// Every point enclosed at most once (mesh.hpp): for each piece, the winding number of all the
// others about one of its vertices (eq. 16.7) must be 0 for an outward piece and 1 for an
// inward one (a cavity). The surfaces are known not to touch, so the numbers are integers.
template <class Where>
void check_nesting(const Mesh& mesh, const Where& where) {
  std::size_t count = 0;
  const std::vector<std::size_t> piece = pieces(mesh, count);
  if (count <= 1) return;
  if (count > kMaxMeshPieces)
    throw SceneError(mesh.source + ": the mesh has " + std::to_string(count) +
                     " separate pieces; noether checks at most " + std::to_string(kMaxMeshPieces) +
                     " in one shape: give the pieces as separate bodies");
  std::vector<double> six_volume(count, 0.0);
  std::vector<std::size_t> first(count, SIZE_MAX);
  for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
    const auto& f = mesh.faces[k];
    Mat3 J;
    J << mesh.vertices.col(f[0]), mesh.vertices.col(f[1]), mesh.vertices.col(f[2]);
    six_volume[piece[k]] += J.determinant();
    if (first[piece[k]] == SIZE_MAX) first[piece[k]] = k;
  }
  for (std::size_t c = 0; c < count; ++c) {
    const Vec3 p = mesh.vertices.col(mesh.faces[first[c]][0]);
    double angle = 0.0;
    for (std::size_t k = 0; k < mesh.faces.size(); ++k)
      if (piece[k] != c) {
        const auto& f = mesh.faces[k];
        angle += triangle_solid_angle(p, mesh.vertices.col(f[0]), mesh.vertices.col(f[1]), mesh.vertices.col(f[2]));
      }
    const long winding = std::lround(angle / (4.0 * M_PI));
    const bool outward = six_volume[c] > 0.0;
    if (outward && winding != 0)
      throw SceneError(where(first[c]) + ": the piece of the surface this face belongs to lies inside "
                       "another solid piece of the same mesh (both outward): the volume between "
                       "them would count twice; remove the inner piece, or reverse its faces to "
                       "make it a cavity");
    if (!outward && winding != 1)
      throw SceneError(where(first[c]) + ": the piece of the surface this face belongs to points "
                       "inwards (a cavity) but lies inside no solid piece; reverse the vertex "
                       "order of its faces");
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
      check_size(vertices.size(), mesh.faces.size(), file, line);
    } else if (tag == "f") {
      std::vector<int> idx;
      for (std::string tok; ls >> tok;)
        idx.push_back(obj_index(tok, static_cast<int>(vertices.size()), file, line));
      if (idx.size() < 3) bad_line(file, line, "a face needs at least three vertices");
      check_size(vertices.size(), mesh.faces.size() + idx.size() - 2, file, line);
      for (std::size_t k = 1; k + 1 < idx.size(); ++k) {  // fan
        mesh.faces.push_back({idx[0], idx[k], idx[k + 1]});
        mesh.face_lines.push_back(line);
      }
    }
  }
  if (vertices.empty() || mesh.faces.empty())
    throw SceneError(file.string() + ": no 'v' and 'f' lines: not a Wavefront OBJ surface");
  mesh.vertices = scaled(vertices, scale, mesh.source);
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
      check_size(vertices.size(), 0, vertex_file, line);
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
    check_size(vertices.size(), mesh.faces.size() + 1, facet_file, line);
    mesh.faces.push_back(face);
    mesh.face_lines.push_back(line);
  }
  if (vertices.empty() || mesh.faces.empty())
    throw SceneError(mesh.source + ": no vertices or no facets");
  mesh.vertices = scaled(vertices, scale, mesh.source);
  return mesh;
}

double triangle_solid_angle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 r1 = a - p, r2 = b - p, r3 = c - p;
  const double l1 = r1.norm(), l2 = r2.norm(), l3 = r3.norm();
  const double numerator = r1.dot(r2.cross(r3));
  const double denominator = l1 * l2 * l3 + r1.dot(r2) * l3 + r1.dot(r3) * l2 + r2.dot(r3) * l1;
  return 2.0 * std::atan2(numerator, denominator);
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
  if (mesh.vertices.cols() == 0 || mesh.faces.empty())
    throw SceneError(mesh.source + ": no vertices or no faces");
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i)
    if (!mesh.vertices.col(i).allFinite())
      throw SceneError(mesh.source + ": vertex " + std::to_string(i + 1) + " is not finite");
  for (std::size_t k = 0; k < mesh.faces.size(); ++k)
    for (int j : mesh.faces[k])
      if (j < 0 || j >= mesh.vertices.cols())
        throw SceneError(where(k) + " names a vertex that does not exist");
  // Lengths relative to the mesh's size (its bounding box), so that the tests below do not
  // depend on where the mesh lies or on its unit.
  const double size = (mesh.vertices.rowwise().maxCoeff() - mesh.vertices.rowwise().minCoeff()).maxCoeff();
  // Directed edges (i, j) and the face that traverses each, sorted: 16 bytes per edge.
  struct Directed {
    int from, to;
    std::size_t face;
  };
  std::vector<Directed> directed;
  directed.reserve(3 * mesh.faces.size());
  for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
    const auto& f = mesh.faces[k];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
      throw SceneError(where(k) + " repeats a vertex: a degenerate face");
    const Vec3 a = mesh.vertices.col(f[0]), b = mesh.vertices.col(f[1]), c = mesh.vertices.col(f[2]);
    if (!((b - a).cross(c - a).norm() / size > 1e-14 * size))
      throw SceneError(where(k) + " has zero area: a degenerate face");
    for (int e = 0; e < 3; ++e)
      directed.push_back({f[static_cast<std::size_t>(e)], f[static_cast<std::size_t>((e + 1) % 3)], k});
  }
  auto key = [](const Directed& d) { return std::make_pair(d.from, d.to); };
  std::sort(directed.begin(), directed.end(), [&](const Directed& x, const Directed& y) {
    return key(x) != key(y) ? key(x) < key(y) : x.face < y.face;
  });
  for (std::size_t i = 1; i < directed.size(); ++i)
    if (key(directed[i]) == key(directed[i - 1])) {
      const Directed& first = directed[i - 1];
      const Directed& second = directed[i];
      std::ostringstream msg;
      msg << where(second.face) << " traverses the edge between vertices " << second.from + 1
          << " and " << second.to + 1 << " in the same direction as "
          << where(first.face).substr(mesh.source.size() + 2)
          << ": the faces are not consistently oriented (one of them is inverted), or more than"
             " two faces share the edge";
      throw SceneError(msg.str());
    }
  // Every edge must be traversed the other way too; report the first face (in file order)
  // with an unmatched edge.
  std::optional<Directed> open;
  for (const Directed& d : directed) {
    const bool matched = std::binary_search(directed.begin(), directed.end(), Directed{d.to, d.from, 0},
                                            [&](const Directed& x, const Directed& y) { return key(x) < key(y); });
    if (!matched && (!open || d.face < open->face)) open = d;
  }
  if (open) {
    std::ostringstream msg;
    msg << where(open->face) << ": its edge between vertices " << open->from + 1 << " and "
        << open->to + 1 << " belongs to no other face: the surface is not closed";
    throw SceneError(msg.str());
  }
  if (const auto crossing = find_self_intersection(mesh)) {
    std::ostringstream msg;
    msg << where(crossing->first) << " and " << where(crossing->second).substr(mesh.source.size() + 2)
        << " cross or touch: the surface intersects itself (faces may meet only along their shared"
           " edges and vertices)";
    throw SceneError(msg.str());
  }
  check_nesting(mesh, where);
  const double volume = mesh_volume(mesh);
  if (!(volume > 0.0)) {
    std::ostringstream msg;
    msg << mesh.source << ": the enclosed volume is " << volume
        << " (not positive): the faces point inwards; reverse the vertex order of every face";
    throw SceneError(msg.str());
  }
}

}  // namespace noether
