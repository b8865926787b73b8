#pragma once
// The kicks of the forces beyond the potential at the ends of an LGVI step, by the discrete
// Lagrange–d'Alembert principle (Marsden & West 2001, §3.2; docs/equations.md §33): the opening
// kick (33.1) at z_k and the closing kick (33.2) at z_{k+1}, implicit in the momenta, each adding
// its share of the balance (33.4), and their tangent maps (33.6)–(33.7), (33.9). Shared by every
// form: the inertial Hamiltonian form kicks its momenta around the conservative map; the inertial
// Lagrangian form's two-step map takes both kicks at x_k in one (its momenta are the discrete
// Legendre transform's); the relative forms kick their reduced momenta (relative_kicks.hpp)
// through the same closing-kick iteration (solve_closing_kick).
#include "discrete_flow.hpp"
#include "tangent_map.hpp"

#include <noether/force_model.hpp>

#include <algorithm>
#include <limits>
#include <memory>

namespace lgvi {

// Throws the IntegrationError of a closing kick that did not converge (at time t, step h).
[[noreturn]] void closing_kick_failed(double t, double h, double change);

// The closing kick (33.2) in momenta y, a body's vector per column: y = y⁻ + (h/2) K(y), solved by
// fixed-point iteration from y = y⁻ (y on entry) until y stands still — bit for bit, or within
// 8 ulps. `kick(y, out)` evaluates the forces with momenta y and writes y⁻ + (h/2) K(y) to `out`
// (`trial`, scratch). Returns true when y moved by its last iteration (within 8 ulps): the forces
// last evaluated are then at the previous y, and the caller, once it has added the kick's balance
// from them, evaluates them once more at y itself. Forces that do not depend on the momenta
// (`depends_on_momenta` false) take one evaluation. Throws after 50 iterations.
template <class Kick>
bool solve_closing_kick(Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& trial, bool depends_on_momenta, Kick&& kick, double t,
                        double h) {
  const double eps = std::numeric_limits<double>::epsilon();
  for (int iteration = 0;; ++iteration) {
    kick(y, trial);
    if (!depends_on_momenta || trial == y) {
      y = trial;
      return false;
    }
    double change = 0.0;  // the largest change of a body's momentum, relative to it
    for (Eigen::Index i = 0; i < y.cols(); ++i)
      change = std::max(change, (trial.col(i) - y.col(i)).norm() / std::max(trial.col(i).norm(), 1e-300));
    y = trial;
    if (change <= 8 * eps) return true;
    if (iteration == 50) closing_kick_failed(t, h, change);
  }
}

class ForcingKicks {
 public:
  ForcingKicks(const System& system, std::shared_ptr<const noether::Forcing> forcing)
      : system_(system), evaluate_(system, std::move(forcing)) {}
  noether::ForcingEvaluator& evaluator() { return evaluate_; }
  const Forces& total() const { return evaluate_.total(); }

  // Evaluates the forces at z (those of the next opening kick (33.1)).
  void at(const State& z) { evaluate_(z); }
  // (33.1): γ += (h/2) f^F, Π += (h/2) M^F with the forces last evaluated (at z = s), and the kick's
  // balance (33.4) added to s.force_balance.
  void open(State& s, double h);
  // (33.2) at s = z_{k+1} with its momenta (γ⁻, Π⁻) on entry: γ = γ⁻ + (h/2) f^F(z), Π likewise,
  // by solve_closing_kick, so that the forces left evaluated are those at z_{k+1} itself; adds
  // the kick's balance.
  void close(State& s, double h);

  // The kicks' tangent maps, V with 6n + 6m rows (21.1) and the carrier's parameters (33.9):
  // at z_k, before (33.1), V ← (I + (h/2) B K^F(z_k)) V [+ (h/2) B G^F(z_k)]            (33.6)
  // at z_{k+1}, after (33.2), V ← (I − (h/2) B K^F(z_{k+1}))⁻¹ (V [+ (h/2) B G^F(z_{k+1})])  (33.7)
  // K^F(z_{k+1}) and G^F(z_{k+1}) are kept for the next step's opening kick until forget_tangent()
  // (a start, a restore, a failed step).
  void open_tangent(const State& z, double h, TangentCarrier& carrier, Eigen::MatrixXd& V);
  void close_tangent(const State& z, double h, TangentCarrier& carrier, Eigen::MatrixXd& V);
  void forget_tangent() { jacobian_valid_ = false; }

 private:
  const System system_;
  noether::ForcingEvaluator evaluate_;
  State kick_from_;
  Eigen::Matrix3Xd y_, trial_;
  // The tangent's: the forces' Jacobian (valid: at the current state, from the last closing kick)
  // and the closing kick's matrix.
  Eigen::MatrixXd jacobian_, closing_;
  bool jacobian_valid_ = false;
};

}  // namespace lgvi
