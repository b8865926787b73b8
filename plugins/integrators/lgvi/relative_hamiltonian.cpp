// LGVI, relative frame, Hamiltonian form: Lee, Leok & McClamroch 2007 eqs. (118)–(124), with the reconstruction
// of body 2's inertial motion (125)–(127) (docs/equations.md §5). Derived here by reducing (93)–(97) by
// the symmetry U(x1, x2, R1, R2) = U(X, R), so that it reproduces the inertial trajectory for
// the same h up to round-off; our M is the negative of Lee et al.'s relative M (see
// relative_frame.hpp):
//   h S(Π2_k + (h/2) M2_k) = F2_k Jd2 − Jd2 F2_kᵀ                                   (124)
//   h S(Π_k + (h/2) M_k)   = F_k JdR_k − JdR_k F_kᵀ,  JdR = R Jd1 Rᵀ                  (123)
//   X_{k+1} = F2_kᵀ (X_k + (h/m) Γ_k − (h²/2m) ∂U_k/∂X)                             (118)
//   R_{k+1} = F2_kᵀ F_k R_k                                                          (122)
//   Γ_{k+1} = F2_kᵀ (Γ_k − (h/2) ∂U_k/∂X) − (h/2) ∂U_{k+1}/∂X                       (119)
//   Π_{k+1} = F2_kᵀ (Π_k + (h/2) M_k) + (h/2) M_{k+1}                                (120)
//   Π2_{k+1} = F2_kᵀ (Π2_k + (h/2) M2_k) + (h/2) M2_{k+1}                            (121)
//   x2_{k+1} = x2_k + (h/m2) γ2_k + (h²/2m2) R2_k ∂U_k/∂X                            (125)
//   γ2_{k+1} = γ2_k + (h/2) (R2_k ∂U_k/∂X + R2_{k+1} ∂U_{k+1}/∂X)                     (126)
//   R2_{k+1} = R2_k F2_k                                                             (127)
// F_k = R_k F1_k R_kᵀ is body 1's F seen from body 2; (123) is (128) with J → R J1 Rᵀ. The same
// map as the inertial form's, so it carries the same tangent map (RelativeTangent, §21).
//
// Forces beyond the potential: the kicks (33.1)–(33.2) in the reduced momenta (33.11) around
// that map (relative_kicks.hpp) — the forced inertial Hamiltonian form's map in these variables.
#include "relative_kicks.hpp"

#include <optional>

namespace lgvi {

namespace {

class RelativeHamiltonian final : public DiscreteFlow {
 public:
  RelativeHamiltonian(const System& system, noether::PotentialEvaluator& evaluate,
                      const Settings& settings)
      : frame_(system, evaluate), evaluate_(evaluate), settings_(settings) {}

  void start(const State& s) override {
    r_ = frame_.reduce(s);
    evaluate(r_, current_);
    tangent_.start(s, r_, frame_, evaluate_, work);
    if (forcing_) forcing_->start(s, r_);  // the forces of the first opening kick (33.1)
  }

  bool add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    forcing_.emplace(frame_, std::move(forcing));
    return true;
  }

  bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    return tangent_.carry_parameters(std::move(parameters));
  }

  // r_k → r_{k+1}; on failure the state stays at k.
  void advance(double h, double t_next) override {
    if (!forcing_) return conservative_step(h, t_next);
    start_of_step_.keep(r_, current_, *forcing_, tangent_);
    try {
      tangent_.open_kick(forcing_->inertial(), r_, frame_, h);  // (33.6), (33.9)
      forcing_->open(r_, h);                                     // (33.1), (33.11)
      conservative_step(h, t_next);
      forcing_->close(r_, h);                                    // (33.2), (33.11)
      tangent_.close_kick(forcing_->inertial(), r_, frame_, h);  // (33.7), (33.9)
    } catch (...) {
      start_of_step_.restore(r_, current_, *forcing_, tangent_);
      throw;
    }
  }

  void current(State& s, Forces& f) const override {
    relative_current(frame_, r_, current_, tangent_, forcing_ ? &*forcing_ : nullptr, s, f);
  }
  double time() const override { return r_.t; }
  // The reduced variables themselves: reduce(reconstruct(r)) is r only up to rounding.
  std::vector<double> checkpoint() const override {
    std::vector<double> out;
    pack(r_, out);
    return out;
  }
  std::size_t checkpoint_size() const override { return kReducedSize; }
  void restore(const State& s, const std::vector<double>& data) override {
    r_ = unpack(data);
    evaluate(r_, current_);
    tangent_.start(s, r_, frame_, evaluate_, work);
    if (forcing_) forcing_->start(s, r_);
  }

 private:
  // The conservative map (118)–(127) from r_ (its momenta kicked, with forces).
  void conservative_step(double h, double t_next) {
    const ReducedForces& fk = current_;
    const Mat3 J2_inverse = frame_.J2.inverse();
    const Mat3 F2 = solve_attitude(h * (r_.Pi2 + 0.5 * h * fk.M2), frame_.J2, J2_inverse, settings_, frame_.name2,
                                   r_.t, h, r_.Pi2, work).F;                 // (124)
    const Mat3 JR = r_.R * frame_.J1 * r_.R.transpose();
    const Mat3 JR_inverse = JR.inverse();
    const Mat3 F = solve_attitude(h * (r_.Pi + 0.5 * h * fk.M), JR, JR_inverse, settings_, frame_.name1, r_.t, h,
                                  r_.Pi, work).F;                            // (123)
    tangent_.before(r_, fk, F, F2, h);
    Reduced next = r_;
    next.t = t_next;
    next.X = F2.transpose() * (r_.X + (h / frame_.m) * r_.Gamma - (0.5 * h * h / frame_.m) * fk.dU_dX);  // (118)
    next.R = F2.transpose() * F * r_.R;                                                   // (122)
    next.x2 = r_.x2 + (h / frame_.m2) * r_.gamma2 + (0.5 * h * h / frame_.m2) * (r_.R2 * fk.dU_dX);  // (125)
    next.R2 = r_.R2 * F2;                                                                 // (127)
    evaluate(next, next_);  // on failure r_ is untouched
    tangent_.at_next(next, frame_, evaluate_, work);
    const ReducedForces& f1 = next_;
    next.Gamma = F2.transpose() * (r_.Gamma - 0.5 * h * fk.dU_dX) - 0.5 * h * f1.dU_dX;   // (119)
    next.Pi = F2.transpose() * (r_.Pi + 0.5 * h * fk.M) + 0.5 * h * f1.M;                 // (120)
    next.Pi2 = F2.transpose() * (r_.Pi2 + 0.5 * h * fk.M2) + 0.5 * h * f1.M2;             // (121)
    next.gamma2 = r_.gamma2 + 0.5 * h * (r_.R2 * fk.dU_dX + next.R2 * f1.dU_dX);          // (126)
    tangent_.advance(r_, next, frame_.system(), h);
    r_ = next;
    std::swap(current_, next_);
    ++work.steps;
  }

  void evaluate(const Reduced& r, ReducedForces& f) {
    frame_.evaluate(r, f);
    ++work.potential_evaluations;
  }

  RelativeFrame frame_;
  noether::PotentialEvaluator& evaluate_;
  Settings settings_;
  Reduced r_;
  ReducedForces current_, next_;
  RelativeTangent tangent_;
  // Forces beyond the potential (none: the conservative map alone), and the step's start
  // (restored on failure).
  std::optional<RelativeKicks> forcing_;
  RelativeStepStart start_of_step_;
};

}  // namespace

std::unique_ptr<DiscreteFlow> make_relative_hamiltonian(const System& s, noether::PotentialEvaluator& p,
                                                       const Settings& settings) {
  return std::make_unique<RelativeHamiltonian>(s, p, settings);
}

}  // namespace lgvi
