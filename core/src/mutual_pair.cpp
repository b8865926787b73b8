#include <noether/mutual_pair.hpp>

namespace noether {

PairFrame pair_frame(const State& s, const MutualPair& p) {
  PairFrame f;
  f.Ra = p.rigid_a >= 0 ? s.R[static_cast<std::size_t>(p.rigid_a)] : Mat3::Identity();
  f.Rb = p.rigid_b >= 0 ? s.R[static_cast<std::size_t>(p.rigid_b)] : Mat3::Identity();
  f.R = f.Ra.transpose() * (s.x.col(static_cast<Eigen::Index>(p.b)) - s.x.col(static_cast<Eigen::Index>(p.a)));
  f.C = f.Ra.transpose() * f.Rb;
  return f;
}

void add_mutual_terms(const MutualPair& p, const PairFrame& frame, const MutualTerms& t, Forces& out) {
  out.U += t.U;
  const Vec3 f = frame.Ra * t.dU_dR;  // the force on a (13.7)
  out.f.col(static_cast<Eigen::Index>(p.a)) += f;
  out.f.col(static_cast<Eigen::Index>(p.b)) -= f;
  if (p.rigid_a >= 0) out.M.col(p.rigid_a) += t.torque_A;
  if (p.rigid_b >= 0) out.M.col(p.rigid_b) += frame.C.transpose() * t.torque_B;
}

}  // namespace noether
