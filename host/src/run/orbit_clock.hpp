#pragma once
// OrbitClock: the period of one pair's relative orbit, measured from the trajectory (docs/user-guide.md,
// "The mutual orbit"): the angle body b sweeps about body a in the plane of their relative
// angular momentum at the start, unwrapped frame by frame, each whole revolution's time
// interpolated between frames (a cubic Hermite in the angle and its rate), the period the last
// whole revolution's time over the revolutions. Frames more than a third of a turn apart leave
// it unmeasured rather than aliased. The binary's mutual orbit (mutual_orbit_feature.cpp) and
// every other attracting pair's (orbit_periods_feature.cpp) are timed by it.
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <limits>
#include <vector>

namespace noether::detail {

class OrbitClock {
 public:
  OrbitClock(const System& system, std::size_t a, std::size_t b);
  void start_at(const State& state);  // the orbit's plane and the clock from here
  void track(const State& state);     // the angle swept since, whole revolutions timed
  bool timing() const { return timing_; }  // false: a radial fall, no orbit to time
  bool undersampled() const { return undersampled_; }
  void forget_undersampling() { undersampled_ = false; }
  double t0() const { return t0_; }
  int revolutions() const { return revolutions_; }
  double period() const { return period_; }  // NaN before a whole revolution
  // Its running values (15 numbers), and back from 13 to 15 (older checkpoints: without the
  // angle's rate, or without the frames' spacing judged); false when they are not that.
  std::vector<double> pack() const;
  bool unpack(const std::vector<double>& numbers);

 private:
  Vec3 relative(const State& state) const { return state.x.col(b_) - state.x.col(a_); }
  Vec3 relative_velocity(const State& state) const;
  double rate(const State& state) const;  // the angle's rate of change in the plane

  const System& system_;
  Eigen::Index a_, b_;
  bool timing_ = false;
  Vec3 e1_ = Vec3::Zero(), e2_ = Vec3::Zero();  // the plane at the start: r0 and its prograde normal
  double t0_ = 0.0, t_prev_ = 0.0, angle_prev_ = 0.0, swept_ = 0.0;
  double rate_prev_ = std::numeric_limits<double>::quiet_NaN();  // the angle's rate at t_prev_
  int revolutions_ = 0;
  bool undersampled_ = false;  // frames more than a third of a turn apart seen: not measured
  double period_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace noether::detail
