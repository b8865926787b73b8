#pragma once
// SpinState: how a rigid body turned over a run (docs/user-guide.md "Spin state",
// docs/equations.md eqs. 17.10–17.14): its libration about the line of centres of its binary, and
// the period of that libration, its rotation period, and how far its rotation is from a
// principal axis (tumbling). Each run's summary has one per rigid body, from the output frames.
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
  // The yaw's turning points (where ψ̇ changes sign), their count: a body librates once it has
  // turned back at least twice (a swing each way); before that the amplitude above is only half
  // the range it has swept, and the summary says the run is too short to tell.
  int turning_points = 0;
  // Twice the mean time between the first and the last turning point (eq. 17.13): the libration
  // period, in the scene's time unit; NaN with fewer than three turning points (a whole
  // swing) or an amplitude at round-off. Where two modes mix (a free libration and the one an
  // eccentric orbit forces) it is their mean half-cycle, twice.
  double libration_period = kNaN;
  // Its error from the turning points' interpolation between frames (the quadratic against the
  // linear root of ψ̇ at the first and the last), and from the integrator (as libration_error).
  double libration_period_frames_error = kNaN;
  DerivedError libration_period_error;
  double turns = kNaN;                     // net turns of the long axis relative to the line of centres
  double max_pitch = kNaN, max_roll = kNaN;  // max |θ|, max |φ| of eq. 17.10, degrees
  // The frames were too far apart to follow the yaw (the body turned by ≥ 90° relative to the
  // line of centres between two of them): the four above are NaN, never aliased.
  bool undersampled = false;
  // Nutation: the angle between the angular momentum Π and the principal axis of largest
  // moment (eq. 17.11), degrees in [0, 90]: 0 for rotation about that axis (the relaxed state),
  // its largest value over the frames and its value at the last one.
  double max_nutation = kNaN, nutation = kNaN;
  // Rotation (eq. 17.14): the net turns of the body's principal axis most nearly perpendicular to
  // its spin (the long axis, for a principal-axis rotator) about the direction its angular
  // momentum R Π had at the first frame, and the mean period of one turn, (t_last − t_first) /
  // |turns|, in the scene's time unit: the sidereal rotation period of a principal-axis rotator;
  // for a tumbling body the mean of its precession and rotation rates. NaN when the body does not
  // rotate, turns less than once over the run, its frames are too far apart (spin_undersampled:
  // a third of a turn or more between two of them), or it tumbles so that the axis followed
  // comes within 30° of k (spin_tumbling: its angle about k is then no measure of a rotation).
  double spin_turns = kNaN, spin_period = kNaN;
  bool spin_undersampled = false, spin_tumbling = false;
  // The spin period's error from the integrator (the run repeated at half the step).
  DerivedError spin_period_error;
};

}  // namespace noether
