// LGVI, inertial frame, Lagrangian form: Lee, Leok & McClamroch 2007 eqs. (78)–(80),
//   (m/h)(x_{k+1} − 2x_k + x_{k−1}) = −h ∂U_k/∂x_k                                    (78)
//   (1/h)(F_k Jd − Jd F_kᵀ − Jd F_{k−1} + F_{k−1}ᵀ Jd) = h S(M_k)                      (79)
//   R_{k+1} = R_k F_k                                                                  (80)
// a two-step map on (x_{k−1}, R_{k−1}, x_k, R_k). Carried, with no loss of precision, as
//   D_k = x_k − x_{k−1}:     D_{k+1} = D_k − (h²/m) ∂U_k/∂x,  x_{k+1} = x_k + D_{k+1}     (78)
//   L_k = vee(Jd F_{k−1} − F_{k−1}ᵀ Jd):  S(L_k + h² M_k) = F_k Jd − Jd F_kᵀ          (79)
// with L evaluated from F's rotation vector (lagrangian_momentum), not from the matrices.
// The start (x_0, R_0, x_1, R_1) is the discrete Legendre transform of the initial momenta:
// D_0 = (h/m) γ_0 + (h²/2m) ∂U_0/∂x, L_0 = h Π_0 − (h²/2) M_0 make the first step give
// x_1, R_1 of (94)–(95). Momenta for output (discrete Legendre transform):
//   γ_k = m D_k/h − (h/2) ∂U_k/∂x,   Π_k = L_k/h + (h/2) M_k.
// Through that transform the map z_k → z_{k+1} on (x, R, γ, Π) is the Hamiltonian form's (94)–(97),
// with w_k = Π_k + (h/2) M_k = L_k/h + h M_k, so it carries the same tangent map (docs/equations.md
// §21).
//
// Forces beyond the potential (docs/equations.md §33): the closing kick (33.2) of step k − 1 and
// the opening kick (33.1) of step k both push at x_k with (h/2) F(z_k), so the forced discrete
// Euler–Lagrange equations add h² F_k to (78)–(79) beside the potential's (33.10):
//   D_{k+1} = D_k + (h²/m)(f_k + f^F_k),   S(L_k + h² (M_k + M^F_k)) = F_k Jd − Jd F_kᵀ,
// and the Legendre transform's momenta take the closing kick, γ_k = m D_k/h + (h/2)(f_k + f^F_k)
// (Π likewise) — implicit when F depends on the momenta, solved as the Hamiltonian form solves
// (33.2). The map is the forced Hamiltonian form's through that transform; each kick's share of
// the balance (33.4) is added as there, and the kicks' tangent maps (33.6)–(33.7) join the
// conservative map's as there.
#include "discrete_flow.hpp"
#include "forcing_kicks.hpp"
#include "tangent_map.hpp"

#include <noether/error.hpp>

#include <optional>

namespace lgvi {

namespace {

class InertialLagrangian final : public DiscreteFlow {
 public:
  InertialLagrangian(const System& system, noether::PotentialEvaluator& evaluate,
                     const Settings& settings)
      : system_(system), evaluate_(evaluate), settings_(settings) {
    forces_.resize(system_);
  }

  void start(const State& s) override {
    s_ = s;
    evaluate_(s_, forces_);
    ++work.potential_evaluations;
    h_ = 0;
    tangent_.start(s_, evaluate_, work);
    if (forcing_) {
      forcing_->evaluator().check_balance(s_, "lgvi");
      forcing_->at(s_);  // F(z_0), for the first step
      forcing_->forget_tangent();
    }
  }

  bool add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    forcing_.emplace(system_, std::move(forcing));
    return true;
  }

  bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    return tangent_.carry_parameters(std::move(parameters));
  }

  // h and the previous step's D = x_k − x_{k−1} and L (h = 0 before the first step); the State
  // holds x and R exactly, but γ and Π only through the discrete Legendre transform.
  std::vector<double> checkpoint() const override {
    std::vector<double> out{h_};
    const std::size_t n = system_.size(), nr = system_.rigid_count();
    out.resize(1 + 3 * n + 3 * nr, 0.0);
    if (h_ != 0) {
      std::copy(D_.data(), D_.data() + 3 * n, out.begin() + 1);
      for (std::size_t r = 0; r < nr; ++r) std::copy(L_[r].data(), L_[r].data() + 3, out.begin() + 1 + 3 * n + 3 * r);
    }
    return out;
  }
  std::size_t checkpoint_size() const override { return 1 + 3 * system_.size() + 3 * system_.rigid_count(); }
  void restore(const State& s, const std::vector<double>& data) override {
    const std::size_t n = system_.size(), nr = system_.rigid_count();
    if (data.size() != checkpoint_size()) throw noether::Error("lgvi: a Lagrangian checkpoint of the wrong size");
    start(s);
    h_ = data[0];
    if (h_ == 0) return;
    D_ = Eigen::Map<const Eigen::Matrix3Xd>(data.data() + 1, 3, static_cast<Eigen::Index>(n));
    L_.resize(nr);
    for (std::size_t r = 0; r < nr; ++r) L_[r] = Vec3(data[1 + 3 * n + 3 * r], data[2 + 3 * n + 3 * r], data[3 + 3 * n + 3 * r]);
  }

  void advance(double h, double t_next) override {
    if (!forcing_) return step(h, t_next);
    before_ = s_, before_forces_ = forces_, before_D_ = D_, before_L_ = L_;  // restored on failure
    const double before_h = h_;
    try {
      step(h, t_next);
    } catch (...) {
      forcing_->forget_tangent();
      s_ = before_, forces_ = before_forces_, D_ = before_D_, L_ = before_L_, h_ = before_h;
      try {
        forcing_->at(s_);
      } catch (...) {  // it was evaluated there before
      }
      throw;
    }
  }

  void current(State& s, Forces& f) const override {
    s = s_;
    f = forces_;
  }
  double time() const override { return s_.t; }

 private:
  // The potential's force plus the forces' (f_k + f^F_k; M likewise) on body column c.
  Vec3 total_force(Eigen::Index c) const {
    return forcing_ ? Vec3(forces_.f.col(c) + forcing_->total().f.col(c)) : Vec3(forces_.f.col(c));
  }
  Vec3 total_moment(Eigen::Index k) const {
    return forcing_ ? Vec3(forces_.M.col(k) + forcing_->total().M.col(k)) : Vec3(forces_.M.col(k));
  }

  void step(double h, double t_next) {
    const std::size_t n = system_.size(), nr = system_.rigid_count();
    if (h_ == 0) {  // the discrete Legendre transform of the initial momenta
      h_ = h;
      D_.resize(3, static_cast<Eigen::Index>(n));
      for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<Eigen::Index>(i);
        const double m = system_.body(i).mass;
        D_.col(c) = (h / m) * s_.p.col(c) - (0.5 * h * h / m) * total_force(c);
      }
      L_.resize(nr);
      for (std::size_t r = 0; r < nr; ++r)
        L_[r] = h * Vec3(s_.Pi.col(static_cast<Eigen::Index>(r))) - 0.5 * h * h * total_moment(static_cast<Eigen::Index>(r));
    }
    if (h != h_) throw noether::Error("lgvi: the Lagrangian form needs one fixed step");
    const bool tangent = s_.tangent.size() > 0;
    if (forcing_) {
      if (tangent) forcing_->open_tangent(s_, h, tangent_, s_.tangent);  // (33.6), (33.9)
      forcing_->open(s_, h);  // the opening kick's balance at x_k (33.1), (33.4)
    }
    // (79): F_k from S(L_k + h² M_k) = F_k Jd − Jd F_kᵀ
    std::vector<noether::DiscreteAttitude> F;
    if (tangent) F_.resize(nr), w_.resize(3, static_cast<Eigen::Index>(nr));
    for (std::size_t r = 0; r < nr; ++r) {
      const auto& b = system_.body(system_.body_of_rigid(r));
      const Vec3 g = L_[r] + h * h * total_moment(static_cast<Eigen::Index>(r));  // (79), (33.10)
      F.push_back(solve_attitude(g, b.inertia, b.inertia_inverse, settings_, b.name, s_.t, h, g / h, work));
      if (tangent) F_[r] = F.back().F, w_.col(static_cast<Eigen::Index>(r)) = g / h;  // w_k = L_k/h + h M_k
    }
    // (78): D_{k+1} = D_k + (h²/m)(f_k + f^F_k),  x_{k+1} = x_k + D_{k+1}            (33.10)
    for (std::size_t i = 0; i < n; ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      D_.col(c) += (h * h / system_.body(i).mass) * total_force(c);
    }
    s_.x += D_;
    for (std::size_t r = 0; r < nr; ++r) {
      s_.R[r] = s_.R[r] * F[r].F;  // (80)
      L_[r] = lagrangian_momentum(F[r].f, system_.body(system_.body_of_rigid(r)).inertia);
    }
    s_.t = t_next;
    evaluate_(s_, forces_);
    ++work.potential_evaluations;
    ++work.steps;
    if (tangent) {
      tangent_.at_next(s_, evaluate_, work);
      tangent_.advance(system_, h, F_, w_, D_, s_.tangent);  // D_ = x_{k+1} − x_k
    }
    // The discrete Legendre transform at k+1, then the closing kick of the forces there (33.2).
    for (std::size_t i = 0; i < n; ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      s_.p.col(c) = (system_.body(i).mass / h) * D_.col(c) + 0.5 * h * forces_.f.col(c);
    }
    for (std::size_t r = 0; r < nr; ++r)
      s_.Pi.col(static_cast<Eigen::Index>(r)) = L_[r] / h + 0.5 * h * Vec3(forces_.M.col(static_cast<Eigen::Index>(r)));
    if (forcing_) {
      forcing_->close(s_, h);
      if (tangent) forcing_->close_tangent(s_, h, tangent_, s_.tangent);  // (33.7), (33.9)
    }
  }

  const System system_;
  noether::PotentialEvaluator& evaluate_;
  Settings settings_;
  double h_ = 0;
  State s_;
  Forces forces_;
  Eigen::Matrix3Xd D_;    // x_k − x_{k−1}
  std::vector<Vec3> L_;   // vee(Jd F_{k−1} − F_{k−1}ᵀ Jd)
  // The tangent map's: the step's F_k and w_k, and the Jacobians at both ends.
  std::vector<Mat3> F_;
  Eigen::Matrix3Xd w_;
  TangentCarrier tangent_;
  std::optional<ForcingKicks> forcing_;  // forces beyond the potential (none: the conservative map)
  // With forces, the step's start (restored on failure; kept to reuse their buffers).
  State before_;
  Forces before_forces_;
  Eigen::Matrix3Xd before_D_;
  std::vector<Vec3> before_L_;
};

}  // namespace

std::unique_ptr<DiscreteFlow> make_inertial_lagrangian(const System& s, noether::PotentialEvaluator& p,
                                                       const Settings& settings) {
  return std::make_unique<InertialLagrangian>(s, p, settings);
}

}  // namespace lgvi
