#pragma once
// Test shapes built in code: an axis-aligned box, a tetrahedron, an ellipsoid tessellated by
// subdividing an icosahedron, and the octahedra and KW4 meshes shipped in examples/shapes.
#include <noether/mesh.hpp>
#include <noether/solid.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include "test_support.hpp"


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

inline Mesh shipped_mesh(const std::string& file, double scale = 1.0) {
  return read_obj(source_path("examples/shapes/" + file), scale);
}

}  // namespace noether::test
