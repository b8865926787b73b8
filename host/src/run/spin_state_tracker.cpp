// The spin state of each rigid body over a run: docs/equations.md eqs. 17.10–17.14.
#include "run/spin_state_tracker.hpp"

#include "run/binary_pair.hpp"

#include <noether/euler_angles.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace noether {

namespace {
constexpr double kPi = std::numbers::pi, kDegrees = 180.0 / std::numbers::pi;
constexpr std::size_t kPacked = 34;  // numbers per rigid body in pack()

// Eq. 17.13: where ψ̇ crosses zero between frames (t1, r1) and (t2, r2) — the linear root, refined
// by a Newton step on the quadratic through the frame before them (t0, r0) as well when there is
// one; its error the refinement's size (half the frames' interval without one).
struct Root {
  double t, error;
};
Root turning_time(double t0, double r0, double t1, double r1, double t2, double r2, bool quadratic) {
  const double linear = t1 + (t2 - t1) * r1 / (r1 - r2);
  if (!quadratic) return {linear, 0.5 * (t2 - t1)};
  const double d01 = (r1 - r0) / (t1 - t0), d12 = (r2 - r1) / (t2 - t1), d012 = (d12 - d01) / (t2 - t0);
  const double q = r0 + (linear - t0) * (d01 + (linear - t1) * d012);
  const double slope = d01 + d012 * ((linear - t0) + (linear - t1));
  double refined = slope != 0.0 ? linear - q / slope : linear;
  if (!(refined >= t1 && refined <= t2)) refined = linear;  // the quadratic has no root there to trust
  return {refined, std::abs(refined - linear)};
}

// Eq. 17.14: the principal axis of J most nearly perpendicular to Π (body frame), the smallest
// moment's (the long axis) first among those more than 60° from it.
Vec3 followed_axis(const Mat3& J, const Vec3& Pi) {
  const Eigen::SelfAdjointEigenSolver<Mat3> principal(J);  // eigenvalues ascending
  const Vec3 spin = Pi.normalized();
  int best = 0;
  for (int c = 0; c < 3; ++c) {
    const double along = std::abs(principal.eigenvectors().col(c).dot(spin));
    if (along < 0.5) return principal.eigenvectors().col(c);
    if (along < std::abs(principal.eigenvectors().col(best).dot(spin))) best = c;
  }
  return principal.eigenvectors().col(best);
}

// The angle of a about the unit k, from u (the coordinate axis least along k, made perpendicular)
// towards k × u.
double angle_about(const Vec3& k, const Vec3& a) {
  Eigen::Index least = 0;
  k.cwiseAbs().minCoeff(&least);
  const Vec3 u = (Vec3::Unit(least) - k[least] * k).normalized();
  return std::atan2(a.dot(k.cross(u)), a.dot(u));
}
}  // namespace

Vec3 orbit_frame_angles(const Vec3& towards_other, const Vec3& orbit_normal, const Mat3& R) {
  Mat3 O;
  O.col(0) = towards_other.normalized();
  O.col(2) = orbit_normal.normalized();
  O.col(1) = O.col(2).cross(O.col(0));
  Vec3 a = euler_angles_321(O.transpose() * R);
  // A Rz(π) = Rz(ψ + π) Ry(−θ) Rx(−φ): the same body turned half a turn about its z axis.
  if (a.x() > kPi / 2 || a.x() <= -kPi / 2) {
    a.x() += a.x() > 0 ? -kPi : kPi;
    a.y() = -a.y();
    a.z() = -a.z();
  }
  return a;
}

Vec3 largest_moment_axis(const Mat3& J) {
  const Eigen::SelfAdjointEigenSolver<Mat3> principal(J);  // eigenvalues ascending
  return principal.eigenvectors().col(2);
}

double nutation_angle(const Vec3& axis, const Vec3& Pi) {
  const double norm = Pi.norm();
  if (!(norm > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::acos(std::clamp(std::abs(axis.dot(Pi)) / norm, 0.0, 1.0));
}

SpinStateTracker::SpinStateTracker(const System& system) : system_(system) {
  const auto pair = binary_pair(system);
  for (std::size_t k = 0; k < system.rigid_count(); ++k) {
    Track t;
    t.body = system.body_of_rigid(k);
    t.axis = largest_moment_axis(system.body(t.body).inertia);
    if (pair && (t.body == pair->primary || t.body == pair->secondary)) {
      t.binary = true;
      t.other = t.body == pair->primary ? pair->secondary : pair->primary;
    }
    tracks_.push_back(t);
  }
}

void SpinStateTracker::start() {
  for (auto& t : tracks_) {
    Track fresh;
    fresh.body = t.body, fresh.other = t.other, fresh.binary = t.binary, fresh.axis = t.axis;
    t = fresh;
  }
}

void SpinStateTracker::observe(const State& state) {
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    Track& t = tracks_[k];
    const Body& body = system_.body(t.body);
    const Vec3 Pi = state.Pi.col(static_cast<Eigen::Index>(k));
    t.nutation = nutation_angle(t.axis, Pi);  // eq. 17.11
    if (!t.seen || !(t.max_nutation >= t.nutation)) t.max_nutation = t.nutation;
    follow_spin(t, state.t, state.R[k], Pi);
    ++t.frames;
    if (!t.binary) {
      t.seen = true;
      continue;
    }
    const auto i = static_cast<Eigen::Index>(t.body), j = static_cast<Eigen::Index>(t.other);
    const Vec3 towards = state.x.col(j) - state.x.col(i);
    const Vec3 v = state.p.col(j) / system_.body(t.other).mass - state.p.col(i) / body.mass;
    const Vec3 normal = towards.cross(v);
    const Mat3& R = state.R[k];
    const Vec3 a = orbit_frame_angles(towards, normal, R);
    // The yaw's rate: the body's spin about the orbit normal less the line of centres' (its
    // angular rate |r × v| / r²), for small pitch and roll.
    const double rate = (R * (body.inertia_inverse * Pi)).dot(normal.normalized()) - normal.norm() / towards.squaredNorm();
    if (!t.seen) {
      t.yaw = t.first = t.low = t.high = a.x();
    } else if (!t.undersampled) {
      // Eq. 17.12: the step of ψ between frames on the nearest branch ψ + kπ — which is the
      // step taken only while the body turns by less than 60° relative to the line of centres
      // between frames. Frames farther apart leave the yaw untracked rather than aliased.
      const double dt = state.t - t.t;
      if (std::max(std::abs(rate), std::abs(t.rate)) * dt > kPi / 3) {
        t.undersampled = true;
      } else {
        double step = a.x() - std::remainder(t.yaw, kPi);
        step -= kPi * std::round(step / kPi);
        t.yaw += step;
        t.low = std::min(t.low, t.yaw);
        t.high = std::max(t.high, t.yaw);
        // Eq. 17.13: ψ̇ changed sign since the last frame — a turning point of the yaw.
        if ((t.rate > 0.0 && rate <= 0.0) || (t.rate < 0.0 && rate >= 0.0)) {
          const Root root = turning_time(t.t_before, t.rate_before, t.t, t.rate, state.t, rate, t.frames >= 3);
          if (t.turning == 0) t.first_turn = root.t, t.first_turn_error = root.error;
          t.last_turn = root.t, t.last_turn_error = root.error;
          ++t.turning;
        }
      }
    }
    t.pitch = std::max(t.seen ? t.pitch : 0.0, std::abs(a.y()));
    t.roll = std::max(t.seen ? t.roll : 0.0, std::abs(a.z()));
    t.t_before = t.t, t.rate_before = t.rate;
    t.rate = rate;
    t.t = state.t;
    t.seen = true;
  }
}

void SpinStateTracker::follow_spin(Track& t, double time, const Mat3& R, const Vec3& Pi) const {
  if (t.spin_undersampled || t.spin_tumbling) return;
  const Body& body = system_.body(t.body);
  if (!t.spinning) {  // the first frame it rotates fixes the axis k and the body axis followed
    if (!(Pi.norm() > 0.0)) return;
    t.spinning = true;
    t.spin_axis = (R * Pi).normalized();
    t.reference = followed_axis(body.inertia, Pi);
    t.spin = t.spin_first = angle_about(t.spin_axis, R * t.reference);
    t.spin_t0 = time;
  } else {
    // The angle on the branch nearest its last value, trusted while the axis turns by less than
    // a third of a turn about k between frames.
    const double angle = angle_about(t.spin_axis, R * t.reference);
    double step = angle - std::remainder(t.spin, 2 * kPi);
    step -= 2 * kPi * std::round(step / (2 * kPi));
    t.spin += step;
  }
  // The projected axis' rate: k · (a × ȧ) / |a⊥|², ȧ = ω × a.
  const Vec3 a = R * t.reference, omega = R * (body.inertia_inverse * Pi);
  const double across = (a - a.dot(t.spin_axis) * t.spin_axis).squaredNorm();
  if (across < 0.25) {  // the axis within 30° of k: its angle about k is no measure of a rotation
    t.spin_tumbling = true;
    return;
  }
  const double rate = t.spin_axis.dot(a.cross(omega.cross(a))) / across;
  if (time > t.spin_t0 && std::max(std::abs(rate), std::abs(t.spin_rate)) * (time - t.spin_t) > 2 * kPi / 3)
    t.spin_undersampled = true;
  t.spin_rate = rate;
  t.spin_t = time;
}

std::vector<SpinState> SpinStateTracker::spin_states() const {
  std::vector<SpinState> out;
  for (const Track& t : tracks_) {
    SpinState s;
    s.body = system_.body(t.body).name;
    if (t.seen) {
      s.max_nutation = t.max_nutation * kDegrees;
      s.nutation = t.nutation * kDegrees;
    }
    s.spin_undersampled = t.spin_undersampled;
    s.spin_tumbling = t.spin_tumbling;
    if (t.spinning && !t.spin_undersampled && !t.spin_tumbling) {  // eq. 17.14
      s.spin_turns = (t.spin - t.spin_first) / (2 * kPi);
      if (std::abs(s.spin_turns) >= 1.0) s.spin_period = (t.spin_t - t.spin_t0) / std::abs(s.spin_turns);
    }
    if (t.binary) {
      s.other = system_.body(t.other).name;
      s.undersampled = t.undersampled;
      if (t.seen && !t.undersampled) {
        s.libration_amplitude = 0.5 * (t.high - t.low) * kDegrees;  // eq. 17.12
        s.turns = (t.yaw - t.first) / (2 * kPi);
        s.max_pitch = t.pitch * kDegrees;
        s.max_roll = t.roll * kDegrees;
        s.turning_points = t.turning;
        // Eq. 17.13, from a whole swing on, for a libration above round-off (ψ̇'s sign is noise
        // for a body at rest in the frame).
        if (t.turning >= 3 && 0.5 * (t.high - t.low) > 1e-9 && 0.5 * (t.high - t.low) <= kPi / 2) {
          s.libration_period = 2.0 * (t.last_turn - t.first_turn) / (t.turning - 1);
          s.libration_period_frames_error = 2.0 * (t.first_turn_error + t.last_turn_error) / (t.turning - 1);
        }
      }
    }
    out.push_back(s);
  }
  return out;
}

std::vector<double> SpinStateTracker::pack() const {
  std::vector<double> out;
  for (const Track& t : tracks_)
    out.insert(out.end(), {t.t, t.yaw, t.first, t.low, t.high, t.rate, t.pitch, t.roll, t.nutation, t.max_nutation,
                           t.seen ? 1.0 : 0.0, t.undersampled ? 1.0 : 0.0, t.t_before, t.rate_before,
                           static_cast<double>(t.frames), static_cast<double>(t.turning), t.first_turn, t.last_turn,
                           t.first_turn_error, t.last_turn_error, t.spin_axis.x(), t.spin_axis.y(), t.spin_axis.z(),
                           t.reference.x(), t.reference.y(), t.reference.z(), t.spin, t.spin_first, t.spin_t0,
                           t.spin_t, t.spin_rate, t.spinning ? 1.0 : 0.0, t.spin_undersampled ? 1.0 : 0.0,
                           t.spin_tumbling ? 1.0 : 0.0});
  return out;
}

void SpinStateTracker::unpack(const std::vector<double>& in) {
  if (in.size() != kPacked * tracks_.size()) return;  // an older file: the spin state starts again
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    Track& t = tracks_[k];
    const double* p = in.data() + kPacked * k;
    t.t = p[0], t.yaw = p[1], t.first = p[2], t.low = p[3], t.high = p[4], t.rate = p[5];
    t.pitch = p[6], t.roll = p[7], t.nutation = p[8], t.max_nutation = p[9];
    t.seen = p[10] != 0.0, t.undersampled = p[11] != 0.0;
    auto count = [](double x) { return x >= 0.0 && x < 2e9 ? static_cast<int>(x) : 0; };  // (a count, as saved)
    t.t_before = p[12], t.rate_before = p[13], t.frames = count(p[14]), t.turning = count(p[15]);
    t.first_turn = p[16], t.last_turn = p[17], t.first_turn_error = p[18], t.last_turn_error = p[19];
    t.spin_axis = Vec3(p[20], p[21], p[22]), t.reference = Vec3(p[23], p[24], p[25]);
    t.spin = p[26], t.spin_first = p[27], t.spin_t0 = p[28], t.spin_t = p[29], t.spin_rate = p[30];
    t.spinning = p[31] != 0.0, t.spin_undersampled = p[32] != 0.0, t.spin_tumbling = p[33] != 0.0;
  }
}

}  // namespace noether
