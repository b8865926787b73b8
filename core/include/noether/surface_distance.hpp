#pragma once
// How far a point is from a solid's surface, for contact events (docs/equations.md §16):
// positive outside, zero on the surface, negative inside.
#include <noether/solid.hpp>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The gap from a point p (in the solid's body frame) to its surface. Outside, the Euclidean
// distance (eq. 16.5: a polyhedron's nearest face; an ellipsoid's nearest point, eq. 16.6);
// inside, minus the distance to the nearest face (polyhedron) or the radial distance to the
// surface, ‖p‖ (1 − 1/ρ) < 0 with ρ² = Σ (p_i / a_i)² (ellipsoid). Inside or outside a polyhedron
// by its winding number (the faces' solid angles seen from p, 16.7).
double surface_gap(const Solid& solid, const Vec3& p);

// Points on the surface, in the body frame, that stand for it when two solids meet: a
// polyhedron's vertices; for an ellipsoid `n` points a_i u_i of the Fibonacci lattice u on the
// unit sphere (spacing ~3.5 a/√n).
Eigen::Matrix3Xd surface_samples(const Solid& solid, int n = 2000);

}  // namespace noether

#pragma GCC visibility pop
