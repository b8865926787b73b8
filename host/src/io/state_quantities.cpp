// The frame quantities of the state alone (state_quantities.hpp), computed when their block of
// frames is written.
#include "io/state_quantities.hpp"

#include <noether/euler_angles.hpp>
#include <noether/lie.hpp>
#include <noether/orbital_elements.hpp>

#include "run/binary_pair.hpp"
#include "run/spin_state_tracker.hpp"

#include <algorithm>
#include <limits>
#include <numbers>

namespace noether::io::of_state {

static double* doubles(void* out) { return static_cast<double*>(out); }
static void copy(double x, void* out) { *doubles(out) = x; }
static void copy(const Vec3& v, void* out) { std::copy(v.data(), v.data() + 3, doubles(out)); }

void velocity(const StateFrame& in, void* out) {  // v = γ/m
  double* v = doubles(out);
  for (std::size_t i = 0; i < in.system.size(); ++i)
    for (int a = 0; a < 3; ++a) v[3 * i + a] = in.state.p(a, static_cast<Eigen::Index>(i)) / in.system.body(i).mass;
}
void quaternion(const StateFrame& in, void* out) {  // (w, x, y, z) of R
  for (std::size_t k = 0; k < in.state.R.size(); ++k) {
    const Vec4 q = quaternion_from_rotation(in.state.R[k]);
    std::copy(q.data(), q.data() + 4, doubles(out) + 4 * k);
  }
}
void angular_velocity(const StateFrame& in, void* out) {  // Ω = J⁻¹Π (docs/equations.md §2)
  for (std::size_t k = 0; k < in.system.rigid_count(); ++k) {
    const Vec3 omega = in.system.body(in.system.body_of_rigid(k)).inertia_inverse *
                       in.state.Pi.col(static_cast<Eigen::Index>(k));
    copy(omega, doubles(out) + 3 * k);
  }
}
// The binary's (present only when there is one: primary and secondary are set).
static Vec3 column(const Eigen::Matrix3Xd& m, std::ptrdiff_t i) { return m.col(static_cast<Eigen::Index>(i)); }
static Vec3 relative_position(const StateFrame& in) { return column(in.state.x, in.secondary) - column(in.state.x, in.primary); }
static Vec3 relative_velocity(const StateFrame& in) {
  const auto mass = [&in](std::ptrdiff_t i) { return in.system.body(static_cast<std::size_t>(i)).mass; };
  return column(in.state.p, in.secondary) / mass(in.secondary) - column(in.state.p, in.primary) / mass(in.primary);
}
static const Mat3& attitude_of(const StateFrame& in, std::ptrdiff_t body) {
  return in.state.R[static_cast<std::size_t>(in.system.rigid_index(static_cast<std::size_t>(body)))];
}
void separation(const StateFrame& in, void* out) { copy(relative_position(in).norm(), out); }
void binary_position(const StateFrame& in, void* out) { copy(relative_position(in), out); }
void binary_velocity(const StateFrame& in, void* out) { copy(relative_velocity(in), out); }
void position_in_primary_frame(const StateFrame& in, void* out) {  // R_pᵀ r
  copy(Vec3(attitude_of(in, in.primary).transpose() * relative_position(in)), out);
}
void velocity_in_primary_frame(const StateFrame& in, void* out) {  // R_pᵀ v − Ω_p × R_pᵀ r (rotating frame)
  const Mat3& R = attitude_of(in, in.primary);
  const auto k = static_cast<Eigen::Index>(in.system.rigid_index(static_cast<std::size_t>(in.primary)));
  const Vec3 omega = in.system.body(static_cast<std::size_t>(in.primary)).inertia_inverse * Vec3(in.state.Pi.col(k));
  const Vec3 r = R.transpose() * relative_position(in);
  copy(Vec3(R.transpose() * relative_velocity(in) - omega.cross(r)), out);
}
void osculating_elements(const StateFrame& in, void* out) {  // a, e, i, Ω, ω, ν (eqs. 17.5–17.8)
  const double mu = in.system.G() * (in.system.body(static_cast<std::size_t>(in.primary)).mass +
                                     in.system.body(static_cast<std::size_t>(in.secondary)).mass);
  double* el = doubles(out);
  const Vec3 r = relative_position(in), v = relative_velocity(in);
  // Unbound (elements_from_state's own test, made here: a throw per frame cost microseconds).
  if (!(0.5 * v.squaredNorm() - mu / r.norm() < 0.0)) {
    std::fill(el, el + 6, std::numeric_limits<double>::quiet_NaN());
    return;
  }
  const OrbitalElements e = elements_from_state({r, v}, mu);
  const double deg = 180.0 / std::numbers::pi;
  const double values[6] = {e.a, e.e, e.i * deg, e.Omega * deg, e.omega * deg, e.nu * deg};
  std::copy(values, values + 6, el);
}
void libration(const StateFrame& in, void* out) {  // the primary's direction in the secondary's body frame
  const Vec3 u = attitude_of(in, in.secondary).transpose() * (-relative_position(in));
  double angle = std::atan2(u.y(), u.x()) * 180.0 / std::numbers::pi;  // (−180, 180]
  if (angle > 90.0) angle -= 180.0;  // the axis is a line: either end may face the primary
  if (angle <= -90.0) angle += 180.0;
  copy(angle, out);
}

static void copy_degrees(const Vec3& radians, void* out) { copy(Vec3(radians * (180.0 / std::numbers::pi)), out); }
void euler_angles(const StateFrame& in, void* out) {  // eq. 17.9 of each rigid body's R
  for (std::size_t k = 0; k < in.state.R.size(); ++k) copy_degrees(euler_angles_321(in.state.R[k]), doubles(out) + 3 * k);
}
// Eq. 17.10: the secondary's attitude in the orbit frame, whose x axis points at the primary and
// z along the orbit normal, yaw folded into (−90, 90].
void secondary_euler_angles(const StateFrame& in, void* out) {
  const Vec3 r = relative_position(in);
  copy_degrees(orbit_frame_angles(-r, r.cross(relative_velocity(in)), attitude_of(in, in.secondary)), out);
}
void nutation_angles(const StateFrame& in, void* out) {  // eq. 17.11, degrees
  for (std::size_t k = 0; k < in.system.rigid_count(); ++k) {
    doubles(out)[k] = nutation_angle(in.largest_moment_axes[k], in.state.Pi.col(static_cast<Eigen::Index>(k))) *
                      (180.0 / std::numbers::pi);
  }
}

}  // namespace noether::io::of_state
