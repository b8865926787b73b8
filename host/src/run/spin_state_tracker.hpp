#pragma once
// SpinStateTracker: the SpinState of every rigid body (noether/spin_state.hpp), followed frame by
// frame (RunStatistics); and the two angles it is made of, which the output's frames share
// (io/frame_schema.cpp).
#include <noether/spin_state.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <vector>

namespace noether {

// Eq. 17.10 for a rigid body of a binary, measured from the other body: (ψ, θ, φ) in radians of
// A = Oᵀ R, O with x̂ towards the other body and ẑ along the pair's orbit normal, folded so that
// ψ ∈ (−π/2, π/2] (the long axis has no sign).
Vec3 orbit_frame_angles(const Vec3& towards_other, const Vec3& orbit_normal, const Mat3& R);
// The principal axis of J's largest moment (body frame, unit; its sign is arbitrary).
Vec3 largest_moment_axis(const Mat3& J);
// Eq. 17.11: the angle between Π (body frame) and that axis, in [0, π/2]; NaN when Π = 0.
double nutation_angle(const Vec3& axis, const Vec3& Pi);

class SpinStateTracker {
 public:
  explicit SpinStateTracker(const System& system);
  void start();  // a new segment: nothing seen yet
  void observe(const State& state);
  std::vector<SpinState> spin_states() const;
  // What a saved simulation keeps of it, and back (Simulation::save, load).
  std::vector<double> pack() const;
  void unpack(const std::vector<double>& numbers);

 private:
  struct Track {
    std::size_t body = 0, other = 0;
    bool binary = false;
    Vec3 axis = Vec3::UnitZ();  // largest_moment_axis of the body's J
    double t = 0.0, yaw = 0.0, first = 0.0, low = 0.0, high = 0.0;  // yaw unwrapped (radians)
    double rate = 0.0;       // the yaw's rate at the last frame (radians per unit time)
    double t_before = 0.0, rate_before = 0.0;  // the frame before it (for a quadratic root)
    double pitch = 0.0, roll = 0.0, nutation = 0.0, max_nutation = 0.0;
    bool seen = false, undersampled = false;
    // Eq. 17.13: the yaw's turning points, the first and the last, with their interpolation errors.
    int frames = 0, turning = 0;
    double first_turn = 0.0, last_turn = 0.0, first_turn_error = 0.0, last_turn_error = 0.0;
    // Eq. 17.14: the inertial direction k of R Π at the first frame it is not zero, the body axis
    // followed about it, that axis' angle unwrapped (radians) since spin_t0, and its rate.
    Vec3 spin_axis = Vec3::Zero(), reference = Vec3::UnitX();
    double spin = 0.0, spin_first = 0.0, spin_t0 = 0.0, spin_t = 0.0, spin_rate = 0.0;
    bool spinning = false, spin_undersampled = false, spin_tumbling = false;
  };
  void follow_spin(Track& t, double time, const Mat3& R, const Vec3& Pi) const;  // eq. 17.14
  const System& system_;
  std::vector<Track> tracks_;  // one per rigid body
};

}  // namespace noether
