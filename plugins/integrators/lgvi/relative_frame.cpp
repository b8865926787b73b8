#include "relative_frame.hpp"

#include "forcing_kicks.hpp"

#include <noether/error.hpp>

namespace lgvi {

RelativeFrame::RelativeFrame(const System& system, noether::PotentialEvaluator& evaluate)
    : system_(system), evaluate_(evaluate) {
  if (system.size() != 2 || system.rigid_count() != 2)
    throw noether::SceneError(
        "lgvi: frame: relative needs exactly two rigid bodies (the full two-body problem of "
        "Lee, Leok & McClamroch 2007 §4.2); this scene has " + std::to_string(system.size()) + " bodies, " +
        std::to_string(system.rigid_count()) + " rigid. Use frame: inertial");
  const auto& b1 = system.body(0);
  const auto& b2 = system.body(1);
  m1 = b1.mass;
  m2 = b2.mass;
  m = m1 * m2 / (m1 + m2);
  J1 = b1.inertia;
  J2 = b2.inertia;
  Jd2 = b2.inertia_nonstandard;
  name1 = b1.name;
  name2 = b2.name;
  canonical_ = State::zeros(system);
}

void pack(const Reduced& r, std::vector<double>& out) {
  out.push_back(r.t);
  for (const Vec3* v : {&r.X, &r.Gamma, &r.Pi, &r.Pi2, &r.x2, &r.gamma2}) out.insert(out.end(), v->data(), v->data() + 3);
  for (const Mat3* m : {&r.R, &r.R2}) out.insert(out.end(), m->data(), m->data() + 9);
}

Reduced unpack(const std::vector<double>& in, std::size_t offset) {
  if (in.size() < offset + kReducedSize) throw noether::Error("lgvi: a relative-frame checkpoint of the wrong size");
  Reduced r;
  const double* p = in.data() + offset;
  r.t = *p++;
  for (Vec3* v : {&r.X, &r.Gamma, &r.Pi, &r.Pi2, &r.x2, &r.gamma2}) {
    *v = Vec3(p[0], p[1], p[2]);
    p += 3;
  }
  for (Mat3* m : {&r.R, &r.R2}) {
    *m = Eigen::Map<const Mat3>(p);
    p += 9;
  }
  return r;
}

Reduced RelativeFrame::reduce(const State& s) const {
  Reduced r;
  r.t = s.t;
  r.x2 = s.x.col(1);
  r.gamma2 = s.p.col(1);
  r.R2 = s.R[1];
  const Mat3 R2t = r.R2.transpose();
  r.X = R2t * Vec3(s.x.col(0) - s.x.col(1));
  r.Gamma = m * (R2t * Vec3(s.p.col(0) / m1 - s.p.col(1) / m2));
  r.R = R2t * s.R[0];
  r.Pi = r.R * Vec3(s.Pi.col(0));
  r.Pi2 = s.Pi.col(1);
  return r;
}

void RelativeFrame::reconstruct(const Reduced& r, State& s) const {
  s.t = r.t;
  s.x.resize(3, 2);
  s.p.resize(3, 2);
  s.R.resize(2);
  s.Pi.resize(3, 2);
  s.x.col(1) = r.x2;
  s.p.col(1) = r.gamma2;
  s.R[1] = r.R2;
  s.x = positions(r);                                                // x1 = x2 + R2 X
  s.p.col(0) = m1 * (r.gamma2 / m2 + r.R2 * r.Gamma / m);            // v1 = v2 + R2 Γ/m
  s.R[0] = r.R2 * r.R;                                               // R1 = R2 R
  s.Pi.col(0) = r.R.transpose() * r.Pi;                              // Π1 = Rᵀ Π
  s.Pi.col(1) = r.Pi2;
}

Eigen::Matrix3Xd RelativeFrame::positions(const Reduced& r) {
  Eigen::Matrix3Xd x(3, 2);
  x.col(0) = r.x2 + r.R2 * r.X;
  x.col(1) = r.x2;
  return x;
}

void RelativeFrame::evaluate(const Reduced& r, ReducedForces& f) {
  canonical_.t = r.t;
  canonical_.x.col(0) = r.X;
  canonical_.x.col(1).setZero();
  canonical_.R[0] = r.R;
  canonical_.R[1].setIdentity();
  if (f.inertial.f.cols() != 2) f.inertial.resize(system_);
  evaluate_(canonical_, f.inertial);
  f.U = f.inertial.U;
  f.dU_dX = -f.inertial.f.col(0);   // with R2 = I, f1 = −∂U/∂X
  f.M = r.R * Vec3(f.inertial.M.col(0));
  // M2 = X × ∂U/∂X − M (124). The potential's own moment on body 2 (at R2 = I its body frame is
  // the canonical frame) is the same quantity evaluated without the cancellation of the
  // nearly parallel X and ∂U/∂X, which would cost about three digits on the dumbbell scene.
  f.M2 = f.inertial.M.col(1);
}

void RelativeFrame::inertial_forces(const Reduced& r, const ReducedForces& rf, Forces& f) const {
  if (f.f.cols() != 2) f.resize(system_);
  f.U = rf.U;
  f.f.col(0) = -(r.R2 * rf.dU_dX);
  f.f.col(1) = r.R2 * rf.dU_dX;
  f.M.col(0) = r.R.transpose() * rf.M;  // M1, body-1 frame
  f.M.col(1) = rf.M2;
}

void RelativeTangent::start(const State& s, const Reduced& r, const RelativeFrame& frame,
                            noether::PotentialEvaluator& evaluate, noether::WorkCounters& work) {
  V_ = s.tangent;
  if (!carried()) return;
  frame.reconstruct(r, inertial_);
  inertial_.tangent = V_;
  carrier_.start(inertial_, evaluate, work);
}

void RelativeTangent::before(const Reduced& r, const ReducedForces& fk, const Mat3& F, const Mat3& F2, double h) {
  if (!carried()) return;
  // R1 = R2 R and R1_{k+1} = R2_k F2 R_{k+1} = R2_k F R_k (122), so F1 = R1_kᵀ R1_{k+1} = R_kᵀ F R_k.
  F_[0] = r.R.transpose() * F * r.R;
  F_[1] = F2;
  // w_k = Π_k + (h/2) M_k in each body's frame: Π = R Π1 and M = R M1 for body 1.
  w_.col(0) = r.R.transpose() * (r.Pi + 0.5 * h * fk.M);
  w_.col(1) = r.Pi2 + 0.5 * h * fk.M2;
}

void RelativeTangent::at_next(const Reduced& next, const RelativeFrame& frame, noether::PotentialEvaluator& evaluate,
                              noether::WorkCounters& work) {
  if (!carried()) return;
  frame.reconstruct(next, inertial_);
  inertial_.tangent = V_;
  carrier_.at_next(inertial_, evaluate, work);
}

void RelativeTangent::advance(const Reduced& r_k, const Reduced& next, const System& system, double h) {
  if (!carried()) return;
  carrier_.advance(system, h, F_, w_, RelativeFrame::positions(next) - RelativeFrame::positions(r_k), V_);
}

void RelativeTangent::open_kick(ForcingKicks& kicks, const Reduced& r, const RelativeFrame& frame, double h) {
  if (!carried()) return;
  frame.reconstruct(r, inertial_);
  kicks.open_tangent(inertial_, h, carrier_, V_);
}

void RelativeTangent::close_kick(ForcingKicks& kicks, const Reduced& r, const RelativeFrame& frame, double h) {
  if (!carried()) return;
  frame.reconstruct(r, inertial_);
  kicks.close_tangent(inertial_, h, carrier_, V_);
}

}  // namespace lgvi
