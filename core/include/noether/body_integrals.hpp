#pragma once
// A body's inertia integrals T^{lmn} to a total degree (docs/equations.md §11–13, (31.3)): what
// the mutual series needs of each body, from whatever the scene gave — a solid, a gravity field,
// an inertia alone, or nothing (a point mass).
#include <noether/inertia_integrals.hpp>
#include <noether/system.hpp>

#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The integrals of `body` to degree `order`, in its body frame about its centre of mass: its
// solid's (ellipsoid closed form, polyhedron exact), its field's (31.3)–(31.4), its inertia's
// (degree ≤ 2; a rigid body without a solid shape, or a point cluster), or a point mass's.
// `for_tolerance`: the degree is a tolerance's max_order + 2, not a fixed order (for the message).
// Throws SceneError naming `plugin` and the body when it cannot give that degree.
InertiaIntegrals body_integrals(const Body& body, int order, const std::string& plugin, bool for_tolerance);

// The radius of the sphere about its centre of mass that holds what the integrals describe — the
// series of a pair converges beyond the sum of the two (docs/equations.md §15): the solid's, a
// field's reference body's radius, and 0 for a point mass or a body known by its inertia alone.
double integrals_radius(const Body& body);

}  // namespace noether

#pragma GCC visibility pop
