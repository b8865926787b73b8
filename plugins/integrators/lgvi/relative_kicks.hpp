#pragma once
// Forces beyond the potential in the relative frame (docs/equations.md (33.11)): the kicks
// (33.1)–(33.2) of the inertial forms, in the reduced momenta. A kick moves the momenta alone, at
// a fixed configuration, and the reduced momenta are linear in the inertial ones
// (relative_frame.hpp), so the inertial kick (Δγ_i, ΔΠ_i) = τ (f^F_i, M^F_i) is
//   ΔΓ = τ m R2ᵀ (f^F_1/m1 − f^F_2/m2),  Δγ2 = τ f^F_2,  ΔΠ = τ R M^F_1,  ΔΠ2 = τ M^F_2   (33.11)
// with the forces evaluated at the reconstructed inertial state. Applied in these variables, not
// by reducing a kicked inertial state, so that the relative motion keeps its precision when the
// pair's barycentre moves fast (a binary about the Sun). The relative Hamiltonian form between
// these kicks is the forced inertial Hamiltonian form's map in the reduced variables, as
// (118)–(127) are (93)–(97); the relative Lagrangian form takes h² times them into its two-step
// equations, as the inertial one does (33.10). Internal forces (tides) and external ones (the Sun,
// a flyby, radiation) alike: the reduction changes the variables, not the dynamics, and body 2's
// inertial (x2, γ2, R2) carries what an external force does to the pair as a whole.
#include "forcing_kicks.hpp"
#include "relative_frame.hpp"

namespace lgvi {

// The forces' rates of the reduced momenta (33.11): Γ̇ = m R2ᵀ(f1/m1 − f2/m2), γ̇2 = f2, Π̇ = R M1, Π̇2 = M2.
struct ReducedForcing {
  Vec3 Gamma, gamma2, Pi, Pi2;
};

class RelativeKicks {
 public:
  RelativeKicks(const RelativeFrame& frame, std::shared_ptr<const noether::Forcing> forcing);
  ForcingKicks& inertial() { return kicks_; }

  // At a start or a restore: the balance `s` carries (checked against the forces), and the forces at r.
  void start(const State& s, const Reduced& r);
  // The balance (33.4) of the kicks so far (State::force_balance), and setting it back (a failed step).
  const Eigen::MatrixXd& balance() const { return balance_; }
  void set_balance(const Eigen::MatrixXd& balance) { balance_ = balance; }

  // Evaluates the forces at r's inertial state.
  void at(const Reduced& r);
  // The rates (33.11) of the forces last evaluated, at r's configuration.
  ReducedForcing rates(const Reduced& r) const;
  // (33.1) in the reduced momenta, with the forces last evaluated (at r), and its balance.
  void open(Reduced& r, double h);
  // (33.2) at r = r_{k+1} with its momenta before the kick on entry, by solve_closing_kick; the
  // forces are left evaluated at r_{k+1} itself; adds the kick's balance.
  void close(Reduced& r, double h);

 private:
  void kick(Reduced& r, const ReducedForcing& rate, double tau) const;
  // The kick's balance (33.4), from the inertial states before and after it.
  void add_balance(const Reduced& before, const Reduced& after, double tau);

  const RelativeFrame& frame_;
  ForcingKicks kicks_;
  Eigen::MatrixXd balance_;
  State z_, before_, after_;  // scratch: reconstructed inertial states
  Reduced kick_from_;
  Eigen::Matrix3Xd y_ = Eigen::Matrix3Xd(3, 4), trial_ = Eigen::Matrix3Xd(3, 4);  // (Γ, γ2, Π, Π2)
};

// The start of a forced relative step, kept so that a failed step leaves the flow where it was:
// the reduced state, the potential's forces there, the balance and the tangent.
class RelativeStepStart {
 public:
  void keep(const Reduced& r, const ReducedForces& forces, const RelativeKicks& kicks, const RelativeTangent& tangent);
  // Sets them back, and the forces beyond the potential evaluated at r again.
  void restore(Reduced& r, ReducedForces& forces, RelativeKicks& kicks, RelativeTangent& tangent) const;

 private:
  Reduced r_;
  ReducedForces forces_;
  Eigen::MatrixXd balance_, tangent_;
};

// DiscreteFlow::current of a relative form: r's inertial state, with the tangent and (when there
// are forces beyond the potential) their balance, and the potential's inertial forces.
void relative_current(const RelativeFrame& frame, const Reduced& r, const ReducedForces& forces,
                      const RelativeTangent& tangent, const RelativeKicks* kicks, State& s, Forces& f);

}  // namespace lgvi
