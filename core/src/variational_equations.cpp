// The variational equations of the inertial Hamiltonian equations (docs/equations.md eq. 21.10).
#include <noether/variational_equations.hpp>

namespace noether {

void variational_rhs(const System& system, const State& state, const Eigen::MatrixXd& K,
                     Eigen::Ref<const Eigen::MatrixXd> V, Eigen::Ref<Eigen::MatrixXd> dV) {
  const auto n = static_cast<Eigen::Index>(system.size());
  const auto m = static_cast<Eigen::Index>(system.rigid_count());
  const Eigen::Index q = 3 * n + 3 * m;
  // (δf, δM) = K (δx, δθ)                                                              (21.2)
  const Eigen::MatrixXd dF = K.lazyProduct(V.topRows(q));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double mass = system.body(static_cast<std::size_t>(i)).mass;
    dV.middleRows(3 * i, 3) = V.middleRows(q + 3 * i, 3) / mass;  // δẋ = δγ/m
    dV.middleRows(q + 3 * i, 3) = dF.middleRows(3 * i, 3);        // δγ̇ = δf
  }
  for (Eigen::Index r = 0; r < m; ++r) {
    const Body& body = system.body(system.body_of_rigid(static_cast<std::size_t>(r)));
    const Vec3 Pi = state.Pi.col(r);
    const Vec3 Omega = body.inertia_inverse * Pi;
    const auto dtheta = V.middleRows(3 * n + 3 * r, 3);
    const auto dPi = V.middleRows(q + 3 * n + 3 * r, 3);
    const Eigen::Matrix3Xd dOmega = body.inertia_inverse * dPi;
    // δθ̇ = δΩ − Ω × δθ (from δṘ = δR S(Ω) + R S(δΩ) with δR = R S(δθ))
    dV.middleRows(3 * n + 3 * r, 3) = dOmega - hat(Omega) * dtheta;
    // δΠ̇ = δΠ × Ω + Π × δΩ + δM
    dV.middleRows(q + 3 * n + 3 * r, 3) = -hat(Omega) * dPi + hat(Pi) * dOmega + dF.middleRows(3 * n + 3 * r, 3);
  }
}

void add_forcing_tangent(const System& system, const Eigen::MatrixXd& KF, double tau,
                         Eigen::Ref<const Eigen::MatrixXd> V, Eigen::Ref<Eigen::MatrixXd> out) {
  const auto n = static_cast<Eigen::Index>(system.size()), m = static_cast<Eigen::Index>(system.rigid_count());
  const Eigen::MatrixXd KV = KF * V;  // before `out` (perhaps V) changes
  out.middleRows(3 * n + 3 * m, 3 * n) += tau * KV.topRows(3 * n);  // δγ: δf^F
  out.middleRows(6 * n + 3 * m, 3 * m) += tau * KV.bottomRows(3 * m);  // δΠ: δM^F (body frame)
}

}  // namespace noether
