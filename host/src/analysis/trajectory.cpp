// A run's frames and the positions and velocities between them (docs/equations.md eq. 16.2).
#include "io/run_record.hpp"

#include <noether/error.hpp>
#include <noether/lightcurve.hpp>
#include <noether/params.hpp>
#include <noether/scene.hpp>
#include <noether/trajectory.hpp>

#include <algorithm>
#include <cmath>
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

void Trajectory::append_attitudes(const std::vector<Mat3>& R, const Eigen::Matrix3Xd& omega) {
  if (R_.size() + 1 != t_.size()) throw Error("a trajectory's frames all have attitudes or none has");
  if (R.size() != static_cast<std::size_t>(x_.back().cols()) || omega.cols() != x_.back().cols())
    throw Error("a trajectory frame's attitudes must be one per body");
  R_.push_back(R);
  omega_.push_back(omega);
}

namespace {

// J_r(θ)⁻¹, the inverse right Jacobian of SO(3): θ̇ = J_r(θ)⁻¹ Ω for R = R0 exp(S(θ)).
Mat3 inverse_right_jacobian(const Vec3& theta) {
  const double a = theta.norm();
  const Mat3 S = hat(theta);
  const double c = a < 1e-4 ? 1.0 / 12 + a * a / 720 : 1 / (a * a) - (1 + std::cos(a)) / (2 * a * std::sin(a));
  return Mat3::Identity() + 0.5 * S + c * S * S;
}

}  // namespace

std::vector<Mat3> Trajectory::attitudes(double t) const {
  if (R_.empty()) throw Error("this trajectory has no attitudes");
  const Weights w = weights(t);
  if (w.k0 == w.k1) return R_[w.k0];
  const double dt = t_[w.k1] - t_[w.k0], s = (t - t_[w.k0]) / dt;
  // (29.4): θ(s) = h10 Δt Ω0 + h01 θ1 + h11 Δt J_r(θ1)⁻¹ Ω1, θ1 = log(R0ᵀ R1).
  const double h10 = s * s * s - 2 * s * s + s, h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  std::vector<Mat3> out(R_[w.k0].size());
  for (std::size_t j = 0; j < out.size(); ++j) {
    const auto col = static_cast<Eigen::Index>(j);
    const Mat3& R0 = R_[w.k0][j];
    const Vec3 w0 = omega_[w.k0].col(col), w1 = omega_[w.k1].col(col);
    if (std::max(w0.norm(), w1.norm()) * dt > 2.0) {
      std::ostringstream why;
      why.precision(6);
      why << (names.size() > j ? "'" + names[j] + "'" : "a body") << " turns by " << std::max(w0.norm(), w1.norm()) * dt
          << " rad between the frames at t = " << t_[w.k0] << " and " << t_[w.k1]
          << ": too far apart to interpolate its attitude; write frames more often (run.output_every)";
      throw SceneError(why.str());
    }
    const Vec3 theta1 = log_so3(R0.transpose() * R_[w.k1][j]);
    const Vec3 theta = h10 * dt * w0 + h01 * theta1 + h11 * dt * (inverse_right_jacobian(theta1) * w1);
    out[j] = R0 * exp_so3(theta);
  }
  return out;
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

std::vector<std::string> read_trajectory_names(const std::filesystem::path& run_file) {
  return io::RunRecord(run_file).body_names();
}

namespace {

Mesh body_surface(const Body& body, int ellipsoid_level) {
  if (body.solid && body.solid->kind == Solid::Kind::Polyhedron) return body.solid->mesh;
  if (body.solid) return tessellated_ellipsoid(body.solid->semi_axes, ellipsoid_level);
  if (body.shape.is_map() && body.shape.size() > 0) return {};  // a cluster of points or spheres: no surface
  if (body.field) return {};  // known by its gravity field alone: no surface (its radius bounds it)
  if (body.radius > 0) return tessellated_ellipsoid(Vec3::Constant(body.radius), ellipsoid_level);
  return {};
}

}  // namespace

Trajectory read_trajectory(const std::filesystem::path& run_file, const TrajectoryShapes& shapes) {
  const io::RunRecord run(run_file);
  Trajectory out;
  out.names = run.body_names();
  out.masses = run.body_masses();
  System system;
  if (shapes.wanted) {
    const Scene scene = parse_scene(run.scene_text, run.scene_path, run.overrides);
    system = scene.system;
    if (system.size() != run.bodies) throw OutputError(run_file.string() + ": its scene does not match its bodies");
    for (const auto& body : system.bodies()) out.surfaces.push_back(body_surface(body, shapes.ellipsoid_level));
  }
  const auto n = static_cast<Eigen::Index>(run.bodies);
  run.read(0, static_cast<std::size_t>(run.frames), [&](std::size_t, const io::RecordedFrame& f) {
    Eigen::Matrix3Xd v(3, n);
    for (Eigen::Index j = 0; j < n; ++j) v.col(j) = f.state.p.col(j) / out.masses[static_cast<std::size_t>(j)];
    out.append(f.state.t, f.state.x, v);
    if (!shapes.wanted) return;
    std::vector<Mat3> R(run.bodies, Mat3::Identity());
    Eigen::Matrix3Xd omega = Eigen::Matrix3Xd::Zero(3, n);
    for (std::size_t j = 0; j < run.bodies; ++j) {
      const int k = system.rigid_index(j);
      if (k < 0) continue;
      R[j] = f.state.R[static_cast<std::size_t>(k)];
      omega.col(static_cast<Eigen::Index>(j)) = system.body(j).inertia_inverse * f.state.Pi.col(k);  // Ω = J⁻¹Π
    }
    out.append_attitudes(R, omega);
  });
  return out;
}

}  // namespace noether
