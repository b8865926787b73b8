// The tangent map of the inertial Hamiltonian LGVI step (docs/equations.md §21).
#include "tangent_map.hpp"

#include <noether/error.hpp>

#include <Eigen/LU>  // Matrix3d::inverse

namespace lgvi {

using noether::Mat3;
using noether::Vec3;

Eigen::MatrixXd advance_tangent(const noether::System& system, double h, const std::vector<Mat3>& F_k,
                                const Eigen::Matrix3Xd& w, const Eigen::MatrixXd& K_k, const Eigen::MatrixXd& K_next,
                                const Eigen::MatrixXd& V, const ParameterStep& ps) {
  const auto n = static_cast<Eigen::Index>(system.size());
  const auto m = static_cast<Eigen::Index>(system.rigid_count());
  const Eigen::Index q = 3 * n + 3 * m;  // configuration rows (δx, δθ); momenta (δγ, δΠ) follow
  // Row blocks of V (21.1): δx [0, 3n), δθ [3n, q), δγ [q, q + 3n), δΠ [q + 3n, 2q).
  const auto dx = V.middleRows(0, 3 * n);
  const auto dtheta = V.middleRows(3 * n, 3 * m);
  const auto dgamma = V.middleRows(q, 3 * n);
  const auto dPi = V.middleRows(q + 3 * n, 3 * m);

  // (δf_k, δM_k) = K_k (δx, δθ)                                                        (21.2)
  // (lazyProduct: coefficient-based products, faster than blocked GEMM at these sizes)
  Eigen::MatrixXd dF_k = K_k.lazyProduct(V.topRows(q));
  // Parameter columns (the last P): the forces' own derivative at z_k, ∂(f_k, M_k)/∂p      (22.3)
  const Eigen::Index P = ps.parameters ? static_cast<Eigen::Index>(ps.parameters->size()) : 0;
  const Eigen::Index first = V.cols() - P;  // the first parameter column
  if (P > 0) dF_k.rightCols(P) += *ps.G_k;
  Eigen::MatrixXd out(V.rows(), V.cols());
  auto dx1 = out.middleRows(0, 3 * n);
  auto dtheta1 = out.middleRows(3 * n, 3 * m);
  auto dgamma1 = out.middleRows(q, 3 * n);
  auto dPi1 = out.middleRows(q + 3 * n, 3 * m);

  // δx_{k+1} = δx_k + (h/m) δγ_k + (h²/2m) δf_k                                         (21.5)
  for (Eigen::Index i = 0; i < n; ++i) {
    const double mass = system.body(static_cast<std::size_t>(i)).mass;
    dx1.middleRows(3 * i, 3) =
        dx.middleRows(3 * i, 3) + (h / mass) * dgamma.middleRows(3 * i, 3) + (0.5 * h * h / mass) * dF_k.middleRows(3 * i, 3);
    // ∂/∂p of 1/m in (94): −(∂m/∂p / m)(x_{k+1} − x_k)                                     (22.4)
    for (Eigen::Index j = 0; j < P; ++j)
      dx1.col(first + j).segment<3>(3 * i) -=
          (ps.parameters->parameters[static_cast<std::size_t>(j)].mass(i) / mass) * ps.displacement->col(i);
  }
  // Each rigid body: δg = h (δΠ_k + (h/2) δM_k) and the variation φ of F_k = exp(S(f)), δF_k = F_k S(φ),
  // from the variation of (93): S(δg) = F_k S(φ) Jd + Jd S(φ) F_kᵀ, i.e. A φ = δg        (21.3)–(21.4)
  std::vector<Eigen::Matrix3Xd> phi(static_cast<std::size_t>(m));
  for (Eigen::Index r = 0; r < m; ++r) {
    const auto& body = system.body(system.body_of_rigid(static_cast<std::size_t>(r)));
    const Mat3& F = F_k[static_cast<std::size_t>(r)];
    const Mat3& Jd = body.inertia_nonstandard;
    Mat3 A;
    for (int c = 0; c < 3; ++c) {
      const Mat3 S = noether::hat(Vec3::Unit(c));
      A.col(c) = noether::vee(F * S * Jd + Jd * S * F.transpose());
    }
    Eigen::Matrix3Xd dg = h * (dPi.middleRows(3 * r, 3) + 0.5 * h * dF_k.middleRows(3 * n + 3 * r, 3));
    // ∂/∂p of Jd in (93): A φ = δg − vee(F_k ∂Jd/∂p − ∂Jd/∂p F_kᵀ)                          (22.5)
    for (Eigen::Index j = 0; j < P; ++j) {
      const Mat3& dJ = ps.parameters->parameters[static_cast<std::size_t>(j)].inertia[static_cast<std::size_t>(r)];
      const Mat3 dJd = 0.5 * dJ.trace() * Mat3::Identity() - dJ;
      dg.col(first + j) -= noether::vee(F * dJd - dJd * F.transpose());
    }
    phi[static_cast<std::size_t>(r)] = A.inverse() * dg;  // 3 × 3: the closed-form inverse
    // δθ_{k+1} = F_kᵀ δθ_k + φ   (R_{k+1} = R_k F_k, (95))                                 (21.6)
    dtheta1.middleRows(3 * r, 3) = F.transpose() * dtheta.middleRows(3 * r, 3) + phi[static_cast<std::size_t>(r)];
  }
  // (δf_{k+1}, δM_{k+1}) = K_{k+1} (δx_{k+1}, δθ_{k+1})
  Eigen::MatrixXd dF_next = K_next.lazyProduct(out.topRows(q));
  if (P > 0) dF_next.rightCols(P) += *ps.G_next;  //                                        (22.3)
  // δγ_{k+1} = δγ_k + (h/2)(δf_k + δf_{k+1})                                            (21.7)
  dgamma1 = dgamma + (0.5 * h) * (dF_k.topRows(3 * n) + dF_next.topRows(3 * n));
  // δΠ_{k+1} = S(F_kᵀ w_k) φ + F_kᵀ (δΠ_k + (h/2) δM_k) + (h/2) δM_{k+1}                  (21.8)
  for (Eigen::Index r = 0; r < m; ++r) {
    const Mat3& F = F_k[static_cast<std::size_t>(r)];
    const Vec3 Fw = F.transpose() * Vec3(w.col(r));
    dPi1.middleRows(3 * r, 3) = noether::hat(Fw) * phi[static_cast<std::size_t>(r)] +
                                F.transpose() * (dPi.middleRows(3 * r, 3) + 0.5 * h * dF_k.middleRows(3 * n + 3 * r, 3)) +
                                0.5 * h * dF_next.middleRows(3 * n + 3 * r, 3);
  }
  return out;
}

void TangentCarrier::evaluate_at(const noether::State& s, noether::PotentialEvaluator& evaluate,
                                 noether::WorkCounters& work, Eigen::MatrixXd& K, Eigen::MatrixXd& G) {
  if (s.tangent.size() == 0) return;
  bool analytic = true;
  K = evaluate.force_jacobian(s, &analytic);
  if (!analytic) work.potential_evaluations += 2 * K.rows();  // a differenced one's evaluations
  if (carries_parameters(s)) {
    work.potential_evaluations += parameter_forces_->evaluations_per_call();
    G = (*parameter_forces_)(s);
  }
}

void TangentCarrier::start(const noether::State& s, noether::PotentialEvaluator& evaluate, noether::WorkCounters& work) {
  if (parameter_forces_ && !parameter_forces_->fits(s.tangent))
    throw noether::Error("lgvi: the tangent has fewer columns than the parameters it carries");
  evaluate_at(s, evaluate, work, K_, G_);
}

void TangentCarrier::at_next(const noether::State& s, noether::PotentialEvaluator& evaluate, noether::WorkCounters& work) {
  evaluate_at(s, evaluate, work, K_next_, G_next_);
}

void TangentCarrier::advance(const noether::System& system, double h, const std::vector<noether::Mat3>& F,
                             const Eigen::Matrix3Xd& w, const Eigen::Matrix3Xd& displacement, Eigen::MatrixXd& V) {
  ParameterStep parameters;
  if (parameter_forces_) parameters = {&parameter_forces_->derivatives(), &G_, &G_next_, &displacement};
  V = advance_tangent(system, h, F, w, K_, K_next_, V, parameters);
  std::swap(K_, K_next_);
  std::swap(G_, G_next_);
}

void TangentCarrier::forcing_parameters_at(const noether::State& s) {
  if (parameter_forces_ && parameter_forces_->has_forcing()) G_forcing_ = parameter_forces_->forcing(s);
}

void TangentCarrier::add_forcing_parameters(double tau, Eigen::MatrixXd& V) const {
  if (G_forcing_.size() == 0 || V.size() == 0) return;
  const Eigen::Index q = G_forcing_.rows();  // δγ, δΠ: V's last q rows, in G^F's row order (21.1)
  V.bottomRows(q).rightCols(G_forcing_.cols()) += tau * G_forcing_;  //                   (33.9)
}

}  // namespace lgvi
