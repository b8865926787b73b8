#pragma once
// Ejecta: massless particles thrown from a point of a body's surface (the scene's
// `particles.ejecta`; docs/user-guide.md "Particles"; docs/equations.md §39). From the site — the
// outermost point of the surface in the body-frame direction (latitude, longitude) — each particle
// leaves at `cone` degrees from the surface's normal, at an azimuth about it drawn uniformly, with a
// speed relative to the spinning surface drawn from the truncated power law (39.1)
//     N(> v) ∝ v^(−γ),  speed_min ≤ v ≤ speed_max
// (γ = 3μ of the point-source scaling of Housen & Holsapple 2011; μ ≈ 0.4 for sand, 0.55 for
// competent rock). Particle i's draws depend on (seed, i) alone, so the first k particles of a
// larger cloud are the same k particles.
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace noether {

struct EjectaSettings {
  std::size_t body = 0;           // the body they leave
  double latitude = 0.0;          // of the site, degrees, in the body frame (principal axes)
  double longitude = 0.0;
  std::size_t count = 0;
  double speed_min = 0.0;         // relative to the surface, the scene's units
  double speed_max = 0.0;
  double exponent = 1.2;          // γ of (39.1)
  double cone = 45.0;             // degrees between the launch direction and the surface's normal
  double height = 0.0;            // above the surface along its normal at launch (0: 1e-6 of the body's radius)
  std::uint64_t seed = 1;          // a scene's k-th cloud (from 0): k + 1 unless given
};

// Where the ray from the centre of mass along the body-frame direction u (unit) crosses the
// surface of `body` last (its shape: ellipsoid, polyhedron, else the sphere of Body::radius), and
// the outward unit normal there. SceneError when the body has no surface.
struct SurfacePoint {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
};
SurfacePoint surface_point_along(const Body& body, const Vec3& u);

// The launch speed (39.1) of the quantile q ∈ (0, 1) of the truncated power law.
double ejecta_speed(const EjectaSettings& ejecta, double q);

// Appends the ejecta's inertial positions and velocities at the bodies' `state`: x_b + R_b (s + h n),
// v_b + R_b (Ω_b × s + v_launch) (39.2).
void launch_ejecta(const EjectaSettings& ejecta, const System& system, const State& state,
                   std::vector<Vec3>& position, std::vector<Vec3>& velocity);

}  // namespace noether
