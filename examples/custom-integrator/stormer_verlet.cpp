// An out-of-tree integrator plugin: Störmer–Verlet (kick–drift–kick leapfrog) for point masses,
// the shortest symplectic method, in one file (docs/writing-a-plugin.md, "An integrator").
//
//   p_{k+1/2} = p_k + (h/2) f(x_k)          kick   (f_i = −∂U/∂x_i, from the scene's potential)
//   x_{k+1}   = x_k + h M⁻¹ p_{k+1/2}        drift
//   p_{k+1}   = p_{k+1/2} + (h/2) f(x_{k+1}) kick
//
// Second order, time-reversible, symplectic: the energy error stays bounded and falls by 4
// when h halves (check_order.py measures both). One potential evaluation per step: the force
// at x_{k+1} is kept for the next step's first kick.
#include <noether/error.hpp>
#include <noether/integrator.hpp>
#include <noether/plugin.hpp>

#include <cmath>
#include <iterator>
#include <memory>

namespace {

using noether::Forces;
using noether::Params;
using noether::State;

class StormerVerlet final : public noether::Integrator {
 public:
  StormerVerlet(const noether::System& system, std::shared_ptr<const noether::Potential> potential, const Params& p)
      : system_(system), evaluate_(std::move(potential)), h_(p.at("step").as_double()) {
    if (!(h_ > 0)) throw noether::SceneError(p.at("step").here() + "stormer-verlet: 'step' must be positive");
    if (system.rigid_count() > 0)
      throw noether::SceneError(p.here() + "stormer-verlet integrates point masses only; body '" +
                                system.body(system.body_of_rigid(0)).name + "' is rigid (use lgvi)");
    forces_.resize(system);
  }

  void start(const State& state) override {
    state_ = state;
    evaluate_(state_, forces_);  // f(x_0), for the first kick
    ++work_.potential_evaluations;
  }

  void step(double t_max) override {
    // A fixed-step method: the host's loop asks only for whole steps (fixed_step() below), so
    // t_max is t + h; a last step shorter than h would lose the symmetry that makes it symplectic.
    const double h = std::min(h_, t_max - state_.t);
    State next = state_;
    for (Eigen::Index i = 0; i < next.x.cols(); ++i) {
      const double m = system_.body(static_cast<std::size_t>(i)).mass;
      next.p.col(i) += 0.5 * h * forces_.f.col(i);  // kick
      next.x.col(i) += h / m * next.p.col(i);       // drift
    }
    Forces at_next = forces_;
    evaluate_(next, at_next);
    ++work_.potential_evaluations;
    if (!std::isfinite(at_next.U))
      throw noether::IntegrationError("stormer-verlet: the potential is not finite after the step", state_.t);
    next.p += 0.5 * h * at_next.f;  // kick
    next.t = state_.t + h;
    state_ = std::move(next);  // only now: a step that throws leaves the state before it
    forces_ = std::move(at_next);
    ++work_.steps;
  }

  double time() const override { return state_.t; }
  void current(State& state, Forces& forces) override {
    state = state_;
    forces = forces_;
  }
  double fixed_step() const override { return h_; }
  int order() const override { return 2; }
  noether::PotentialEvaluator* potential_evaluator() override { return &evaluate_; }

 private:
  const noether::System& system_;
  noether::PotentialEvaluator evaluate_;
  double h_;
  State state_;
  Forces forces_;
};

std::unique_ptr<noether::Integrator> make(const noether::System& system,
                                          std::shared_ptr<const noether::Potential> potential, const Params& p) {
  return std::make_unique<StormerVerlet>(system, std::move(potential), p);
}

const noether::ParamDoc params[] = {
    {"step", "number", nullptr, "time step h (fixed)"},
};

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {NOETHER_PLUGIN_API_VERSION, noether::PluginKind::Integrator, "stormer-verlet",
                             "Störmer–Verlet (kick–drift–kick leapfrog) for point masses: order 2, symplectic",
                             params, std::size(params), nullptr, &make};
