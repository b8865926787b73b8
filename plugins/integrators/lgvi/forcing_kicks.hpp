#pragma once
// The kicks of the forces beyond the potential at the ends of an LGVI step, by the discrete
// Lagrange–d'Alembert principle (Marsden & West 2001, §3.2; docs/equations.md §33): the opening
// kick (33.1) at z_k and the closing kick (33.2) at z_{k+1}, implicit in the momenta, each adding
// its share of the balance (33.4). Shared by the inertial forms: the Hamiltonian form kicks its
// momenta around the conservative map; the Lagrangian form's two-step map takes both kicks at
// x_k in one (its momenta are the discrete Legendre transform's).
#include "discrete_flow.hpp"

#include <noether/force_model.hpp>

#include <memory>

namespace lgvi {

class ForcingKicks {
 public:
  ForcingKicks(const System& system, std::shared_ptr<const noether::Forcing> forcing)
      : evaluate_(system, std::move(forcing)) {}
  noether::ForcingEvaluator& evaluator() { return evaluate_; }
  const Forces& total() const { return evaluate_.total(); }

  // Evaluates the forces at z (those of the next opening kick (33.1)).
  void at(const State& z) { evaluate_(z); }
  // (33.1): γ += (h/2) f^F, Π += (h/2) M^F with the forces last evaluated (at z = s), and the kick's
  // balance (33.4) added to s.force_balance.
  void open(State& s, double h);
  // (33.2) at s = z_{k+1} with its momenta (γ⁻, Π⁻) on entry: γ = γ⁻ + (h/2) f^F(z), Π likewise,
  // iterated until the momenta stand still (bit for bit, or within 8 ulps and then one more
  // evaluation, so that the forces left evaluated are those at z_{k+1} itself); adds the kick's
  // balance. Throws IntegrationError after 50 iterations.
  void close(State& s, double h);

 private:
  noether::ForcingEvaluator evaluate_;
  State kick_from_;
  Eigen::Matrix3Xd trial_p_, trial_Pi_;
};

}  // namespace lgvi
