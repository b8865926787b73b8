// A run's frames and the positions and velocities between them (docs/equations.md eq. 16.2).
#include "io/run_record.hpp"

#include <noether/error.hpp>
#include <noether/params.hpp>
#include <noether/trajectory.hpp>

#include <algorithm>
#include <sstream>

namespace noether {

void Trajectory::append(double t, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  if (!t_.empty() && !(t >= t_.back())) throw Error("a trajectory's frames must not go back in time");
  if (!dx_.empty()) throw Error("a trajectory's frames all have derivatives or none has");
  t_.push_back(t);
  x_.push_back(x);
  v_.push_back(v);
}

void Trajectory::append(double t, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, const Eigen::MatrixXd& dx,
                        const Eigen::MatrixXd& dv) {
  if (!t_.empty() && !(t >= t_.back())) throw Error("a trajectory's frames must not go back in time");
  if (dx_.size() != t_.size()) throw Error("a trajectory's frames all have derivatives or none has");
  if (dx.rows() != 3 * x.cols() || dv.rows() != dx.rows() || dv.cols() != dx.cols())
    throw Error("a trajectory frame's derivatives must be 3n × P, for positions and velocities alike");
  t_.push_back(t);
  x_.push_back(x);
  v_.push_back(v);
  dx_.push_back(dx);
  dv_.push_back(dv);
}

std::size_t body_index(const std::vector<std::string>& names, const std::string& name) {
  for (std::size_t j = 0; j < names.size(); ++j)
    if (names[j] == name) return j;
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  const std::string near = closest_match(name, names);
  throw SceneError("no body '" + name + "' in the run" + (near.empty() ? "" : " (did you mean " + near + "?)") +
                   "; its bodies are " + known);
}

Trajectory::Weights Trajectory::weights(double t) const {
  if (t_.empty() || !(t >= t_.front() && t <= t_.back())) {
    std::ostringstream why;
    why.precision(10);
    why << "t = " << t << " is outside the run";
    if (!t_.empty()) why << " (" << t_.front() << " … " << t_.back() << ")";
    throw SceneError(why.str());
  }
  // The first frame later than t; the frame before it is at or before t.
  const auto after = std::upper_bound(t_.begin(), t_.end(), t);
  const auto k1 = static_cast<std::size_t>(after - t_.begin());
  Weights w;
  if (k1 == 0 || t_[k1 - 1] == t || k1 == t_.size()) {  // at a frame (the last of its time)
    w.k0 = w.k1 = k1 - 1;
    return w;
  }
  w.k0 = k1 - 1, w.k1 = k1;
  const double dt = t_[k1] - t_[k1 - 1], s = (t - t_[k1 - 1]) / dt;
  // (16.2) and its time derivative
  w.a0 = 2 * s * s * s - 3 * s * s + 1, w.b0 = (s * s * s - 2 * s * s + s) * dt;
  w.a1 = -2 * s * s * s + 3 * s * s, w.b1 = (s * s * s - s * s) * dt;
  w.c0 = (6 * s * s - 6 * s) / dt, w.d0 = 3 * s * s - 4 * s + 1;
  w.c1 = (-6 * s * s + 6 * s) / dt, w.d1 = 3 * s * s - 2 * s;
  return w;
}

void Trajectory::sample(double t, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v) const {
  const Weights w = weights(t);
  x = w.a0 * x_[w.k0] + w.b0 * v_[w.k0] + w.a1 * x_[w.k1] + w.b1 * v_[w.k1];
  v = w.c0 * x_[w.k0] + w.d0 * v_[w.k0] + w.c1 * x_[w.k1] + w.d1 * v_[w.k1];
}

void Trajectory::sample(double t, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, Eigen::MatrixXd& dx,
                        Eigen::MatrixXd& dv) const {
  if (dx_.empty()) throw Error("this trajectory has no derivatives");
  sample(t, x, v);
  const Weights w = weights(t);
  dx = w.a0 * dx_[w.k0] + w.b0 * dv_[w.k0] + w.a1 * dx_[w.k1] + w.b1 * dv_[w.k1];
  dv = w.c0 * dx_[w.k0] + w.d0 * dv_[w.k0] + w.c1 * dx_[w.k1] + w.d1 * dv_[w.k1];
}

Trajectory read_trajectory(const std::filesystem::path& run_file) {
  const io::RunRecord run(run_file);
  Trajectory out;
  out.names = run.body_names();
  out.masses = run.body_masses();
  const auto n = static_cast<Eigen::Index>(run.bodies);
  run.read(0, static_cast<std::size_t>(run.frames), [&](std::size_t, const io::RecordedFrame& f) {
    Eigen::Matrix3Xd v(3, n);
    for (Eigen::Index j = 0; j < n; ++j) v.col(j) = f.state.p.col(j) / out.masses[static_cast<std::size_t>(j)];
    out.append(f.state.t, f.state.x, v);
  });
  return out;
}

}  // namespace noether
