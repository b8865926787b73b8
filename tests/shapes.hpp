#pragma once
// Test shapes built in code: an axis-aligned box, a tetrahedron, an ellipsoid tessellated by
// subdividing an icosahedron, and the octahedra and KW4 meshes shipped in examples/shapes.
#include <noether/mesh.hpp>
#include <noether/solid.hpp>

#include "test_support.hpp"

#include <map>

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
inline Mesh ellipsoid_mesh(const Vec3& axes, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                       {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int i, int j) {
      const auto key = std::minmax(i, j);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[static_cast<std::size_t>(i)] + v[static_cast<std::size_t>(j)]).normalized());
      return mid[key] = static_cast<int>(v.size() - 1);
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& [a, b, c] : f) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.push_back({a, ab, ca});
      g.push_back({b, bc, ab});
      g.push_back({c, ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  Mesh m;
  m.source = "ellipsoid mesh";
  m.vertices.resize(3, static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) m.vertices.col(static_cast<Eigen::Index>(i)) = v[i].cwiseProduct(axes);
  m.faces = f;
  return m;
}

inline Mesh shipped_mesh(const std::string& file, double scale = 1.0) {
  return read_obj(source_path("examples/shapes/" + file), scale);
}

}  // namespace noether::test
