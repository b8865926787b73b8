#pragma once
// Mesh: a closed triangulated surface read from a shape file, and its validation
// (docs/equations.md §11). Faces are vertex triples, counter-clockwise seen from outside.
#include <noether/lie.hpp>

#include <array>
#include <filesystem>
#include <string>
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

// Wavefront OBJ: `v x y z` and `f i j k` lines (1-based indices, `i/t/n` forms accepted,
// negative indices relative to the end); polygons with more than three vertices are
// fanned into triangles. Other lines are ignored. Coordinates are multiplied by `scale`.
Mesh read_obj(const std::filesystem::path& file, double scale);

// The vertex + facet CSV pair of GUBAS: vertex rows `id, x, y, z` (or `x, y, z`), facet rows
// `i, j, k` with 1-based indices (trailing empty fields allowed).
Mesh read_vertex_facet_csv(const std::filesystem::path& vertices,
                                       const std::filesystem::path& facets, double scale);

// Throws SceneError naming the file and the first offending face unless the mesh is a
// closed, consistently oriented, outward-facing triangulated surface: no face repeats a
// vertex or has zero area, every edge is shared by exactly two faces that traverse it in
// opposite directions, and the enclosed volume is positive.
void validate_mesh(const Mesh& mesh);

// Signed volume, Σ det[v1 v2 v3]/6 over faces (positive for outward faces).
double mesh_volume(const Mesh& mesh);

}  // namespace noether

#pragma GCC visibility pop
