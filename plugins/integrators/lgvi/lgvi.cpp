// lgvi: the Lie group variational integrator of the full body problem, inertial frame,
// Hamiltonian form (MATH.md §4; seed 000 eqs. (93)–(97), attitude solve (128)–(130)).
// Symmetric, second order, symplectic; conserves total linear and angular momentum to
// round-off and keeps every R on SO(3) to round-off. One potential evaluation per step.
// With point masses only it is velocity Verlet.
#include <noether/discrete_attitude.hpp>
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <cmath>
#include <sstream>

namespace {

using noether::Forces;
using noether::IntegrationError;
using noether::Mat3;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

class Lgvi final : public noether::Integrator {
 public:
  Lgvi(const System& system, std::shared_ptr<const noether::Potential> potential,
       const Params& params)
      : system_(system), potential_(std::move(potential)) {
    h_ = params.at("step").as_double();
    if (!(h_ > 0.0))
      throw SceneError(params.at("step").here() + "lgvi: 'step' must be positive");
    newton_.tolerance = params.get("newton_tolerance", 1e-15);
    newton_.max_iterations = static_cast<int>(params.get("newton_max_iterations", 30L));
    if (newton_.tolerance <= 0.0 || newton_.max_iterations < 1)
      throw SceneError(params.here() +
                       "lgvi: newton_tolerance and newton_max_iterations must be positive");
    for (auto* f : {&current_, &next_}) f->resize(system_);
    F_.resize(system_.rigid_count());
  }

  void integrate(State& s, const noether::OutputSchedule& schedule,
                 noether::Observer& observer) override {
    const double t0 = s.t;
    const std::int64_t n = noether::whole_steps(schedule.t_end - t0, h_, "run.t_end − t0", "lgvi");
    const std::int64_t stride = noether::whole_steps(schedule.output_every, h_, "run.output_every", "lgvi");
    evaluate(s, current_);
    observer.observe(s, current_);
    for (std::int64_t k = 0; k < n; ++k) {
      step(s, t0 + static_cast<double>(k + 1) * h_);
      if ((k + 1) % stride == 0 || k + 1 == n) observer.observe(s, current_);
    }
  }

 private:
  void evaluate(const State& s, Forces& forces) {
    potential_->evaluate(s, forces);
    ++work_.potential_evaluations;
  }

  // One step (x, γ, R, Π)_k → (x, γ, R, Π)_{k+1}. `current_` holds the forces at k on entry
  // and at k+1 on exit. If the attitude solve fails, `s` is left untouched at step k.
  void step(State& s, double t_next) {
    const Forces& fk = current_;
    // Solve h S(Π_k + (h/2) M_k) = F_k Jd − Jd F_kᵀ for every rigid body first (93).
    for (std::size_t r = 0; r < system_.rigid_count(); ++r) {
      const auto k = static_cast<Eigen::Index>(r);
      const Vec3 g = h_ * (Vec3(s.Pi.col(k)) + 0.5 * h_ * Vec3(fk.M.col(k)));
      const auto& body = system_.body(system_.body_of_rigid(r));
      try {
        const auto solved = noether::solve_discrete_attitude(g, body.inertia, newton_);
        F_[r] = solved.F;
        work_.newton_iterations += solved.iterations;
      } catch (const noether::Error& e) {
        const Vec3 omega = body.inertia_inverse * Vec3(s.Pi.col(k));
        std::ostringstream msg;
        msg << "lgvi: step too large for the spin of body '" << body.name << "' at t = " << s.t
            << " with step h = " << h_ << " (|Ω| h = " << omega.norm() * h_ << " rad): "
            << e.what() << ". Reduce integrator.step (|Ω| h well below 1 is safe)";
        throw IntegrationError(msg.str(), s.t);
      }
    }
    // Keep step k so that a failing potential evaluation (a collision) leaves it intact.
    x_prev_ = s.x;
    R_prev_ = s.R;
    const double t_prev = s.t;
    // x_{k+1} = x_k + (h/m) γ_k − (h²/2m) ∂U_k/∂x                                   (94)
    for (std::size_t i = 0; i < system_.size(); ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      const double m = system_.body(i).mass;
      s.x.col(c) += (h_ / m) * s.p.col(c) + (0.5 * h_ * h_ / m) * fk.f.col(c);
    }
    // R_{k+1} = R_k F_k                                                              (95)
    for (std::size_t r = 0; r < system_.rigid_count(); ++r) s.R[r] = s.R[r] * F_[r];
    s.t = t_next;
    try {
      evaluate(s, next_);  // the only potential evaluation of the step
    } catch (...) {
      s.x = x_prev_;
      s.R = R_prev_;
      s.t = t_prev;
      throw;
    }
    // γ_{k+1} = γ_k − (h/2) ∂U_k/∂x − (h/2) ∂U_{k+1}/∂x                             (96)
    s.p += (0.5 * h_) * (fk.f + next_.f);
    // Π_{k+1} = F_kᵀ Π_k + (h/2) F_kᵀ M_k + (h/2) M_{k+1}                            (97)
    for (std::size_t r = 0; r < system_.rigid_count(); ++r) {
      const auto k = static_cast<Eigen::Index>(r);
      s.Pi.col(k) = F_[r].transpose() * (Vec3(s.Pi.col(k)) + 0.5 * h_ * Vec3(fk.M.col(k))) +
                    0.5 * h_ * next_.M.col(k);
    }
    std::swap(current_, next_);
    ++work_.steps;
  }

  const System system_;
  std::shared_ptr<const noether::Potential> potential_;
  double h_ = 0.0;
  noether::DiscreteAttitudeOptions newton_;
  Forces current_, next_;
  std::vector<Mat3> F_;
  Eigen::Matrix3Xd x_prev_;
  std::vector<Mat3> R_prev_;
};

const noether::ParamDoc params[] = {
    {"step", "number", nullptr, "time step h (fixed); run.t_end and run.output_every must be "
                                "whole multiples of it"},
    {"newton_tolerance", "number", "1e-15",
     "relative tolerance ‖Δf‖/‖f‖ of the Newton solve for F_k (128)"},
    {"newton_max_iterations", "integer", "30",
     "Newton iterations before the step is declared too large for the spin"},
};

std::unique_ptr<noether::Integrator> make(const System& system,
                                          std::shared_ptr<const noether::Potential> potential,
                                          const Params& p) {
  return std::make_unique<Lgvi>(system, std::move(potential), p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Integrator,
    "lgvi",
    "Lie group variational integrator, inertial frame, Hamiltonian form (order 2, symplectic)",
    params,
    std::size(params),
    nullptr,
    &make};
