#pragma once
// Trajectory: the bodies' positions and velocities at a run's frames, and between them by the
// cubic Hermite interpolant of docs/equations.md eq. 16.2 (exact at the frames; error
// O(Δt⁴) between them). What observables are computed from (docs/fitting.md).
#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace noether {

class Trajectory {
 public:
  std::vector<std::string> names;  // the bodies, in scene order
  std::vector<double> masses;

  // Appends a frame: positions and velocities [3][body]; times must not decrease (two frames at
  // one time are an impulse's before and after).
  void append(double t, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v);
  std::size_t frames() const { return t_.size(); }
  double t_first() const { return t_.front(); }
  double t_last() const { return t_.back(); }
  const std::vector<double>& times() const { return t_; }
  // The body index of a name; SceneError naming the bodies when there is none.
  std::size_t body(const std::string& name) const;

  // Positions and velocities at t ∈ [t_first, t_last] (SceneError outside): a frame's own at its
  // time (the later of two frames at one time: after an impulse), else eq. 16.2 between the two
  // frames around t.
  void sample(double t, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v) const;

 private:
  std::vector<double> t_;
  std::vector<Eigen::Matrix3Xd> x_, v_;
};

// The trajectory recorded in a run's output file: its complete frames, each verified against
// its checksum (OutputError: not a run's output, damaged).
Trajectory read_trajectory(const std::filesystem::path& run_file);

}  // namespace noether
