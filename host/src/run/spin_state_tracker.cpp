// The spin state of each rigid body over a run: docs/equations.md eqs. 17.10–17.12.
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
constexpr std::size_t kPacked = 12;  // numbers per rigid body in pack()
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
      }
    }
    t.pitch = std::max(t.seen ? t.pitch : 0.0, std::abs(a.y()));
    t.roll = std::max(t.seen ? t.roll : 0.0, std::abs(a.z()));
    t.rate = rate;
    t.t = state.t;
    t.seen = true;
  }
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
    if (t.binary) {
      s.other = system_.body(t.other).name;
      s.undersampled = t.undersampled;
      if (t.seen && !t.undersampled) {
        s.libration_amplitude = 0.5 * (t.high - t.low) * kDegrees;  // eq. 17.12
        s.turns = (t.yaw - t.first) / (2 * kPi);
        s.max_pitch = t.pitch * kDegrees;
        s.max_roll = t.roll * kDegrees;
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
                           t.seen ? 1.0 : 0.0, t.undersampled ? 1.0 : 0.0});
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
  }
}

}  // namespace noether
