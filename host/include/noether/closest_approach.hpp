#pragma once
// ClosestApproach: the least distance between two bodies' centres over a run, located between the
// integrator's steps (docs/user-guide.md "Closest approaches"; host/src/run/closest_approach_feature.hpp),
// with its time and their errors by the run repeated at half the step (DerivedError).
#include <noether/derived_error.hpp>

#include <cstddef>
#include <limits>
#include <string>

namespace noether {

// The most bodies whose every pair's closest approach a run follows (66 pairs); larger scenes keep
// only the closest centres seen at the frames (RunSummary::min_distance).
inline constexpr std::size_t kClosestApproachMostBodies = 12;

struct ClosestApproach {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string pair;        // "a–b", the scene's order
  double distance = kNaN;  // min ‖x_a − x_b‖
  double t = kNaN;         // when
  // Where the least distance lies: between steps (an encounter: the centres approach, then
  // recede), or at the segment's start (receding from there) or at the run's end (still closing).
  enum class Where { kEncounter, kStart, kEnd };
  Where where = Where::kEncounter;
  // The bound on the error of locating it between two frames (the Hermite's remainder; 0 at a
  // frame), and its errors from the integrator by the run at half the step (set when a run
  // finishes: Simulation::finish), distance_error's error then including frames_error.
  double frames_error = 0.0;
  // The same bound on its time: the Hermite's error in r·ṙ over the rate at which r·ṙ turns
  // (large where the distance hardly changes: a near-circular orbit's periapsis).
  double frames_time_error = 0.0;
  DerivedError distance_error, time_error;
  const char* where_text() const {
    return where == Where::kStart ? "start" : where == Where::kEnd ? "end" : "encounter";
  }
};

}  // namespace noether
