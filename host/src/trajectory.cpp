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
  t_.push_back(t);
  x_.push_back(x);
  v_.push_back(v);
}

std::size_t Trajectory::body(const std::string& name) const {
  for (std::size_t j = 0; j < names.size(); ++j)
    if (names[j] == name) return j;
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  const std::string near = closest_match(name, names);
  throw SceneError("no body '" + name + "' in the run" + (near.empty() ? "" : " (did you mean " + near + "?)") +
                   "; its bodies are " + known);
}

void Trajectory::sample(double t, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v) const {
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
  if (k1 == 0 || t_[k1 - 1] == t || k1 == t_.size()) {  // at a frame (the last of its time)
    const std::size_t k = k1 - 1;
    x = x_[k], v = v_[k];
    return;
  }
  const std::size_t k0 = k1 - 1;
  const double dt = t_[k1] - t_[k0], s = (t - t_[k0]) / dt;
  // (16.2) and its time derivative
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s, h01 = -2 * s * s * s + 3 * s * s,
               h11 = s * s * s - s * s;
  const double d00 = (6 * s * s - 6 * s) / dt, d10 = 3 * s * s - 4 * s + 1, d01 = (-6 * s * s + 6 * s) / dt,
               d11 = 3 * s * s - 2 * s;
  x = h00 * x_[k0] + h10 * dt * v_[k0] + h01 * x_[k1] + h11 * dt * v_[k1];
  v = d00 * x_[k0] + d10 * v_[k0] + d01 * x_[k1] + d11 * v_[k1];
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
