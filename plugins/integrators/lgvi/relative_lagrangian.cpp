// LGVI, relative frame, Lagrangian form: Lee, Leok & McClamroch 2007 eqs. (112)–(117), our sign of M
// (relative_frame.hpp):
//   F2_k X_{k+1} − 2X_k + F2_{k−1}ᵀ X_{k−1} = −(h²/m) ∂U_k/∂X_k                      (112)
//   F_k JdR_k − JdR_k F_kᵀ = F2_{k−1}ᵀ (F_{k−1} JdR_{k−1} − JdR_{k−1} F_{k−1}ᵀ) F2_{k−1}
//                            + h² S(M_k)                                             (113)
//   F2_k Jd2 − Jd2 F2_kᵀ = Jd2 F2_{k−1} − F2_{k−1}ᵀ Jd2 + h² S(M2_k)                  (114)
//   R_{k+1} = F2_kᵀ F_k R_k,  R2_{k+1} = R2_k F2_k                               (115), (116)
//   x2_{k+1} − 2 x2_k + x2_{k−1} = (h²/m2) R2_k ∂U_k/∂X_k                            (117)
// (113), (114) are Lee et al.'s up to its sign of M, with the sides as the Hamiltonian form
// implies (Lee et al.'s extraction is garbled there). Carried without loss of precision as
//   D_k = X_k − F2_{k−1}ᵀ X_{k−1}:  D_{k+1} = F2_kᵀ (D_k − (h²/m) ∂U_k/∂X),
//                                   X_{k+1} = F2_kᵀ X_k + D_{k+1}                      (112)
//   A_k = F2_{k−1}ᵀ vee(F_{k−1} JdR_{k−1} − JdR_{k−1} F_{k−1}ᵀ):  S(A_k + h² M_k) = F_k JdR_k − …  (113)
//   L2_k = vee(Jd2 F2_{k−1} − F2_{k−1}ᵀ Jd2):  S(L2_k + h² M2_k) = F2_k Jd2 − …     (114)
//   Δ_k = x2_k − x2_{k−1}:  Δ_{k+1} = Δ_k + (h²/m2) R2_k ∂U_k/∂X                      (117)
// with the vee terms evaluated from rotation vectors. The start is the discrete Legendre
// transform of the initial momenta: D_0 = (h/m) Γ_0 + (h²/2m) ∂U_0/∂X, A_0 = h Π_0 − (h²/2) M_0,
// L2_0 = h Π2_0 − (h²/2) M2_0, Δ_0 = (h/m2) γ2_0 − (h²/2m2) R2_0 ∂U_0/∂X. Momenta for output:
//   Γ_k = m D_k/h − (h/2) ∂U_k/∂X,  Π_k = A_k/h + (h/2) M_k,  Π2_k = L2_k/h + (h/2) M2_k,
//   γ2_k = m2 Δ_k/h + (h/2) R2_k ∂U_k/∂X.
// The same map as the Hamiltonian forms' through that transform: it carries the same tangent map
// (RelativeTangent, §21).
//
// Forces beyond the potential, with rates (Γ̇, γ̇2, Π̇, Π̇2)^F of (33.11) at r_k (relative_kicks.hpp):
// the closing kick of step k − 1 and the opening kick of step k push at r_k, so the forced
// equations add h² times them beside the potential's, as the inertial form's (33.10) do:
//   D_{k+1} = F2_kᵀ (D_k + (h²/m)(Γ̇^F_k − ∂U_k/∂X)),   Δ_{k+1} = Δ_k + (h²/m2)(R2_k ∂U_k/∂X + γ̇2^F_k),
//   S(A_k + h² (M_k + Π̇^F_k)) = F_k JdR_k − …,          S(L2_k + h² (M2_k + Π̇2^F_k)) = F2_k Jd2 − …,
// and the Legendre transform's momenta take the closing kick (Γ_k = m D_k/h − (h/2) ∂U_k/∂X +
// (h/2) Γ̇^F_k, the others likewise), implicit when the forces depend on the momenta and solved as
// (33.2). The map is the forced relative Hamiltonian form's through that transform.
#include "relative_kicks.hpp"

#include <noether/error.hpp>

#include <optional>

namespace lgvi {

namespace {

class RelativeLagrangian final : public DiscreteFlow {
 public:
  RelativeLagrangian(const System& system, noether::PotentialEvaluator& evaluate,
                     const Settings& settings)
      : frame_(system, evaluate), evaluate_(evaluate), settings_(settings) {}

  void start(const State& s) override {
    r_ = frame_.reduce(s);
    frame_.evaluate(r_, forces_);
    ++work.potential_evaluations;
    h_ = 0;
    tangent_.start(s, r_, frame_, evaluate_, work);
    if (forcing_) forcing_->start(s, r_);  // the forces at r_0, for the first step
  }

  bool add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    forcing_.emplace(frame_, std::move(forcing));
    return true;
  }

  bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    return tangent_.carry_parameters(std::move(parameters));
  }

  // The reduced variables, then h and the previous step's D, A, L2, Δ (h = 0 before the first).
  std::vector<double> checkpoint() const override {
    std::vector<double> out;
    pack(r_, out);
    out.push_back(h_);
    for (const Vec3* v : {&D_, &A_, &L2_, &Delta_}) out.insert(out.end(), v->data(), v->data() + 3);
    return out;
  }
  std::size_t checkpoint_size() const override { return kReducedSize + 13; }
  void restore(const State& s, const std::vector<double>& data) override {
    if (data.size() != checkpoint_size()) throw noether::Error("lgvi: a relative Lagrangian checkpoint of the wrong size");
    r_ = unpack(data);
    frame_.evaluate(r_, forces_);
    ++work.potential_evaluations;
    const double* p = data.data() + kReducedSize;
    h_ = *p++;
    for (Vec3* v : {&D_, &A_, &L2_, &Delta_}) {
      *v = Vec3(p[0], p[1], p[2]);
      p += 3;
    }
    tangent_.start(s, r_, frame_, evaluate_, work);
    if (forcing_) forcing_->start(s, r_);
  }

  // r_k → r_{k+1}; with forces, on failure the state stays at k.
  void advance(double h, double t_next) override {
    if (!forcing_) return step(h, t_next);
    start_of_step_.keep(r_, forces_, *forcing_, tangent_);
    const double h_before = h_;
    const Vec3 D = D_, A = A_, L2 = L2_, Delta = Delta_;
    try {
      step(h, t_next);
    } catch (...) {
      start_of_step_.restore(r_, forces_, *forcing_, tangent_);
      h_ = h_before, D_ = D, A_ = A, L2_ = L2, Delta_ = Delta;
      throw;
    }
  }

  void current(State& s, Forces& f) const override {
    relative_current(frame_, r_, forces_, tangent_, forcing_ ? &*forcing_ : nullptr, s, f);
  }
  double time() const override { return r_.t; }

 private:
  void step(double h, double t_next) {
    const ReducedForces& fk = forces_;
    // The forces' rates (33.11) at r_k (zero without forces).
    ReducedForcing kf{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    if (forcing_) kf = forcing_->rates(r_);
    if (h_ == 0) {  // the discrete Legendre transform of the initial momenta
      h_ = h;
      D_ = (h / frame_.m) * r_.Gamma + (0.5 * h * h / frame_.m) * (fk.dU_dX - kf.Gamma);
      A_ = h * r_.Pi - 0.5 * h * h * (fk.M + kf.Pi);
      L2_ = h * r_.Pi2 - 0.5 * h * h * (fk.M2 + kf.Pi2);
      Delta_ = (h / frame_.m2) * r_.gamma2 - (0.5 * h * h / frame_.m2) * (r_.R2 * fk.dU_dX + kf.gamma2);
    }
    if (h != h_) throw noether::Error("lgvi: the Lagrangian form needs one fixed step");
    if (forcing_) {
      tangent_.open_kick(forcing_->inertial(), r_, frame_, h);  // (33.6), (33.9)
      forcing_->open(r_, h);  // the opening kick's balance at r_k (33.1), (33.4); r_'s momenta: Π_k + (h/2) Π̇^F_k, …
    }
    const Vec3 g2 = L2_ + h * h * (fk.M2 + kf.Pi2);                                       // (114)
    const Mat3 J2_inverse = frame_.J2.inverse();
    const auto F2 = solve_attitude(g2, frame_.J2, J2_inverse, settings_, frame_.name2, r_.t, h, g2 / h, work);
    const Mat3 JR = r_.R * frame_.J1 * r_.R.transpose();
    const Mat3 JR_inverse = JR.inverse();
    const Vec3 g = A_ + h * h * (fk.M + kf.Pi);                                           // (113)
    const auto F = solve_attitude(g, JR, JR_inverse, settings_, frame_.name1, r_.t, h, g / h, work);
    tangent_.before(r_, fk, F.F, F2.F, h);  // Π_k (kicked) + (h/2) M_k = g/h
    const Mat3 F2t = F2.F.transpose();
    const Vec3 D = F2t * (D_ + (h * h / frame_.m) * (kf.Gamma - fk.dU_dX));              // (112)
    const Vec3 Delta = Delta_ + (h * h / frame_.m2) * (r_.R2 * fk.dU_dX + kf.gamma2);     // (117)
    Reduced next = r_;
    next.t = t_next;
    next.X = F2t * r_.X + D;
    next.R = F2t * F.F * r_.R;   // (115)
    next.R2 = r_.R2 * F2.F;      // (116)
    next.x2 = r_.x2 + Delta;
    ReducedForces f1;
    frame_.evaluate(next, f1);  // on failure nothing has changed
    ++work.potential_evaluations;
    tangent_.at_next(next, frame_, evaluate_, work);
    const Vec3 A = F2t * noether::discrete_attitude_residual_map(F.f, JR);  // F2ᵀ vee(F JdR − JdR Fᵀ)
    const Vec3 L2 = lagrangian_momentum(F2.f, frame_.J2);
    // The discrete Legendre transform at k+1.
    next.Gamma = (frame_.m / h) * D - 0.5 * h * f1.dU_dX;
    next.Pi = A / h + 0.5 * h * f1.M;
    next.Pi2 = L2 / h + 0.5 * h * f1.M2;
    next.gamma2 = (frame_.m2 / h) * Delta + 0.5 * h * (next.R2 * f1.dU_dX);
    tangent_.advance(r_, next, frame_.system(), h);
    r_ = next;
    forces_ = std::move(f1);
    D_ = D;
    A_ = A;
    L2_ = L2;
    Delta_ = Delta;
    if (forcing_) {
      forcing_->close(r_, h);  // the closing kick at r_{k+1} (33.2), (33.11)
      tangent_.close_kick(forcing_->inertial(), r_, frame_, h);  // (33.7), (33.9)
    }
    ++work.steps;
  }

  RelativeFrame frame_;
  noether::PotentialEvaluator& evaluate_;
  Settings settings_;
  double h_ = 0;
  Reduced r_;
  ReducedForces forces_;
  Vec3 D_, A_, L2_, Delta_;
  RelativeTangent tangent_;
  // Forces beyond the potential (none: the conservative map), and the step's start (restored on
  // failure).
  std::optional<RelativeKicks> forcing_;
  RelativeStepStart start_of_step_;
};

}  // namespace

std::unique_ptr<DiscreteFlow> make_relative_lagrangian(const System& s, noether::PotentialEvaluator& p,
                                                      const Settings& settings) {
  return std::make_unique<RelativeLagrangian>(s, p, settings);
}

}  // namespace lgvi
