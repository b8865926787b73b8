#pragma once
// Lightcurve: the disk-integrated brightness of bodies of given shapes, lit by a distant Sun and
// seen by a distant observer, with the bodies' mutual occultations and shadows — the mutual
// events of a binary — and each body's shadows on itself (docs/equations.md §29;
// docs/fitting.md, "Lightcurves").
#include <noether/lie.hpp>
#include <noether/mesh.hpp>
#include <noether/tessellated_ellipsoid.hpp>

#include <vector>

namespace noether {

// The scattering law of a surface element (29.1): S(μ0, μ), μ0 = n·ŝ the cosine of incidence,
// μ = n·ô of emission (ŝ towards the Sun, ô towards the observer).
//   Lommel–Seeliger: S = μ0 μ / (μ0 + μ)      Lambert: S = μ0 μ
enum class Scattering { lommel_seeliger, lambert };
double scattering(Scattering law, double mu0, double mu);

struct FluxSettings {
  // A facet that is partly hidden or partly shadowed (its centre and three points near its
  // corners disagree) is cut into boundary_samples² equal triangles, each hidden or lit as a
  // whole (29.3). 1: every facet whole.
  int boundary_samples = 8;
};

// The brightness F = Σ_facets ∫ S(μ0, μ) [seen] [lit] dA (29.2) of closed surfaces whose
// vertices are in one frame (the scene's), in the square of their length unit. `sunlight` is the
// direction sunlight travels (from the Sun towards the bodies), `line_of_sight` from the observer
// towards the bodies (both need not be unit; opposition is sunlight = line_of_sight). A point is
// seen when the ray from it towards the observer meets no facet of any surface, lit when the ray
// towards the Sun meets none. The flux received is F times E ϖ/(4π) (Lommel–Seeliger, single-
// scattering albedo ϖ) or E A/π (Lambert, albedo A) over the observer's distance squared, E the
// solar irradiance. SceneError for a zero or non-finite direction.
double disk_integrated_flux(const std::vector<Mesh>& surfaces, const Vec3& sunlight, const Vec3& line_of_sight,
                            Scattering law, const FluxSettings& settings = {});

}  // namespace noether
