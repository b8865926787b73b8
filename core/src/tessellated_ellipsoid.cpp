// The ellipsoid as a closed mesh: the subdivided icosahedron of tessellated_ellipsoid.hpp.
#include <noether/error.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace noether {

Mesh tessellated_ellipsoid(const Vec3& semi_axes, int level) {
  if (level < 0 || level > 8) throw SceneError("an ellipsoid's tessellation level must be in [0, 8]");
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v{{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                      {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<int, 3>> faces{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      const int k = static_cast<int>(v.size()) - 1;
      middle.emplace(key, k);
      return k;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(4 * faces.size());
    for (const auto& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  Mesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(v.size()));
  for (std::size_t k = 0; k < v.size(); ++k)
    mesh.vertices.col(static_cast<Eigen::Index>(k)) = v[k].cwiseProduct(semi_axes);
  mesh.faces = std::move(faces);
  mesh.source = "ellipsoid, " + std::to_string(mesh.faces.size()) + " facets";
  return mesh;
}

}  // namespace noether
