#pragma once
// Test shapes built in code: an axis-aligned box, a tetrahedron, an ellipsoid tessellated by
// subdividing an icosahedron, and the octahedra and KW4 meshes shipped in examples/shapes.
#include <noether/mesh.hpp>
#include <noether/solid.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include "test_support.hpp"

#include <array>
#include <map>
#include <set>
#include <vector>


namespace noether::test {

// [−h, h] × [−k, k] × [−l, l], outward faces.
inline Mesh box_mesh(const Vec3& half) {
  Mesh m;
  m.source = "box";
  m.vertices.resize(3, 8);
  for (int i = 0; i < 8; ++i)
    m.vertices.col(i) = Vec3((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                             (i & 4) ? half.z() : -half.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.push_back({q[0], q[1], q[2]});
    m.faces.push_back({q[0], q[2], q[3]});
  }
  return m;
}

inline Mesh tetrahedron_mesh(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Mesh m;
  m.source = "tetrahedron";
  m.vertices.resize(3, 4);
  m.vertices << a, b, c, d;
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  if (mesh_volume(m) < 0)
    for (auto& f : m.faces) std::swap(f[1], f[2]);
  return m;
}

// An icosahedron subdivided `levels` times, projected onto the ellipsoid (x/a)² + … = 1.
inline Mesh ellipsoid_mesh(const Vec3& axes, int levels) { return tessellated_ellipsoid(axes, levels); }

// The surface of a union of unit cubes (cell (i, j, k) is [i, i + 1] × [j, j + 1] × [k, k + 1]):
// each face between a filled and an empty cell divided into m × m squares, each square into four
// triangles about its centre (so that a mirror of the cells is a mirror of the facets), outward,
// the vertices shared — a concave shape whose facets' edges can be made to fall where a shadow's
// edge does.
inline Mesh voxel_mesh(const std::vector<std::array<int, 3>>& cells, int m) {
  const std::set<std::array<int, 3>> filled(cells.begin(), cells.end());
  Mesh mesh;
  mesh.source = "voxels";
  std::map<std::array<long, 3>, int> index;  // on the lattice of spacing 1/(2m)
  std::vector<Vec3> vertices;
  auto vertex = [&](const std::array<long, 3>& p) {
    const auto [it, added] = index.try_emplace(p, static_cast<int>(vertices.size()));
    if (added) vertices.emplace_back(0.5 * p[0] / m, 0.5 * p[1] / m, 0.5 * p[2] / m);
    return it->second;
  };
  for (const auto& c : cells)
    for (int a = 0; a < 3; ++a)
      for (const int side : {-1, 1}) {
        std::array<int, 3> n = c;
        n[a] += side;
        if (filled.count(n)) continue;
        const int b = (a + 1) % 3, d = (a + 2) % 3;  // e_b × e_d = e_a
        for (int i = 0; i < m; ++i)
          for (int j = 0; j < m; ++j) {
            std::array<long, 3> p00{};
            for (int k = 0; k < 3; ++k) p00[k] = 2L * c[k] * m;
            p00[a] += side > 0 ? 2L * m : 0;
            p00[b] += 2L * i;
            p00[d] += 2L * j;
            std::array<long, 3> p10 = p00, p11 = p00, p01 = p00, centre = p00;
            p10[b] += 2, p11[b] += 2, p11[d] += 2, p01[d] += 2, centre[b] += 1, centre[d] += 1;
            const int ring[4] = {vertex(p00), vertex(p10), vertex(p11), vertex(p01)}, o = vertex(centre);
            for (int k = 0; k < 4; ++k) {
              const int v = ring[k], w = ring[(k + 1) % 4];  // counter-clockwise about e_a
              mesh.faces.push_back(side > 0 ? std::array<int, 3>{v, w, o} : std::array<int, 3>{w, v, o});
            }
          }
      }
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) mesh.vertices.col(static_cast<Eigen::Index>(i)) = vertices[i];
  return mesh;
}

inline Mesh shipped_mesh(const std::string& file, double scale = 1.0) {
  return read_obj(source_path("examples/shapes/" + file), scale);
}

}  // namespace noether::test
