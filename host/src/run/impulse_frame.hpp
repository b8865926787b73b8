#pragma once
// The frame an impulse's Δv is given in (docs/equations.md §24): the scene's inertial axes, or the
// RTN frame of the body's orbit about another body at the impulse's time, and how that frame
// moves with the state (for the tangent's jump).
#include <noether/scene.hpp>
#include <noether/state.hpp>

namespace noether::detail {

// Columns r̂ = r/|r|, t̂ = n̂ × r̂, n̂ = (r × v)/|r × v| of an orbit with relative position r and
// velocity v (24.4). Throws Error when r × v = 0: a radial or resting orbit has no RTN frame.
Mat3 rtn_frame(const Vec3& r, const Vec3& v);

// The frame's directional derivative along (δr, δv) (24.5).
Mat3 rtn_frame_derivative(const Vec3& r, const Vec3& v, const Vec3& dr, const Vec3& dv);

// The impulse's orbit at `state`: the body's position and velocity relative to `around`.
struct RelativeOrbit {
  Vec3 r, v;
};
RelativeOrbit relative_orbit(const Impulse& impulse, const System& system, const State& state);

}  // namespace noether::detail
