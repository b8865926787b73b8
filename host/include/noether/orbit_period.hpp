#pragma once
// OrbitPeriod: the period of one body's orbit about the body, at least as heavy, to which it is
// bound with the smallest semi-major axis at the start — a spacecraft's about Didymos, a moon's
// about its primary, a planet's about the Sun —, measured from the trajectory as the binary's
// mutual period is (docs/user-guide.md "Orbit periods"; host/src/run/orbit_periods_feature.hpp),
// with its error by the run repeated finer.
#include <noether/derived_error.hpp>

#include <limits>
#include <string>

namespace noether {

struct OrbitPeriod {
  std::string body, about;  // the lighter body, and the one it orbits
  // The last whole revolution's time over the revolutions, since the run began or its last jump
  // (an impulse); NaN before one.
  double period = std::numeric_limits<double>::quiet_NaN();
  int revolutions = 0;
  // The frames were more than a third of a turn of this orbit apart: the period is not measured.
  bool undersampled = false;
  // A radial fall (no angular momentum about the body): no orbit to time.
  bool radial = false;
  DerivedError error;  // set when a run finishes
};

}  // namespace noether
