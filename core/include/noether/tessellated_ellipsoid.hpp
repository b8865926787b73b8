#pragma once
// A triaxial ellipsoid as a closed triangulated surface, for what needs facets of a smooth shape
// (lightcurves, radiation pressure, the viewer). The subdivided icosahedron keeps the
// ellipsoid's three mirror planes: a facet's mirror image in x = 0, y = 0 or z = 0 is a facet.
#include <noether/mesh.hpp>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The ellipsoid x²/a² + y²/b² + z²/c² = 1 as a closed mesh: the icosahedron subdivided `level`
// times (20·4^level faces), its vertices on the unit sphere, then stretched by the semi-axes.
// Outward, counter-clockwise faces. level ∈ [0, 8].
Mesh tessellated_ellipsoid(const Vec3& semi_axes, int level);

}  // namespace noether

#pragma GCC visibility pop
