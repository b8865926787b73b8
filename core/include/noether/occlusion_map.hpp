#pragma once
// OcclusionMap: which points of a set of surfaces a distant source sees (docs/equations.md eq.
// 29.3). Every ray towards the source is parallel to one direction ŵ, so its projection on the
// plane ⟂ ŵ is a single point: the ray from p meets a facet exactly when p's projection lies in
// the facet's projected triangle and the facet lies further along ŵ than p there. The projected
// facets are binned in a uniform grid over the plane, so a query tests only the facets of one
// cell. Built per direction: a lightcurve's Sun and observer (eq. 29.3), radiation's Sun at each
// evaluation (its shadows, eq. 36.5).
#include <noether/lie.hpp>
#include <noether/mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <limits>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class OcclusionMap {
 public:
  // The facets of `surfaces` (one frame), seen from a source in the direction `towards` (unit).
  OcclusionMap(const std::vector<Mesh>& surfaces, const Vec3& towards);

  // Whether the ray p + t ŵ, t > 0, meets a facet other than facet `own` (its global index:
  // the surfaces' faces counted in order; kNone for a point on no facet).
  bool blocked(const Vec3& p, std::size_t own = kNone) const;
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

 private:
  Vec3 w_, e1_, e2_;
  double tolerance_ = 0.0;  // along ŵ: a facet must lie this far beyond p to hide it
  // Per facet: projected corners (2 × 3) and heights along ŵ.
  std::vector<Eigen::Matrix<double, 2, 3>> corners_;
  std::vector<Eigen::Vector3d> heights_;
  // The grid: cells × cells over [lo, lo + cells·size]², each cell's facets (CSR).
  Eigen::Vector2d lo_ = Eigen::Vector2d::Zero();
  double cell_ = 1.0;
  int cells_ = 1;
  std::vector<std::size_t> start_, facet_;
};

}  // namespace noether

#pragma GCC visibility pop
