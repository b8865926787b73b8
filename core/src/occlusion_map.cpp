// The occlusion map of docs/equations.md eq. 29.3.
#include <noether/occlusion_map.hpp>
#include <noether/orthonormal_basis.hpp>

#include <algorithm>
#include <cmath>

namespace noether {

OcclusionMap::OcclusionMap(const std::vector<Mesh>& surfaces, const Vec3& towards) : w_(towards.normalized()) {
  complete_basis(w_, e1_, e2_);
  std::size_t total = 0;
  for (const auto& s : surfaces) total += s.faces.size();
  corners_.reserve(total);
  heights_.reserve(total);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = Eigen::Vector2d::Constant(-INFINITY);
  double hmin = INFINITY, hmax = -INFINITY;
  for (const auto& s : surfaces)
    for (const auto& f : s.faces) {
      Eigen::Matrix<double, 2, 3> c;
      Eigen::Vector3d h;
      for (int k = 0; k < 3; ++k) {
        const Vec3 v = s.vertices.col(f[static_cast<std::size_t>(k)]);
        c.col(k) << v.dot(e1_), v.dot(e2_);
        h[k] = v.dot(w_);
        lo = lo.cwiseMin(c.col(k));
        hi = hi.cwiseMax(c.col(k));
        hmin = std::min(hmin, h[k]);
        hmax = std::max(hmax, h[k]);
      }
      corners_.push_back(c);
      heights_.push_back(h);
    }
  if (total == 0) return;
  const double extent = std::max({hi.x() - lo.x(), hi.y() - lo.y(), hmax - hmin});
  tolerance_ = 1e-9 * extent;
  // About two facets a cell on average: cells² ≈ total / 2.
  cells_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(0.5 * static_cast<double>(total)))), 1, 4096);
  cell_ = std::max(hi.x() - lo.x(), hi.y() - lo.y()) / cells_ * (1 + 1e-12) + 1e-300;
  lo_ = lo;
  const auto cell_of = [&](double u) { return std::clamp(static_cast<int>(std::floor(u / cell_)), 0, cells_ - 1); };
  const std::size_t n_cells = static_cast<std::size_t>(cells_) * static_cast<std::size_t>(cells_);
  std::vector<std::size_t> count(n_cells + 1, 0);
  auto visit = [&](std::size_t f, auto&& use) {
    const auto& c = corners_[f];
    const int i0 = cell_of(c.row(0).minCoeff() - lo_.x()), i1 = cell_of(c.row(0).maxCoeff() - lo_.x());
    const int j0 = cell_of(c.row(1).minCoeff() - lo_.y()), j1 = cell_of(c.row(1).maxCoeff() - lo_.y());
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j) use(static_cast<std::size_t>(i) * static_cast<std::size_t>(cells_) + j);
  };
  for (std::size_t f = 0; f < total; ++f) visit(f, [&](std::size_t cell) { ++count[cell + 1]; });
  for (std::size_t k = 0; k < n_cells; ++k) count[k + 1] += count[k];
  start_ = count;
  facet_.resize(count.back());
  for (std::size_t f = 0; f < total; ++f) visit(f, [&](std::size_t cell) { facet_[count[cell]++] = f; });
}

bool OcclusionMap::blocked(const Vec3& p, std::size_t own) const {
  if (facet_.empty()) return false;
  const Eigen::Vector2d q(p.dot(e1_) - lo_.x(), p.dot(e2_) - lo_.y());
  if (q.x() < 0 || q.y() < 0 || q.x() > cells_ * cell_ || q.y() > cells_ * cell_) return false;
  const auto i = static_cast<std::size_t>(std::min(static_cast<int>(q.x() / cell_), cells_ - 1));
  const auto j = static_cast<std::size_t>(std::min(static_cast<int>(q.y() / cell_), cells_ - 1));
  const std::size_t cell = i * static_cast<std::size_t>(cells_) + j;
  const double hp = p.dot(w_);
  const Eigen::Vector2d at = q + lo_;
  for (std::size_t k = start_[cell]; k < start_[cell + 1]; ++k) {
    const std::size_t f = facet_[k];
    if (f == own) continue;
    const auto& c = corners_[f];
    // Barycentric coordinates of the projected point in the projected triangle.
    const Eigen::Vector2d ab = c.col(1) - c.col(0), ac = c.col(2) - c.col(0), ap = at - c.col(0);
    const double det = ab.x() * ac.y() - ab.y() * ac.x();
    if (std::abs(det) <= 1e-14 * ab.squaredNorm() + 1e-300) continue;  // edge-on: hides nothing
    const double l1 = (ap.x() * ac.y() - ap.y() * ac.x()) / det, l2 = (ab.x() * ap.y() - ab.y() * ap.x()) / det;
    const double l0 = 1 - l1 - l2;
    if (l0 < -1e-12 || l1 < -1e-12 || l2 < -1e-12) continue;
    const auto& h = heights_[f];
    if (l0 * h[0] + l1 * h[1] + l2 * h[2] > hp + tolerance_) return true;
  }
  return false;
}

}  // namespace noether
