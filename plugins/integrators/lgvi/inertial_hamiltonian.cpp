// LGVI, inertial frame, Hamiltonian form: Lee, Leok & McClamroch 2007 eqs. (93)–(97) (docs/equations.md §4),
// and with forces beyond the potential by the discrete Lagrange–d'Alembert principle (Marsden &
// West 2001, §3.2; docs/equations.md §33): a kick of the forces at each end of the step around
// the conservative map, the closing one implicit in the momenta (33.1)–(33.2).
#include "discrete_flow.hpp"
#include "forcing_kicks.hpp"
#include "tangent_map.hpp"

#include <noether/error.hpp>


#include <limits>
#include <optional>
#include <sstream>

namespace lgvi {

noether::DiscreteAttitude solve_attitude(const Vec3& g, const Mat3& J, const Mat3& J_inverse, const Settings& settings,
                                         const std::string& body, double t, double h,
                                         const Vec3& angular_momentum, noether::WorkCounters& work) {
  try {
    const auto solved = noether::solve_discrete_attitude(g, J, J_inverse, settings.newton);
    work.newton_iterations += solved.iterations;
    return solved;
  } catch (const noether::Error& e) {
    std::ostringstream msg;
    const Vec3 omega = J_inverse * angular_momentum;
    msg << "lgvi: step too large for the spin of body '" << body << "' at t = " << t
        << " with step h = " << h << " (|Ω| h = " << omega.norm() * std::abs(h) << " rad): " << e.what()
        << ". Reduce integrator.step (|Ω| h well below 1 is safe)";
    throw noether::IntegrationError(msg.str(), t);
  }
}

Vec3 lagrangian_momentum(const Vec3& f, const Mat3& J) {
  const auto [a, b] = noether::rodrigues_coefficients(f.norm());
  const Vec3 Jf = J * f;
  return a * Jf - b * f.cross(Jf);
}

namespace {

class InertialHamiltonian final : public DiscreteFlow {
 public:
  InertialHamiltonian(const System& system, noether::PotentialEvaluator& evaluate,
                      const Settings& settings)
      : system_(system), evaluate_(evaluate), settings_(settings) {
    for (auto* f : {&current_, &next_}) f->resize(system_);
    F_.resize(system_.rigid_count());
  }

  void start(const State& s) override {
    s_ = s;
    evaluate(s_, current_);
    tangent_.start(s_, evaluate_, work);
    if (forcing_) {
      forcing_->evaluator().check_balance(s_, "lgvi");
      forcing_->at(s_);  // the forces of the first opening kick (33.1)
      forcing_->forget_tangent();
    }
  }

  bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    return tangent_.carry_parameters(std::move(parameters));
  }

  bool add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    forcing_.emplace(system_, std::move(forcing));
    return true;
  }

  // (x, γ, R, Π)_k → (x, γ, R, Π)_{k+1}; on failure the state stays at k.
  void advance(double h, double t_next) override {
    if (!forcing_) return conservative_step(h, t_next);
    before_ = s_;
    before_forces_ = current_;
    try {
      if (carries_tangent()) forcing_->open_tangent(s_, h, tangent_, s_.tangent);  // (33.6), (33.9)
      forcing_->open(s_, h);  // γ⁺ = γ_k + (h/2) f^F_k,  Π⁺ = Π_k + (h/2) M^F_k        (33.1)
      conservative_step(h, t_next);
      forcing_->close(s_, h);  // γ_{k+1} = γ⁻ + (h/2) f^F(z_{k+1}), Π likewise          (33.2)
      if (carries_tangent()) forcing_->close_tangent(s_, h, tangent_, s_.tangent);  // (33.7), (33.9)
    } catch (...) {
      forcing_->forget_tangent();
      s_ = before_;
      current_ = before_forces_;
      try {
        forcing_->at(s_);
      } catch (...) {  // it was evaluated there before
      }
      throw;
    }
  }

 private:
  void conservative_step(double h, double t_next) {
    const Forces& fk = current_;
    // h S(Π_k + (h/2) M_k) = F_k Jd − Jd F_kᵀ                                        (93)
    for (std::size_t r = 0; r < system_.rigid_count(); ++r) {
      const auto k = static_cast<Eigen::Index>(r);
      const auto& body = system_.body(system_.body_of_rigid(r));
      const Vec3 g = h * (Vec3(s_.Pi.col(k)) + 0.5 * h * Vec3(fk.M.col(k)));
      F_[r] = solve_attitude(g, body.inertia, body.inertia_inverse, settings_, body.name, s_.t, h,
                             Vec3(s_.Pi.col(k)), work).F;
    }
    if (carries_tangent()) w_ = s_.Pi + (0.5 * h) * fk.M;  // w_k, for the tangent map (21.8)
    x_prev_ = s_.x;
    R_prev_ = s_.R;
    const double t_prev = s_.t;
    // x_{k+1} = x_k + (h/m) γ_k − (h²/2m) ∂U_k/∂x                                   (94)
    for (std::size_t i = 0; i < system_.size(); ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      const double m = system_.body(i).mass;
      s_.x.col(c) += (h / m) * s_.p.col(c) + (0.5 * h * h / m) * fk.f.col(c);
    }
    // R_{k+1} = R_k F_k                                                              (95)
    for (std::size_t r = 0; r < system_.rigid_count(); ++r) s_.R[r] = s_.R[r] * F_[r];
    s_.t = t_next;
    try {
      evaluate(s_, next_);  // the only potential evaluation of the step
      tangent_.at_next(s_, evaluate_, work);
    } catch (...) {
      s_.x = x_prev_;
      s_.R = R_prev_;
      s_.t = t_prev;
      throw;
    }
    // γ_{k+1} = γ_k − (h/2) ∂U_k/∂x − (h/2) ∂U_{k+1}/∂x                             (96)
    s_.p += (0.5 * h) * (fk.f + next_.f);
    // Π_{k+1} = F_kᵀ Π_k + (h/2) F_kᵀ M_k + (h/2) M_{k+1}                            (97)
    for (std::size_t r = 0; r < system_.rigid_count(); ++r) {
      const auto k = static_cast<Eigen::Index>(r);
      s_.Pi.col(k) = F_[r].transpose() * (Vec3(s_.Pi.col(k)) + 0.5 * h * Vec3(fk.M.col(k))) +
                     0.5 * h * next_.M.col(k);
    }
    std::swap(current_, next_);
    if (carries_tangent()) tangent_.advance(system_, h, F_, w_, s_.x - x_prev_, s_.tangent);
    ++work.steps;
  }

 public:
  void current(State& s, Forces& f) const override {
    s = s_;
    f = current_;
  }
  void current_state(State& s, Forces&) const override { s = s_; }
  double time() const override { return s_.t; }

 private:
  bool carries_tangent() const { return s_.tangent.size() > 0; }
  void evaluate(const State& s, Forces& f) {
    evaluate_(s, f);
    ++work.potential_evaluations;
  }

  const System system_;
  noether::PotentialEvaluator& evaluate_;
  Settings settings_;
  State s_;
  Forces current_, next_;
  std::vector<Mat3> F_;
  Eigen::Matrix3Xd x_prev_;
  std::vector<Mat3> R_prev_;
  // The tangent map's: the step's w_k (F_k is F_), and the Jacobians at both ends.
  Eigen::Matrix3Xd w_;
  TangentCarrier tangent_;
  // Forces beyond the potential (none: the conservative map alone) and the state and forces at
  // the step's start (restored on failure).
  std::optional<ForcingKicks> forcing_;
  State before_;
  Forces before_forces_;
};

}  // namespace

std::unique_ptr<DiscreteFlow> make_inertial_hamiltonian(const System& s, noether::PotentialEvaluator& p,
                                                        const Settings& settings) {
  return std::make_unique<InertialHamiltonian>(s, p, settings);
}

}  // namespace lgvi
