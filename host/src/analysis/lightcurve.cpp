// The disk-integrated brightness of docs/equations.md §29.
#include <noether/occlusion_map.hpp>

#include <noether/error.hpp>
#include <noether/lightcurve.hpp>

#include <cmath>
#include <string>
#include <utility>

namespace noether {

double scattering(Scattering law, double mu0, double mu) {  // (29.1)
  if (!(mu0 > 0) || !(mu > 0)) return 0.0;
  return law == Scattering::lommel_seeliger ? mu0 * mu / (mu0 + mu) : mu0 * mu;
}

double disk_integrated_flux(const std::vector<Mesh>& surfaces, const Vec3& sunlight, const Vec3& line_of_sight,
                            Scattering law, const FluxSettings& settings) {
  for (const Vec3* d : {&sunlight, &line_of_sight})
    if (!(d->norm() > 0) || !d->allFinite())
      throw SceneError("a lightcurve's sunlight and line of sight must be finite, non-zero vectors");
  if (settings.boundary_samples < 1) throw SceneError("boundary_samples must be at least 1");
  const Vec3 s = -sunlight.normalized(), o = -line_of_sight.normalized();  // towards the Sun, the observer
  const OcclusionMap from_sun(surfaces, s), from_observer(surfaces, o);
  const int m = settings.boundary_samples;
  double flux = 0.0;
  std::size_t global = 0;
  for (const auto& surface : surfaces)
    for (const auto& f : surface.faces) {
      const std::size_t own = global++;
      const Vec3 a = surface.vertices.col(f[0]), b = surface.vertices.col(f[1]), c = surface.vertices.col(f[2]);
      const Vec3 normal_area = 0.5 * (b - a).cross(c - a);  // n A
      const double area = normal_area.norm();
      if (!(area > 0)) continue;
      const Vec3 n = normal_area / area;
      const double S = scattering(law, n.dot(s), n.dot(o));
      if (S == 0.0) continue;  // faces away from the Sun or the observer
      auto seen_and_lit = [&](const Vec3& p) {
        return !from_observer.blocked(p, own) && !from_sun.blocked(p, own);
      };
      // (29.3): the centre and three points near the corners; all agreeing, the facet is whole.
      const Vec3 centre = (a + b + c) / 3;
      const bool whole = seen_and_lit(centre);
      bool agree = true;
      if (m > 1)
        for (const Vec3* corner : {&a, &b, &c})
          agree = agree && seen_and_lit(centre + 0.95 * (*corner - centre)) == whole;
      if (agree) {
        if (whole) flux += S * area;
        continue;
      }
      // Cut into m² equal triangles: barycentric (u, v) centres of the upward and downward ones.
      int hits = 0;
      const Vec3 ab = (b - a) / m, ac = (c - a) / m;
      for (int i = 0; i < m; ++i)
        for (int j = 0; i + j < m; ++j) {
          hits += seen_and_lit(a + (i + 1.0 / 3) * ab + (j + 1.0 / 3) * ac);
          if (i + j < m - 1) hits += seen_and_lit(a + (i + 2.0 / 3) * ab + (j + 2.0 / 3) * ac);
        }
      flux += S * area * hits / (static_cast<double>(m) * m);
    }
  return flux;
}

}  // namespace noether
