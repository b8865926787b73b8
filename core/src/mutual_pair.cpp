#include <noether/mutual_pair.hpp>

#include <vector>

namespace noether {

PairFrame pair_frame(const State& s, const MutualPair& p) {
  PairFrame f;
  f.Ra = p.rigid_a >= 0 ? s.R[static_cast<std::size_t>(p.rigid_a)] : Mat3::Identity();
  f.Rb = p.rigid_b >= 0 ? s.R[static_cast<std::size_t>(p.rigid_b)] : Mat3::Identity();
  f.R = f.Ra.transpose() * (s.x.col(static_cast<Eigen::Index>(p.b)) - s.x.col(static_cast<Eigen::Index>(p.a)));
  f.C = f.Ra.transpose() * f.Rb;
  return f;
}

PairShare pair_share(const PairFrame& frame, const MutualTerms& t) {
  PairShare s;
  s.U = t.U;
  s.f_a = frame.Ra * t.dU_dR;  // the force on a (13.7)
  s.M_a = t.torque_A;
  s.M_b = frame.C.transpose() * t.torque_B;
  return s;
}

void add_pair_share(const MutualPair& p, const PairShare& share, Forces& out) {
  out.U += share.U;
  out.f.col(static_cast<Eigen::Index>(p.a)) += share.f_a;
  out.f.col(static_cast<Eigen::Index>(p.b)) -= share.f_a;
  if (p.rigid_a >= 0) out.M.col(p.rigid_a) += share.M_a;
  if (p.rigid_b >= 0) out.M.col(p.rigid_b) += share.M_b;
}

void add_mutual_terms(const MutualPair& p, const PairFrame& frame, const MutualTerms& t, Forces& out) {
  add_pair_share(p, pair_share(frame, t), out);
}

void add_mutual_jacobian(const MutualPair& p, const PairFrame& frame, const MutualTerms& t, const MutualJacobian& J,
                         std::size_t n, Eigen::MatrixXd& K) {
  using Eigen::Index;
  const Index xa = 3 * static_cast<Index>(p.a), xb = 3 * static_cast<Index>(p.b);
  const Index N = 3 * static_cast<Index>(n);
  const Mat3 Ct = frame.C.transpose();
  // Each variable moves the pair's R (A's frame) and turns B about its centre in A's axes (φ),
  // (25.6): δR = R_aᵀ(δx_b − δx_a) + S(R) θ_a,  δφ = C θ_b − θ_a.
  struct Variable {
    Index column;
    Mat3 dR, dphi;
    bool theta_a, theta_b;
  };
  std::vector<Variable> variables = {{xa, -frame.Ra.transpose(), Mat3::Zero(), false, false},
                                     {xb, frame.Ra.transpose(), Mat3::Zero(), false, false}};
  if (p.rigid_a >= 0) variables.push_back({N + 3 * p.rigid_a, hat(frame.R), -Mat3::Identity(), true, false});
  if (p.rigid_b >= 0) variables.push_back({N + 3 * p.rigid_b, Mat3::Zero(), frame.C, false, true});
  for (const Variable& v : variables) {
    // f_a = R_a g: δf_a = R_a (δg + θ_a × g); f_b = −f_a.
    Mat3 df = frame.Ra * (J.g_R * v.dR + J.g_phi * v.dphi);
    if (v.theta_a) df -= frame.Ra * hat(t.dU_dR);
    K.block<3, 3>(xa, v.column) += df;
    K.block<3, 3>(xb, v.column) -= df;
    // M_a = τ_A (A's body frame).
    if (p.rigid_a >= 0) K.block<3, 3>(N + 3 * p.rigid_a, v.column) += J.tauA_R * v.dR + J.tauA_phi * v.dphi;
    // M_b = Cᵀ τ_B: C → (I − S(θ_a)) C and C (I + S(θ_b)) turn Cᵀ τ_B too.
    if (p.rigid_b >= 0) {
      Mat3 dM = Ct * (J.tauB_R * v.dR + J.tauB_phi * v.dphi);
      if (v.theta_a) dM -= Ct * hat(t.torque_B);
      if (v.theta_b) dM += hat(Ct * t.torque_B);
      K.block<3, 3>(N + 3 * p.rigid_b, v.column) += dM;
    }
  }
}

}  // namespace noether
