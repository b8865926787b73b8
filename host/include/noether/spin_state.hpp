#pragma once
// SpinState: how a rigid body turned over a run (docs/user-guide.md "Spin state",
// docs/equations.md eqs. 17.10–17.12): its libration about the line of centres of its binary, and
// how far its rotation is from a principal axis (tumbling). Each run's summary has one per rigid
// body, from the output frames.
#include <noether/derived_error.hpp>

#include <limits>
#include <string>

namespace noether {

struct SpinState {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string body;
  // The binary's other body, whose direction the orbit-frame angles (eq. 17.10) are measured
  // from; empty when the body is not one of a binary's two (then the next four are NaN).
  std::string other;
  // Half the range of the yaw ψ about the line of centres over the frames, unwrapped, degrees
  // (eq. 17.12): the libration amplitude; above 90 the body circulates.
  double libration_amplitude = kNaN;
  // Its error from the integrator, by the run repeated at half the step (when a run finishes;
  // not the frames' sampling of the extremes, the same in both runs).
  DerivedError libration_error;
  double turns = kNaN;                     // net turns of the long axis relative to the line of centres
  double max_pitch = kNaN, max_roll = kNaN;  // max |θ|, max |φ| of eq. 17.10, degrees
  // The frames were too far apart to follow the yaw (the body turned by ≥ 90° relative to the
  // line of centres between two of them): the four above are NaN, never aliased.
  bool undersampled = false;
  // Nutation: the angle between the angular momentum Π and the principal axis of largest
  // moment (eq. 17.11), degrees in [0, 90]: 0 for rotation about that axis (the relaxed state),
  // its largest value over the frames and its value at the last one.
  double max_nutation = kNaN, nutation = kNaN;
};

}  // namespace noether
