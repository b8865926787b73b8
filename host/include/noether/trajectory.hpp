#pragma once
// Trajectory: the bodies' positions and velocities at a run's frames, and between them by the
// cubic Hermite interpolant of docs/equations.md eq. 16.2 (exact at the frames; error
// O(Δt⁴) between them). What observables are computed from (docs/fitting.md).
#include <noether/lie.hpp>
#include <noether/mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace noether {

// The index of a body in `names`; SceneError "no body 'X' in the run (did you mean …?); its
// bodies are …" when there is none.
std::size_t body_index(const std::vector<std::string>& names, const std::string& name);

class Trajectory {
 public:
  std::vector<std::string> names;  // the bodies, in scene order
  std::vector<double> masses;
  // The bodies' surfaces in their body frames, for lightcurves (read_trajectory with shapes): a
  // polyhedron's mesh, an ellipsoid tessellated, a sphere of the body's radius; an empty mesh
  // for a body without one.
  std::vector<Mesh> surfaces;

  // Appends a frame: positions and velocities [3][body]; times must not decrease (two frames at
  // one time are an impulse's before and after).
  void append(double t, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v);
  // With their derivatives with respect to P parameters: ∂x/∂p and ∂v/∂p, 3n × P (rows 3j…3j+2
  // for body j, as the positions' rows of docs/equations.md eq. 21.1). Every frame has them or
  // none does.
  void append(double t, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, const Eigen::MatrixXd& dx,
              const Eigen::MatrixXd& dv);
  bool has_derivatives() const { return !dx_.empty(); }
  // Attaches the bodies' attitudes R (body → scene) and angular velocities Ω (body frame) to the
  // frame appended last — identity and zero for a point mass. Every frame has them or none does.
  void append_attitudes(const std::vector<Mat3>& R, const Eigen::Matrix3Xd& omega);
  bool has_attitudes() const { return !R_.empty(); }
  std::size_t frames() const { return t_.size(); }
  double t_first() const { return t_.front(); }
  double t_last() const { return t_.back(); }
  const std::vector<double>& times() const { return t_; }
  // The body index of a name (body_index).
  std::size_t body(const std::string& name) const { return body_index(names, name); }

  // Positions and velocities at t ∈ [t_first, t_last] (SceneError outside): a frame's own at its
  // time (the later of two frames at one time: after an impulse), else eq. 16.2 between the two
  // frames around t.
  void sample(double t, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v) const;
  // The same with the derivatives: eq. 16.2 is linear in the frames' x and v, so the
  // interpolant's derivative is the interpolant of theirs (Error when the frames have none).
  void sample(double t, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, Eigen::MatrixXd& dx, Eigen::MatrixXd& dv) const;
  // The attitudes at t: a frame's own, else R0 exp(S(θ)) with θ the cubic Hermite interpolant
  // of eq. 29.4 between the two frames around t (exact for a steady spin; error O(Δt⁴)).
  // SceneError when a body turns by more than 2 rad between the frames (too far apart to tell
  // which way it turned).
  std::vector<Mat3> attitudes(double t) const;

 private:
  // The frames and weights of (16.2) at t: x = a0 x_k0 + b0 v_k0 + a1 x_k1 + b1 v_k1 and
  // v = c0 x_k0 + d0 v_k0 + c1 x_k1 + d1 v_k1 (k0 = k1 and weights (1, 0, 0, 0) at a frame).
  struct Weights {
    std::size_t k0 = 0, k1 = 0;
    double a0 = 1, b0 = 0, a1 = 0, b1 = 0, c0 = 0, d0 = 1, c1 = 0, d1 = 0;
  };
  Weights weights(double t) const;
  std::vector<double> t_;
  std::vector<Eigen::Matrix3Xd> x_, v_;
  std::vector<Eigen::MatrixXd> dx_, dv_;
  std::vector<std::vector<Mat3>> R_;
  std::vector<Eigen::Matrix3Xd> omega_;
};

// The trajectory recorded in a run's output file: its complete frames, each verified against
// its checksum (OutputError: not a run's output, damaged). With `shapes`, also the attitudes
// and the bodies' surfaces, from the scene the run was made from (its shape files must still be
// where it names them; an ellipsoid's tessellation level as tessellated_ellipsoid's).
struct TrajectoryShapes {
  bool wanted = false;
  int ellipsoid_level = 4;
};
Trajectory read_trajectory(const std::filesystem::path& run_file, const TrajectoryShapes& shapes = {});
// The names of a run's bodies, in scene order, without reading its frames.
std::vector<std::string> read_trajectory_names(const std::filesystem::path& run_file);

}  // namespace noether
