#pragma once
// Mesh: a closed triangulated surface read from a shape file, and its validation
// (docs/equations.md §11). Faces are vertex triples, counter-clockwise seen from outside.
#include <noether/lie.hpp>

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct Mesh {
  Eigen::Matrix3Xd vertices;                // columns, in metres after reading
  std::vector<std::array<int, 3>> faces;    // 0-based vertex indices
  std::vector<int> face_lines;              // line of each face in its file (for messages)
  std::string source;                       // file name(s), for messages
};

// Bounds on what a shape file may hold, so that no file takes unbounded memory or time: a
// mesh of 4,194,304 faces (2^22; a 3-million-facet Bennu model fits) takes about 9 s and 1 GB
// to read, check and integrate (1.3 million faces: 2.7 s, 0.3 GB, `noether run`). Larger
// files are refused by name.
constexpr std::size_t kMaxShapeFileBytes = std::size_t{1} << 30;  // 1 GiB
constexpr std::size_t kMaxMeshFaces = std::size_t{1} << 22;
constexpr std::size_t kMaxMeshVertices = std::size_t{1} << 22;
// The self-intersection search (find_self_intersection) tests at most this many face pairs.
constexpr std::size_t kMaxFacePairTests = std::size_t{200'000'000};
// Faces closer than this fraction of the mesh's size are taken to touch.
constexpr double kSelfIntersectionTolerance = 1e-10;
// A mesh of several separate closed pieces (lobes, or a shell round a cavity) may have at most
// this many: each piece's nesting in the others is checked at O(faces) cost.
constexpr std::size_t kMaxMeshPieces = 64;

// Wavefront OBJ: `v x y z` and `f i j k` lines (1-based indices, `i/t/n` forms accepted,
// negative indices relative to the end); polygons with more than three vertices are
// fanned into triangles. Other lines are ignored. Coordinates are multiplied by `scale`.
Mesh read_obj(const std::filesystem::path& file, double scale);

// The vertex + facet CSV pair of GUBAS: vertex rows `id, x, y, z` (or `x, y, z`), facet rows
// `i, j, k` with 1-based indices (trailing empty fields allowed).
Mesh read_vertex_facet_csv(const std::filesystem::path& vertices,
                                       const std::filesystem::path& facets, double scale);

// Throws SceneError naming the file and the first offending face unless the mesh is a
// closed, consistently oriented, outward-facing triangulated surface that does not cross or
// touch itself: no face repeats a vertex or has zero area, every edge is shared by exactly two
// faces that traverse it in opposite directions, no two faces meet except along their shared
// edges and vertices, and the enclosed volume is positive. Its vertices must be finite. A mesh
// of several pieces (at most kMaxMeshPieces) must enclose every point at most once: an outward
// piece may not lie inside another solid piece, an inward one (a cavity) must lie inside one.
void validate_mesh(const Mesh& mesh);

// The first pair of faces (0-based, in order) found to cross or touch where a closed surface
// must not: faces sharing no vertex that have a point in common, faces sharing a vertex that
// meet elsewhere, faces sharing an edge folded onto each other. Throws SceneError past
// kMaxFacePairTests. Bounded memory: O(faces).
std::optional<std::pair<std::size_t, std::size_t>> find_self_intersection(const Mesh& mesh);

// The solid angle of the triangle (a, b, c) seen from p, signed (positive for a face
// counter-clockwise seen from outside and p inside), by van Oosterom & Strackee (1983): eq. 16.7.
// Summed over a closed surface: 4π × its winding number about p.
double triangle_solid_angle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Signed volume, Σ det[v1 v2 v3]/6 over faces (positive for outward faces).
double mesh_volume(const Mesh& mesh);

}  // namespace noether

#pragma GCC visibility pop
